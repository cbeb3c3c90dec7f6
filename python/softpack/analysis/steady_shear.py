"""The steady state of a simple shear in a periodic cell (issue 38).

A shear run's ``stress.csv`` (:mod:`softpack.analysis.cell`) and
``series.csv`` give, per output row, gamma (the imposed shear from the
shear stage's start), mu* = |sym sigma_xy| / sigma_yy and P of the contacts'
Love-Weber stress, Phi, the inertial number I, Z and the fabric. The
steady state is read over the last ``window`` of the shear (by default the
last half of gamma in the run's last stage):

- each quantity's mean and its fluctuation (the standard deviation of the
  rows: what one snapshot of the flow scatters by);
- the standard error of the mean by batch means: the window cut into
  ``BATCHES`` consecutive blocks of rows, the error the standard deviation
  of the blocks' means over sqrt(BATCHES) (rows closer than a block are
  correlated; Flyvbjerg and Petersen, J. Chem. Phys. 91, 461 (1989));
- stationarity: the change of a straight line fitted over the window, from
  its start to its end, against the fluctuation. A quantity is called
  stationary when that drift is below the fluctuation and the two halves'
  means differ by less than 3 of their combined standard errors
  (``stationary``); a run whose mu* or Phi is not is reported as such.

A quantity with fewer finite rows in the window than the statistics need
has NaN statistics and the reason: Z under the default exclusion rule, which
was written for packings at rest, leaves every particle of a flowing
packing out (``series.csv`` ``z_undefined``); the analysis run again with a
large ``[observables] unbalanced_threshold`` counts them
(docs/bulk_shear.md).

Two runs sheared at rates whose I differ are compared by their mu* means:
:func:`compare` gives the difference against the fluctuation and against
the combined standard error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table

#: The quantities read in the steady state: column -> the table holding it
QUANTITIES = {"mu_star": "stress", "phi": "stress", "contact_yy": "stress",
              "contact_P": "stress", "inertial_number": "stress",
              "z": "series", "fabric_anisotropy": "series",
              "fabric_angle": "series"}
#: Blocks of the batch-means error
BATCHES = 6


@dataclass
class Statistic:
    """One quantity over the window."""
    mean: float
    fluctuation: float
    error: float
    drift: float
    halves: tuple
    stationary: bool
    #: Why there is no statistic (too few finite rows), else empty
    reason: str = ""

    @classmethod
    def missing(cls, reason: str) -> "Statistic":
        """No statistic: every value NaN, not stationary, and why."""
        nan = float("nan")
        return cls(nan, nan, nan, nan, (nan, nan), False, reason)


@dataclass
class SteadyState:
    """A run's steady state: the window and each quantity's statistic."""
    run: str
    gamma_window: tuple
    rows: int
    shear_rate: float
    stats: dict = field(default_factory=dict)
    balance: float = float("nan")


def batch_error(values: np.ndarray, batches: int = BATCHES) -> float:
    """Standard error of the mean of correlated rows by batch means."""
    blocks = np.array_split(values, batches)
    means = np.array([b.mean() for b in blocks if len(b)])
    return float(means.std(ddof=1) / np.sqrt(len(means)))


def statistic(gamma: np.ndarray, values: np.ndarray) -> Statistic:
    """:class:`Statistic` of ``values`` over the window ``gamma``."""
    ok = np.isfinite(values)
    g, v = gamma[ok], values[ok]
    if len(v) < 2 * BATCHES:
        raise RunError(f"{len(v)} finite rows in the steady window: too few"
                       f" for its statistics (at least {2 * BATCHES})")
    slope = np.polyfit(g, v, 1)[0]
    drift = float(slope * (g[-1] - g[0]))
    half = len(v) // 2
    first, second = v[:half], v[half:]
    halves = (float(first.mean()), float(second.mean()))
    separation = abs(halves[1] - halves[0])
    combined = np.hypot(batch_error(first, BATCHES // 2),
                        batch_error(second, BATCHES // 2))
    fluctuation = float(v.std(ddof=1))
    return Statistic(float(v.mean()), fluctuation, batch_error(v), drift,
                     halves, bool(abs(drift) < fluctuation
                                  and separation < 3 * combined))


def last_stage(steps: dict) -> np.ndarray:
    """Whether each output row belongs to the run's last stage (every row
    of a run without stages)."""
    stage = np.asarray(steps["stage"], int) if "stage" in steps \
        else np.zeros(len(steps["step"]), int)
    return stage == stage[-1]


def shear_rows(stress: dict, steps: dict, window: float) -> np.ndarray:
    """Indices of the rows of the last stage whose gamma lies in the last
    ``window`` of its shear."""
    gamma = np.asarray(stress["gamma"], float)
    last = last_stage(steps)
    start = gamma[last][0]
    end = gamma[last][-1]
    if not end > start:
        raise RunError("the run's last stage is not sheared (gamma "
                       f"{start:g} to {end:g})")
    low = end - window * (end - start)
    return np.flatnonzero(last & (gamma >= low))


def steady_state(run_dir, window: float = 0.5) -> SteadyState:
    """The steady state of a finished shear run (module doc)."""
    if not 0 < window <= 1:
        raise ValueError(f"window must be in (0, 1], not {window}")
    run = RunDirectory(run_dir)
    for path in (run.stress_csv, run.series_csv, run.raw.steps_csv):
        if not path.is_file():
            raise RunError(f"{path}: no such file (is {run.path} a finished"
                           " run with its analysis?)")
    tables = {"stress": read_table(run.stress_csv),
              "series": read_table(run.series_csv)}
    steps = read_table(run.raw.steps_csv)
    rows = shear_rows(tables["stress"], steps, window)
    gamma = np.asarray(tables["stress"]["gamma"], float)[rows]
    time = np.asarray(tables["stress"]["time"], float)[rows]
    out = SteadyState(str(run.path), (float(gamma[0]), float(gamma[-1])),
                      len(rows), float(np.polyfit(time, gamma, 1)[0]))
    for name, table in QUANTITIES.items():
        values = np.asarray(tables[table][name], float)[rows]
        try:
            out.stats[name] = statistic(gamma, values)
        except RunError as err:  # e.g. Z with every particle unbalanced
            out.stats[name] = Statistic.missing(str(err))
    residual = np.abs(np.asarray(steps["energy_residual"], float))
    work = np.abs(np.asarray(steps["cell_work"], float))
    out.balance = float(residual.max() / work[-1]) if work[-1] > 0 \
        else float("nan")
    return out


def compare(a: SteadyState, b: SteadyState, name: str = "mu_star") -> dict:
    """The difference of two runs' means of ``name`` against their
    fluctuation (the larger) and their combined standard error."""
    sa, sb = a.stats[name], b.stats[name]
    difference = sb.mean - sa.mean
    return {"difference": difference,
            "fluctuation": max(sa.fluctuation, sb.fluctuation),
            "error": float(np.hypot(sa.error, sb.error)),
            "within_fluctuation": abs(difference) < max(sa.fluctuation,
                                                         sb.fluctuation)}
