"""The paper's connectivity law and its fit (Sec. VI, Eqs. 14-15).

Above the rigidity transition Phi_T the coordination number follows

    Z = Z_T + (Z_1 - Z_T) sqrt((Phi - Phi_T) / (Phi_1 - Phi_T)),

Z_T = 3, Z_1 = 4.72, Phi_1 = 0.9, with Phi_T the one free parameter.

The fit and its uncertainty
    Phi_T minimises the mean squared residual of the law over the points
    with Phi > Phi_T (the law holds above the transition only), scanned on
    a grid of step ``step`` between the smallest Phi and the value that
    leaves ``min_points`` points above it. Its uncertainty comes from the
    data: a moving-block bootstrap over the output rows of the run (blocks
    of ~n^(1/3) consecutive rows in Phi, because successive outputs are
    correlated), refitted ``resamples`` times; the error is the standard
    deviation of the refitted Phi_T. Over several runs (seeds) each run is
    fitted alone; Phi_T is their mean and the error the standard deviation
    over seeds (ddof = 1), the spread of one realisation.

When the data do not constrain Phi_T (no fit is reported: ``phi_t`` NaN and
``reason`` says why)
    - fewer than ``min_points`` usable points (finite, Phi < Phi_1) above
      every candidate, or the points above Phi_T span less than
      ``min_span`` in Phi;
    - Phi_T at an edge of the scanned range: at the lowest Phi (the
      transition may lie below the data) or where only ``min_points``
      points remain (the fit then follows the last few points);
    - more than ``max_edge_fraction`` of the bootstrap refits at an edge;
    - a bootstrap spread larger than ``max_spread`` x (Phi_1 - Phi_T).
"""

from __future__ import annotations

import abc

from dataclasses import dataclass, field

import numpy as np

#: The paper's connectivity law (Sec. VI, Eqs. 14-15, Fig. 8).
Z_T, Z_1, PHI_1 = 3.0, 4.72, 0.9
#: The paper's result (Fig. 8), for comparison only.
PAPER_PHI_T, PAPER_PHI_T_ERROR = 0.785, 0.005


def connectivity_law(phi, phi_t):
    """``Z_T + (Z_1 - Z_T) sqrt((Phi - Phi_T) / (Phi_1 - Phi_T))`` (Eq. 14).

    Z_T below Phi_T.
    """
    phi = np.asarray(phi, float)
    return Z_T + (Z_1 - Z_T) * np.sqrt(np.maximum(phi - phi_t, 0.0)
                                       / (PHI_1 - phi_t))


@dataclass(frozen=True)
class FitSettings:
    """What the fit scans and when it refuses (see the module doc)."""

    step: float = 1e-4
    min_points: int = 10
    min_span: float = 0.01
    resamples: int = 200
    max_spread: float = 0.1
    max_edge_fraction: float = 0.2
    seed: int = 0


class FitOutcome(abc.ABC):
    """What every fit's result shares: ``reason`` (empty when the fit is
    reported), :attr:`ok`, and a :meth:`summary` that says why not.

    A subclass (a frozen dataclass) sets ``SUBJECT``, what is fitted, and
    ``_reported``, the one line of the values it reports.
    """

    SUBJECT = "fit"
    reason: str

    @property
    def ok(self) -> bool:
        """Whether the fit is reported."""
        return not self.reason

    def summary(self) -> str:
        """One line with the values and errors, or why there is no fit."""
        if not self.ok:
            return f"no {self.SUBJECT}: {self.reason}"
        return self._reported()

    @abc.abstractmethod
    def _reported(self) -> str:
        """The one line of the values a subclass reports."""


@dataclass(frozen=True)
class TransitionFit(FitOutcome):
    """Phi_T of Eq. 14 with its uncertainty, or why there is none.

    Attributes
    ----------
    phi_t, error : float
        NaN when the data do not constrain Phi_T.
    reason : str
        Empty when the fit is reported; otherwise why not.
    method : str
        How ``error`` was obtained.
    points, points_above : int
        Usable points, and those above Phi_T (above the best candidate
        when refused; 0 when no candidate exists).
    runs : tuple of TransitionFit
        The per-run fits of a several-run fit (empty for one run).
    """

    phi_t: float
    error: float
    reason: str
    method: str
    points: int
    points_above: int
    runs: tuple = field(default=())

    SUBJECT = "Phi_T"

    def _reported(self) -> str:
        """``Phi_T = 0.7912 +- 0.0031 (how)``."""
        return (f"Phi_T = {self.phi_t:.4f} +- {self.error:.4f}"
                f" ({self.method})")


def _refused(reason, points, above=0, runs=()) -> TransitionFit:
    """A fit that reports no Phi_T, and why."""
    return TransitionFit(float("nan"), float("nan"), reason, "", points,
                         above, tuple(runs))


def _usable(phi, z):
    """Finite points below Phi_1, sorted by Phi (blocks follow Phi)."""
    phi, z = np.asarray(phi, float), np.asarray(z, float)
    ok = np.isfinite(phi) & np.isfinite(z) & (phi < PHI_1)
    order = np.argsort(phi[ok], kind="stable")
    return phi[ok][order], z[ok][order]


def _scan(phi, z, weights, candidates, min_points):
    """Best candidate index of each weight row (-1 where none qualifies).

    ``weights`` (B, n): how many times each point is drawn; the cost of
    candidate t is the weighted mean squared residual over phi > t.
    """
    above = phi[None, :] > candidates[:, None]                  # (T, n)
    residual = np.where(above, z[None, :] - connectivity_law(
        phi[None, :], candidates[:, None]), 0.0)**2
    count = weights @ above.T                                   # (B, T)
    cost = np.divide(weights @ residual.T, count,
                     out=np.full(count.shape, np.inf),
                     where=count >= min_points)
    best = np.argmin(cost, axis=1)
    return np.where(np.isfinite(cost[np.arange(len(best)), best]), best, -1)


def _block_weights(n, resamples, rng) -> np.ndarray:
    """Moving-block bootstrap draw counts, shape (resamples, n)."""
    block = max(1, int(round(n ** (1.0 / 3.0))))
    starts = rng.integers(0, n - block + 1,
                          size=(resamples, -(-n // block)))
    rows = (starts[:, :, None] + np.arange(block)).reshape(resamples, -1)
    weights = np.zeros((resamples, n))
    np.add.at(weights, (np.arange(resamples)[:, None], rows[:, :n]), 1.0)
    return weights


def fit_rigidity_transition(phi, z, settings: FitSettings = FitSettings()
                            ) -> TransitionFit:
    """Fit Phi_T of Eq. 14 to one run's points.

    Parameters
    ----------
    phi, z : array_like
        Output rows of one run (NaNs and Phi >= Phi_1 dropped).
    settings : FitSettings

    Returns
    -------
    TransitionFit
    """
    s = settings
    phi, z = _usable(phi, z)
    n = len(phi)
    if n < s.min_points + 1:
        return _refused(f"{n} usable points, fewer than"
                        f" {s.min_points + 1}", n)
    top = phi[-s.min_points]
    candidates = np.arange(phi[0] - s.step, top, s.step)
    if len(candidates) < 3:
        return _refused(f"the data span {phi[-1] - phi[0]:.4f} in Phi, too"
                        " narrow to scan", n)
    k = int(_scan(phi, z, np.ones((1, n)), candidates, s.min_points)[0])
    best, above = float(candidates[k]), int((phi > candidates[k]).sum())
    if k == 0:
        return _refused(f"Phi_T at the lowest Phi of the data ({best:.4f}):"
                        " the transition may lie below them", n, above)
    if k == len(candidates) - 1:
        return _refused(f"Phi_T at the last {s.min_points} points"
                        f" ({best:.4f}): the data above it do not"
                        " constrain it", n, above)
    if phi[-1] - best < s.min_span:
        return _refused(f"the points above Phi_T = {best:.4f} span"
                        f" {phi[-1] - best:.4f} < {s.min_span} in Phi", n,
                        above)
    rng = np.random.default_rng(s.seed)
    picks = _scan(phi, z, _block_weights(n, s.resamples, rng), candidates,
                  s.min_points)
    edge = (picks <= 0) | (picks == len(candidates) - 1)
    if edge.mean() > s.max_edge_fraction:
        return _refused(f"{edge.mean():.0%} of the bootstrap refits at an"
                        " edge of the data", n, above)
    spread = float(np.std(candidates[picks[~edge]], ddof=1))
    if spread > s.max_spread * (PHI_1 - best):
        return _refused(f"bootstrap spread {spread:.4f} >"
                        f" {s.max_spread:g} x (Phi_1 - Phi_T)", n, above)
    return TransitionFit(best, spread, "", f"block bootstrap over {n} output"
                         f" rows, {s.resamples} refits", n, above)


def fit_runs(curves, settings: FitSettings = FitSettings()
             ) -> TransitionFit:
    """Fit Phi_T to several runs (seeds) of one set-up.

    Parameters
    ----------
    curves : list of (phi, z) array pairs
        One pair per run.
    settings : FitSettings

    Returns
    -------
    TransitionFit
        For one run, its fit. For several, the mean of the runs that
        constrain Phi_T and the standard deviation over them (ddof = 1); a
        single constraining run gives its own fit, with a note. ``runs``
        holds every run's fit.
    """
    fits = tuple(fit_rigidity_transition(p, z, settings) for p, z in curves)
    if len(fits) == 1:
        return fits[0]
    good = [f for f in fits if f.ok]
    points = sum(f.points for f in fits)
    refused = len(fits) - len(good)
    note = f"; {refused} of {len(fits)} runs refused" if refused else ""
    if not good:
        reasons = "; ".join(f"run {i + 1}: {f.reason}"
                            for i, f in enumerate(fits))
        return _refused(f"no run constrains Phi_T ({reasons})", points,
                        runs=fits)
    if len(good) == 1:
        f = good[0]
        return TransitionFit(f.phi_t, f.error, "", f.method + note, points,
                             f.points_above, fits)
    values = np.array([f.phi_t for f in good])
    return TransitionFit(float(values.mean()), float(values.std(ddof=1)), "",
                         f"std over {len(good)} seeds{note}", points,
                         sum(f.points_above for f in good), fits)


#: Width in Phi of the bins of :func:`rigidity_onset`.
ONSET_BIN = 0.005


def rigidity_onset(phi, z, bin_width=ONSET_BIN) -> float:
    """Where Z first leaves Z_T: the smallest Phi whose bin (``bin_width``
    wide, centred on a grid of half that step from the smallest Phi of the
    data) holds points with a mean Z above Z_T; NaN when none does.

    A reading of the transition that assumes no law above it (Eq. 14
    fixes the slope through Z_1 at Phi_1, so its Phi_T also answers for the
    whole curve up to Phi_1).
    """
    phi, z = _usable(phi, z)
    if not len(phi):
        return float("nan")
    for centre in np.arange(phi[0], phi[-1], bin_width / 2):
        inside = np.abs(phi - centre) <= bin_width / 2
        if inside.any() and z[inside].mean() > Z_T:
            return float(centre)
    return float("nan")
