"""The compaction law P(Phi) of an isotropic compaction, fitted with its
uncertainty, and the shear-test series.

The law
    Soft (hyperelastic) particles compacted beyond jamming approach a
    largest packing fraction Phi_max, where the bulk modulus diverges
    (Cantor, Cardenas-Barrantes, Preechawuttipong, Renouf, Azema, "Compaction
    model for highly deformable particle assemblies", Phys. Rev. Lett. 124,
    208003 (2020); Cardenas-Barrantes, Cantor, Bares, Renouf, Azema,
    "Micromechanical description of the compaction of soft pentagon
    assemblies", Phys. Rev. E 103, 062902 (2021), arXiv:2012.10399; 3D:
    Soft Matter 18, 312 (2022)). Fitted here is the logarithmic compaction
    equation with a maximum packing fraction,

        P(Phi) = -kappa ln[(Phi_max - Phi) / (Phi_max - Phi_0)],
        i.e. Phi(P) = Phi_max - (Phi_max - Phi_0) exp(-P / kappa),

    three parameters: Phi_0 (Phi where P vanishes: the jamming point of the
    law), Phi_max and the pressure scale kappa (Pa, per unit length in 2D
    like every stress here). With Phi_max = 1 it is Heckel's powder
    compaction equation (Trans. Metall. Soc. AIME 221, 671 (1961), which
    those papers compare with); the soft-particle papers derive P from the
    granular stress with the connectivity Z - Z_0 ~ sqrt(Phi - Phi_0) and
    a particle-stress closure, which multiplies this logarithm by slowly
    varying factors of Phi and Z(Phi). CAUTION: the equations' text was not
    retrievable from the sources stored for this work (only the abstracts
    were); the form above is the logarithmic-divergence structure those
    abstracts describe (Phi tends to Phi_max asymptotically as P grows),
    not a verified transcription of their Eq. with its prefactor. Check it
    against the papers before comparing numbers with theirs.

The fit
    Least squares of Phi(P) (Phi is the measured variable, bounded; P the
    applied one) over the output rows with P > ``min_pressure_fraction`` x
    max P, by ``scipy.optimize.curve_fit``. The uncertainty never comes from
    the optimiser's covariance alone: it is the standard deviation of the
    parameters refitted on ``resamples`` bootstrap resamples: moving-block
    resamples of the rows (blocks of ~n^(1/3) consecutive rows, the
    resampling of :mod:`softpack.analysis.fits`), or, when the rows come in
    groups (the equilibria of a loading program's stages, each several
    nearly equal rows), resamples of whole groups, so that one equilibrium
    counts once; over several runs (seeds), the standard deviation across
    seeds.

When the data do not constrain the law (``reason`` says why, values NaN)
    - fewer than ``min_points`` usable rows, or fewer than ``min_groups``
      groups;
    - a systematic misfit: the signs of the residuals, in the order of P
      (of the group means with groups), form fewer runs than random ones
      would (Wald-Wolfowitz runs test, z < ``min_runs_z``): the data
      follow another curve than the law, whatever the error bars;
    - the data do not reach saturation: P_max / kappa < ``min_saturation``
      (exp(-P/kappa) stays near 1, so only the initial slope
      (Phi_max - Phi_0)/kappa is measured, not Phi_max and kappa apart);
    - the optimiser fails, or more than ``max_failed_fraction`` of the
      bootstrap refits fail;
    - the best fit at a bound of the optimiser, Phi_max below the data's
      largest Phi, or Phi_0 further below the data than they span (an
      extrapolation, not a measurement);
    - a bootstrap spread of Phi_0 or Phi_max larger than ``max_spread`` x
      (Phi_max - Phi_0), or of kappa larger than ``max_spread`` x kappa.

Shear tests: :func:`shear_series` gives q/P and the volumetric and
deviatoric strains from ``stress.csv`` (dilatancy: eps_v against eps_q).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import curve_fit

from softpack.analysis.fits import FitOutcome, _block_weights

#: Upper bound of Phi_max in the optimiser (a fit there is refused).
_PHI_MAX_BOUND = 1.5

#: Names of the fitted parameters, in the order of :func:`packing_fraction`.
PARAMETERS = ("phi_0", "phi_max", "kappa")


def packing_fraction(pressure, phi_0, phi_max, kappa):
    """Phi(P) = Phi_max - (Phi_max - Phi_0) exp(-P / kappa)."""
    return phi_max - (phi_max - phi_0) * np.exp(-np.asarray(pressure, float)
                                                / kappa)


def pressure(phi, phi_0, phi_max, kappa):
    """P(Phi) = -kappa ln[(Phi_max - Phi) / (Phi_max - Phi_0)] (NaN >= max)."""
    phi = np.asarray(phi, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(phi < phi_max, -kappa * np.log(
            (phi_max - phi) / (phi_max - phi_0)), np.nan)


@dataclass(frozen=True)
class CompactionSettings:
    """What the fit uses and when it refuses (see the module doc)."""

    min_points: int = 8
    min_groups: int = 5
    min_pressure_fraction: float = 1e-3
    min_saturation: float = 0.5
    min_runs_z: float = -3.0
    resamples: int = 200
    max_spread: float = 0.25
    max_failed_fraction: float = 0.2
    seed: int = 0


@dataclass(frozen=True)
class CompactionFit(FitOutcome):
    """The law's parameters with their uncertainties, or why there are none.

    Attributes
    ----------
    values, errors : dict
        ``phi_0``, ``phi_max``, ``kappa``; NaN when refused.
    reason : str
        Empty when the fit is reported.
    method : str
        How ``errors`` were obtained.
    points : int
        Rows used.
    pressure_max : float
        Largest P of the rows (Pa).
    runs : tuple of CompactionFit
        Per-run fits of a several-run fit.
    """

    values: dict
    errors: dict
    reason: str
    method: str
    points: int
    pressure_max: float
    runs: tuple = field(default=())

    SUBJECT = "compaction law"

    def _reported(self) -> str:
        """The three parameters with their errors, and how."""
        v, e = self.values, self.errors
        return (f"Phi_max = {v['phi_max']:.4f} +- {e['phi_max']:.4f}, "
                f"Phi_0 = {v['phi_0']:.4f} +- {e['phi_0']:.4f}, "
                f"kappa = {v['kappa']:.4g} +- {e['kappa']:.2g} Pa"
                f" ({self.method})")


def _refused(reason, points, pressure_max, runs=()) -> CompactionFit:
    nan = {k: float("nan") for k in PARAMETERS}
    return CompactionFit(nan, dict(nan), reason, "", points, pressure_max,
                         tuple(runs))


def _usable(phi, p, s: CompactionSettings, labels):
    """Finite rows with P above the threshold, sorted by P."""
    phi, p = np.asarray(phi, float), np.asarray(p, float)
    labels = np.asarray(labels)
    ok = np.isfinite(phi) & np.isfinite(p) & (p > 0)
    if ok.any():
        ok &= p > s.min_pressure_fraction * p[ok].max()
    order = np.argsort(p[ok], kind="stable")
    return phi[ok][order], p[ok][order], labels[ok][order]


def _least_squares(phi, p, weights=None, start=None):
    """(phi_0, phi_max, kappa) minimising the weighted squared residual."""
    keep = np.ones(len(p), bool) if weights is None else weights > 0
    sigma = None if weights is None else 1.0 / np.sqrt(weights[keep])
    if start is None:
        slope = max((phi[-1] - phi[0]) / max(p[-1] - p[0], 1e-300), 1e-300)
        start = (phi[0], phi[0] + slope * p[-1], p[-1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        values, _ = curve_fit(packing_fraction, p[keep], phi[keep], p0=start,
                              sigma=sigma, maxfev=20000,
                              bounds=([0.0, 0.0, 1e-12 * p[-1]],
                                      [1.0, _PHI_MAX_BOUND, 1e6 * p[-1]]))
    return values


def _group_weights(groups, resamples, rng) -> np.ndarray:
    """Draw counts of each row when whole groups are resampled."""
    labels, index = np.unique(groups, return_inverse=True)
    picks = rng.integers(0, len(labels), size=(resamples, len(labels)))
    counts = np.zeros((resamples, len(labels)))
    np.add.at(counts, (np.arange(resamples)[:, None], picks), 1.0)
    return counts[:, index]


def _runs_z(residual, labels) -> float:
    """Wald-Wolfowitz z of the residuals' signs (in P order; group means
    when rows come in groups); 0 when there are too few to test."""
    _, first, index = np.unique(labels, return_index=True,
                                return_inverse=True)
    if len(first) > 1:  # one residual per group, in the groups' P order
        means = np.bincount(index, weights=residual) / np.bincount(index)
        residual = means[np.argsort(first)]
    signs = residual[residual != 0] > 0
    n, up = len(signs), int(signs.sum())
    down = n - up
    if n < 10 or up == 0 or down == 0:
        return 0.0
    runs = 1 + int(np.count_nonzero(signs[1:] != signs[:-1]))
    mean = 2.0 * up * down / n + 1
    variance = (mean - 1) * (mean - 2) / (n - 1)
    return float((runs - mean) / np.sqrt(variance))


def _at_an_edge(best, phi, p) -> str:
    """Why the best fit is not a measurement (at a bound, or extrapolated
    further than the data span), or ""."""
    phi_0, phi_max, kappa = best
    span = phi.max() - phi.min()
    if phi_0 <= 1e-6 or phi_max >= _PHI_MAX_BOUND - 1e-6 or not (
            1e-12 * p[-1] * 1.001 < kappa < 1e6 * p[-1] * 0.999):
        return (f"the fit sits at a bound of the optimiser (Phi_0 ="
                f" {phi_0:.3g}, Phi_max = {phi_max:.3g}, kappa ="
                f" {kappa:.3g} Pa)")
    if phi_max <= phi.max():
        return (f"Phi_max = {phi_max:.4f} lies below the largest Phi of the"
                f" data ({phi.max():.4f})")
    if phi_0 < phi.min() - span:
        return (f"Phi_0 = {phi_0:.4f} lies further below the data"
                f" ({phi.min():.4f}) than they span ({span:.4f})")
    return ""


def fit_compaction(phi, p, settings: CompactionSettings = CompactionSettings(),
                   groups=None, checked: bool = True) -> CompactionFit:
    """Fit the compaction law to one run's rows (Phi, P).

    Parameters
    ----------
    phi, p : array_like
        Packing fraction and pressure (Pa, compression positive) of the
        output rows (e.g. ``raw/steps.csv`` phi and ``stress.csv`` wall_P).
    settings : CompactionSettings
    groups : array_like, optional
        A label per row (e.g. the loading stage): the bootstrap resamples
        whole groups. Default: moving blocks of rows.
    checked : bool
        False: none of the refusals of the module doc except a least
        squares that does not converge (and fewer than two bootstrap
        refits); the law as it fits data it may not describe, for
        illustration only (``method`` says so).
    """
    s = settings
    labels = np.zeros(len(np.asarray(p))) if groups is None else groups
    phi, p, labels = _usable(phi, p, s, labels)
    n = len(p)
    p_max = float(p.max()) if n else float("nan")
    if checked and n < s.min_points:
        return _refused(f"{n} usable rows (P > 0), fewer than"
                        f" {s.min_points}", n, p_max)
    distinct = len(np.unique(labels))
    if checked and groups is not None and distinct < s.min_groups:
        return _refused(f"{distinct} groups (equilibria), fewer than"
                        f" {s.min_groups}", n, p_max)
    try:
        best = _least_squares(phi, p)
    except (RuntimeError, ValueError) as error:
        return _refused(f"the least squares did not converge ({error})", n,
                        p_max)
    phi_0, phi_max, kappa = best
    edge = _at_an_edge(best, phi, p)
    if checked and edge:
        return _refused(edge, n, p_max)
    z = _runs_z(phi - packing_fraction(p, *best), labels)
    if checked and z < s.min_runs_z:
        return _refused(f"systematic misfit: the residuals' signs form too"
                        f" few runs (runs test z = {z:.1f} <"
                        f" {s.min_runs_z:g}); the data follow another"
                        " curve", n, p_max)
    if checked and p_max / kappa < s.min_saturation:
        return _refused(f"the data reach P/kappa = {p_max / kappa:.2g} <"
                        f" {s.min_saturation:g}: they do not approach"
                        " Phi_max, only the initial slope is measured", n,
                        p_max)
    rng = np.random.default_rng(s.seed)
    refits = []
    weights = (_block_weights(n, s.resamples, rng) if groups is None
               else _group_weights(labels, s.resamples, rng))
    for w in weights:
        try:
            refits.append(_least_squares(phi, p, w, start=best))
        except (RuntimeError, ValueError):
            continue
    failed = 1 - len(refits) / s.resamples
    if (failed > s.max_failed_fraction if checked else len(refits) < 2):
        return _refused(f"{failed:.0%} of the bootstrap refits failed", n,
                        p_max)
    spread = np.std(np.array(refits), axis=0, ddof=1)
    limits = s.max_spread * np.array([phi_max - phi_0, phi_max - phi_0,
                                      kappa])
    for name, error, limit in zip(("Phi_0", "Phi_max", "kappa"), spread,
                                  limits):
        if checked and error > limit:
            return _refused(f"bootstrap spread of {name} {error:.3g} >"
                            f" {s.max_spread:g} x "
                            + ("kappa" if name == "kappa"
                               else "(Phi_max - Phi_0)"), n, p_max)
    return CompactionFit(dict(zip(PARAMETERS, map(float, best))),
                         dict(zip(PARAMETERS, map(float, spread))), "",
                         (f"block bootstrap over {n} output rows"
                          if groups is None else f"bootstrap over {distinct}"
                          f" groups ({n} rows)") + f", {len(refits)} refits"
                         + ("" if checked else "; checks switched off (runs"
                            f" test z = {z:.1f}; {edge or 'within the data'}):"
                            " for illustration only"),
                         n, p_max)


def fit_runs(curves, settings: CompactionSettings = CompactionSettings()
             ) -> CompactionFit:
    """Fit several runs (seeds): mean and standard deviation across seeds.

    Parameters
    ----------
    curves : list of (phi, p) array pairs, one per run.
    """
    fits = tuple(fit_compaction(phi, p, settings) for phi, p in curves)
    if len(fits) == 1:
        return fits[0]
    good = [f for f in fits if f.ok]
    points = sum(f.points for f in fits)
    p_max = max((f.pressure_max for f in fits), default=float("nan"))
    if len(good) < 2:
        reasons = "; ".join(f"run {i + 1}: {f.reason or 'fitted'}"
                            for i, f in enumerate(fits))
        return _refused(f"fewer than two runs constrain the law"
                        f" ({reasons})", points, p_max, fits)
    values = {k: float(np.mean([f.values[k] for f in good]))
              for k in PARAMETERS}
    errors = {k: float(np.std([f.values[k] for f in good], ddof=1))
              for k in PARAMETERS}
    refused = len(fits) - len(good)
    note = f"; {refused} of {len(fits)} runs refused" if refused else ""
    return CompactionFit(values, errors, "", f"std over {len(good)} seeds"
                         f"{note}", points, p_max, fits)


def shear_series(stress: dict, estimate: str = "wall") -> dict:
    """q/P and the strains of a shear test from ``stress.csv`` columns.

    Parameters
    ----------
    stress : dict
        The columns of ``stress.csv`` (:mod:`softpack.analysis.stress`).
    estimate : {"wall", "contact", "fe"}
        Which stress estimate gives P and q.

    Returns
    -------
    dict with ``eps_q``, ``eps_v`` (compression positive, so dilatancy is
    a decreasing eps_v), ``P``, ``q`` and ``q_over_p`` (NaN where P <= 0).
    """
    p = np.asarray(stress[f"{estimate}_P"], float)
    q = np.asarray(stress[f"{estimate}_q"], float)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(p > 0, q / p, np.nan)
    return {"eps_q": np.asarray(stress["eps_q"], float),
            "eps_v": np.asarray(stress["eps_v"], float), "P": p, "q": q,
            "q_over_p": ratio}
