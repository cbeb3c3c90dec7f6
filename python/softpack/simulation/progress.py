"""Progress and ETA of a running driver, from the rows of ``raw/steps.csv``.

The fraction done is the largest of ``(Phi - Phi0) / (target - Phi0)``,
``time / max_time`` and ``steps / stop.steps`` (the stopping criteria).
A run with stages is followed stage by stage (:func:`stage_status`): the
current stage, how far it is from its criterion (the fraction is the
largest over its criteria: time / max_time, Phi, strain, pressure; an
equilibrium criterion has no fraction before it is met), and the ETA of
that stage.

The ETA is not ``elapsed * (1 - f) / f``: the cost per unit of progress
grows during a compaction (more contacts, stiffer assembly as Phi rises),
so a constant pace is optimistic (issue 16: at 25 % it implied 5m56s for a
run of 8m00s). :func:`remaining_seconds` measures the cost per unit of
progress (the driver's own ``seconds`` column against the fraction) on each
half of the history and extrapolates its trend to the end.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from softpack.scene.config import initial_packing_fraction

#: Intervals between rows needed to measure a cost trend.
MIN_FIT_ROWS = 4


class Progress:
    """Progress lines of a running driver.

    Parameters
    ----------
    config : Config
        The run's configuration (its stopping criteria).
    steps_csv : Path
        ``raw/steps.csv``, read again at each :meth:`update`.
    echo : callable
        Prints a line on the terminal (``end`` keyword as print's).
    before : Path, optional
        A resumed run's killed part (``raw.part/steps.csv``): its rows lead
        the driver's, so that the fractions, the stage's start and the cost
        history are the whole run's.
    """

    def __init__(self, config, steps_csv: Path, echo=None, before=None):
        self.steps_csv = steps_csv
        self.before = before
        self._before_rows = None
        self.phi0 = initial_packing_fraction(config)
        self.target = config["stop"]["packing_fraction"]
        self.max_time = config["stop"]["max_time"]
        self.max_steps = config["stop"]["steps"]
        #: [stop] base_area_fraction (3D), against the first row's phi_base
        self.base_target = config["stop"].get("base_area_fraction", 0.0)
        self.started = time.time()
        self.echo = echo
        self.tty = echo is not None and sys.stdout.isatty()
        self.logged = -1  # last 5 % mark written to the log / non-tty
        self.logged_rows = 0  # the rows it had
        self.stages = list(config.get("stages") or [])

    def stage_line(self, rows) -> str:
        """The progress line of a run with stages."""
        k, stage_rows = current_stage(rows)
        stage = self.stages[min(k, len(self.stages) - 1)]
        start = stage_rows[0]
        fractions = [stage_status(stage["stop"], start, row)[0]
                     for row in stage_rows]
        done, what = stage_status(stage["stop"], start, stage_rows[-1])
        seconds = [r.get("seconds", float("nan")) for r in stage_rows]
        row = rows[-1]
        # An equilibrium may come before the time bound the fraction counts
        bound = "<= " if stage["stop"].get("equilibrium", 0) > 0 else ""
        return (f"stage {k + 1}/{len(self.stages)} {stage['name']!r}: {what}"
                f" ({100 * done:.0f} %)  step {int(row['step'])}  Phi ="
                f" {row.get('phi', math.nan):.4f}  elapsed"
                f" {duration(time.time() - self.started)}  stage ETA {bound}"
                f"{duration(remaining_seconds(fractions, seconds))}")

    def mark(self, rows) -> int:
        """The 5 % mark reached (per stage with stages)."""
        if not self.stages:
            return int(20 * self.fraction(rows[-1], rows[0]["step"],
                                          rows[0]))
        k, stage_rows = current_stage(rows)
        stage = self.stages[min(k, len(self.stages) - 1)]
        done = stage_status(stage["stop"], stage_rows[0], stage_rows[-1])[0]
        return 21 * k + int(20 * done)

    def fraction(self, row, first_step, first=None) -> float:
        """Fraction of the run done at ``row``, in [0, 1] (``first``: the
        first row, for a 3D run's phi_base)."""
        phi, t = row.get("phi", float("nan")), row["time"]
        done = t / self.max_time
        if self.target > 0 and phi == phi:
            done = max(done, (phi - self.phi0) / (self.target - self.phi0))
        base = row.get("phi_base", float("nan"))
        if self.base_target > 0 and first is not None and base == base:
            base0 = first["phi_base"]
            done = max(done, (base - base0) / (self.base_target - base0))
        if self.max_steps > 0:
            done = max(done, (row["step"] - first_step) / self.max_steps)
        return min(max(done, 0.0), 1.0)

    def line(self, rows) -> str:
        """One progress line from the rows of ``steps.csv`` so far."""
        if self.stages:
            return self.stage_line(rows)
        row = rows[-1]
        first = rows[0]["step"]
        fractions = [self.fraction(r, first, rows[0]) for r in rows]
        seconds = [r.get("seconds", float("nan")) for r in rows]
        done = fractions[-1]
        elapsed = time.time() - self.started
        eta = remaining_seconds(fractions, seconds)
        phi = row.get("phi", float("nan"))
        return (f"{100 * done:5.1f} %  step {int(row['step'])}  t ="
                f" {row['time']:.4g} s  Phi = {phi:.4f}  elapsed"
                f" {duration(elapsed)}  ETA {duration(eta)}")

    def rows(self) -> list[dict]:
        """The run's rows so far (a resumed run's killed part first)."""
        rows = read_rows(self.steps_csv)
        if self.before is None or not rows:
            return rows
        from softpack.simulation.resume import splice_rows

        if self._before_rows is None:  # the killed part does not change
            self._before_rows = read_rows(self.before)
        return splice_rows(self._before_rows, rows, int(rows[0]["step"]),
                           "step", "seconds")

    def update(self, log, final=False) -> None:
        """Show the latest row: a live line on a terminal, 5 % marks else."""
        rows = self.rows()
        if not rows:
            return
        text = self.line(rows)
        mark = self.mark(rows)
        if self.tty:
            self.echo(f"\r{text}", end="\n" if final else "")
        # the final row once: not again when its mark was just written
        if mark > self.logged or (final and len(rows) != self.logged_rows):
            self.logged, self.logged_rows = mark, len(rows)
            if self.echo is not None and not self.tty:
                self.echo(text)
            log.write(f"[progress] {text}\n")
            log.flush()


def current_stage(rows) -> tuple[int, list]:
    """The stage of the last row and its rows, led by the row where the
    stage before it ended (its start), when there is one."""
    k = int(rows[-1].get("stage", 0))
    first = next(i for i, r in enumerate(rows) if int(r.get("stage", 0)) == k)
    return k, rows[max(first - 1, 0):]


#: The box wall facing each box wall.
_FACING = {"left": "right", "right": "left", "bottom": "top", "top": "bottom"}


def _box_length(row, wall) -> float:
    """Distance between a box wall and the one facing it (NaN if not a box
    wall of the row)."""
    if wall not in _FACING:
        return math.nan
    axis = "x" if wall in ("left", "right") else "y"
    return abs(row.get(f"{wall}_{axis}", math.nan)
               - row.get(f"{_FACING[wall]}_{axis}", math.nan))


def _box_pressure(row) -> float:
    """The box's wall pressure of a row (as the stage criterion's)."""
    from softpack.analysis.stress import wall_normal_stresses
    try:
        stresses = wall_normal_stresses({k: np.array([v])
                                         for k, v in row.items()})
    except KeyError:
        return math.nan
    return float(np.mean([v[0] for v in stresses.values()]))


def stage_status(stop: dict, start: dict, row: dict) -> tuple[float, str]:
    """How far a stage is from its criteria at ``row``: the largest
    fraction over them (in [0, 1]) and what it says; ``start`` the row where
    the stage began (:func:`current_stage`)."""
    elapsed = row["time"] - start["time"]
    status = [(elapsed / stop["max_time"],
               f"t = {elapsed:.4g} of {stop['max_time']:.4g} s")]
    if stop.get("packing_fraction", 0) > 0:
        phi0, phi, target = (start.get("phi", math.nan),
                             row.get("phi", math.nan), stop["packing_fraction"])
        status.append(((phi - phi0) / (target - phi0),
                       f"Phi = {phi:.4f} to {target:.4f}"))
    if stop.get("strain", 0) > 0:
        wall = stop.get("strain_wall", "")
        length0 = _box_length(start, wall)
        strain = (length0 - _box_length(row, wall)) / length0
        status.append((abs(strain) / stop["strain"],
                       f"strain {strain:.4f} of {stop['strain']:.4g}"))
    if stop.get("pressure", 0) > 0:
        p0, p, target = _box_pressure(start), _box_pressure(row), \
            stop["pressure"]
        status.append(((p - p0) / (target - p0),
                       f"P = {p / 1e3:.4g} to {target / 1e3:.4g} kPa"))
    if stop.get("equilibrium", 0) > 0:
        status.append((0.0, f"until equilibrium {stop['equilibrium']:.2g}"))
    known = [f for f, _ in status if f == f]
    fraction = min(max(max(known), 0.0), 1.0) if known else 0.0
    return fraction, "; ".join(text for _, text in status[1:] + status[:1])


def remaining_seconds(fractions, seconds) -> float:
    """Seconds left from a history of (fraction done, seconds spent).

    The cost per unit of progress is measured on each half of the history
    (seconds over fraction gained: averages over many rows, robust to a
    busy machine's noise); a straight line through the two, ``c(f)``, at
    their midpoints, is integrated from the last fraction to 1 (exact when
    the cost grows linearly). Its slope is taken as zero if the cost fell
    (a start transient: a compaction only gets dearer), so the estimate is
    never below the recent pace's. With fewer than :data:`MIN_FIT_ROWS`
    intervals: the constant pace of the whole history.

    Returns
    -------
    float
        NaN when nothing is known yet, 0 when done.
    """
    f = np.asarray(fractions, dtype=float)
    t = np.asarray(seconds, dtype=float)
    keep = np.isfinite(f) & np.isfinite(t)
    f, t = f[keep], t[keep]
    if len(f) == 0:
        return float("nan")
    if f[-1] >= 1.0:
        return 0.0
    forward = np.concatenate(([True], np.diff(f) > 0))  # progress made
    f, t = f[forward], t[forward]
    if len(f) < 2:
        return float("nan")
    rest = 1.0 - f[-1]
    if len(f) - 1 < MIN_FIT_ROWS:
        return (t[-1] - t[0]) / (f[-1] - f[0]) * rest
    k = len(f) // 2
    early = (t[k] - t[0]) / (f[k] - f[0])
    late = (t[-1] - t[k]) / (f[-1] - f[k])
    trend = max((late - early) / (0.5 * (f[-1] - f[0])), 0.0)
    now = late + trend * 0.5 * (f[-1] - f[k])
    return float(now * rest + 0.5 * trend * rest ** 2)


def read_rows(path: Path) -> list[dict]:
    """The complete rows of a growing CSV file as dicts of floats."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError:
        return []
    if len(lines) < 2:
        return []
    header = lines[0].split(",")
    rows = []
    for line in lines[1:]:
        values = line.split(",")
        if len(values) != len(header):
            continue  # a row being written
        try:
            rows.append({k: float(v) if v else float("nan")
                         for k, v in zip(header, values)
                         if v not in ("true", "false")})
        except ValueError:
            continue
    return rows


def duration(seconds) -> str:
    """``1h02m03s`` style; ``?`` when unknown."""
    if seconds != seconds or seconds == float("inf"):
        return "?"
    s = int(round(seconds))
    h, m = s // 3600, s // 60 % 60
    return f"{h}h{m:02d}m{s % 60:02d}s" if h else f"{m}m{s % 60:02d}s"
