"""The end-of-run summary: one line per stage (one for a run without
stages) from the tables the analysis wrote.

Each line names how the stage (the run) ended and gives, at its last output
row, the packing fraction, the box's pressure P and deviatoric stress q
(Love-Weber from the contacts, which rigid bodies take part in, and from
the walls; :func:`stress_source` when the contact estimate is missing),
its volumetric and deviatoric strains eps_v and eps_q (from the
initial box), and Z with the particles it counts (docs/observables.md).
"""

from __future__ import annotations

import math

import numpy as np

from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table


def _number(table, column, row) -> float:
    values = table.get(column) if table else None
    return float(values[row]) if values is not None else math.nan


def stress_source(stress, row, rigid: bool) -> tuple[str, str]:
    """The estimate of P and q a summary gives at a row, and what it is:
    the contacts' (Love-Weber, rigid bodies included), else the particles'
    own stress (the contact estimate needs the deformed boundaries of
    output.fields; the particles' own misses rigid bodies, so not with
    them), else the walls'."""
    if math.isfinite(_number(stress, "contact_P", row)):
        return "contact", "contacts"
    if not rigid and math.isfinite(_number(stress, "fe_P", row)):
        return "fe", ("the particles' own stress: the contact estimate"
                      " needs output.fields")
    return "wall", "walls: the contact estimate needs output.fields"


def _state(series, stress, row, rigid=False) -> str:
    """Phi, P, q, strains and Z at a row."""
    parts = [f"Phi = {_number(series, 'phi', row):.4f}"]
    if stress:
        source, what = stress_source(stress, row, rigid)
        p = _number(stress, f"{source}_P", row)
        q = _number(stress, f"{source}_q", row)
        walls = ("" if source == "wall" else
                 f"; walls: P = {_number(stress, 'wall_P', row) / 1e3:.4g}"
                 " kPa")
        parts.append(f"P = {p / 1e3:.4g} kPa, q = {q / 1e3:.4g} kPa"
                     f" ({what}{walls})")
        parts.append(f"eps_v = {_number(stress, 'eps_v', row):.4f}, eps_q ="
                     f" {_number(stress, 'eps_q', row):.4f}")
    counts = {k: _number(series, k, row)
              for k in ("retained", "rattlers", "unbalanced")}
    total = sum(v for v in counts.values() if v == v)
    z = _number(series, "z", row)
    parts.append(f"Z = {z:.3f} over {counts['retained']:.0f} of {total:.0f}"
                 f" particles (rattlers {counts['rattlers']:.0f}, unbalanced"
                 f" {counts['unbalanced']:.0f})")
    return "; ".join(parts)


def summary_lines(run_dir) -> list[str]:
    """The summary of a finished run (series.csv written)."""
    run = RunDirectory(run_dir)
    done = run.done()
    series = read_table(run.series_csv)
    stress = (read_table(run.stress_csv) if run.stress_csv.is_file()
              else None)
    rows = len(series["step"])
    if not rows:
        return []
    setup = read_setup(run_dir)
    rigid = bool(np.any(setup.body_rigid))
    if "stages" not in done:
        return [f"stopped by {done.get('reason', '?')} after"
                f" {done.get('steps', '?')} steps; "
                + _state(series, stress, rows - 1, rigid)]
    stage = np.asarray(read_table(run.raw.steps_csv)["stage"][:rows])
    ended = list(done.get("ended_by", ()))
    names = setup.stage_names
    lines = []
    for k in range(int(done["stages"])):
        mine = np.flatnonzero(stage == k)
        if not len(mine):
            continue
        last = int(mine[-1])
        how = (f"ended by {ended[k]}" if k < len(ended)
               else f"stopped by {done.get('reason', '?')} (incomplete)")
        name = names[k] if k < len(names) else ""
        label = f"stage {k}" + (f" \"{name}\"" if name else "")
        lines.append(f"{label}: {how} at t = {series['time'][last]:.4g} s"
                     f" (step {int(series['step'][last])}); "
                     + _state(series, stress, last, rigid))
    return lines


def check_lines(finish: dict) -> list:
    """What ``raw/done.json`` (``finish``) marks: a run incomplete, not
    converged, retried or overlapping.

    ``raw/done.json`` counts the steps whose Newton iterations or contact
    solves stopped unconverged, and the output steps whose bodies overlapped
    by more than ``contact.alert_distance`` (the driver's independent check).
    """
    lines = []
    if finish.get("complete", True) is False:
        lines.append(
            f"WARNING: incomplete: the run ended in stage"
            f" {finish.get('stage', '?')} '{finish.get('stage_name', '?')}'"
            f" (of {finish.get('stages', '?')}) before its stop criterion:"
            f" {finish.get('reason', '?')} (raw/done.json complete = false)")
    if finish.get("converged", True) is False:
        lines.append(
            f"WARNING: marked as not converged:"
            f" {finish.get('newton_unconverged_steps', '?')} steps with"
            f" Newton and {finish.get('nlgs_unconverged_steps', '?')} with a"
            f" contact solve unconverged (raw/steps.csv"
            f" newton_unconverged_steps, nlgs_unconverged_steps)")
    if finish.get("retried_steps", 0):
        lines.append(
            f"{finish['retried_steps']} steps were solved only after a retry"
            f" at half the time step (time.max_step_factor; raw/steps.csv"
            f" retried_steps)")
    if finish.get("overlap_steps", 0):
        lines.append(
            f"WARNING: bodies overlap by up to"
            f" {finish.get('max_overlap_depth', 0):.3g} m at"
            f" {finish['overlap_steps']} output steps (more than"
            f" contact.alert_distance; raw/steps.csv max_overlap_depth)")
    return lines
