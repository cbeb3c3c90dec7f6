"""``./softpack bench --solids3d``: cost per 3D time step against tetrahedra.

Issue 40 asks for the cost per step against the number of tetrahedra
(target ~N^1.1). The scene is examples/cylinders3d_small.toml (14 standing
cylinders, D 20/30 mm, H 15 mm, frictionless base) at several element sizes
(``mesh.element_size``), its contact distances scaled with the element size
as the example sets them at 4 mm (alert distance a third of it: 1.3 mm,
max_penetration half of it: 2 mm; the example's comments say why). Each
size, with the same packing (seed 0), runs twice:

1. **compaction**: the piston at 1 m/s (twice the example's) from the
   initial packing until the bottom faces cover ``compact_to`` (0.76) of
   the base, writing its state;
2. **timed**: from that state, the piston at the example's 0.5 m/s for
   ``warm`` + ``steps`` steps, an output row at every step (no state
   file); the cost is that of the last ``steps`` (from the row ``warm``
   steps after the state to the last: the first step from a state
   computes the compliance columns of every contact node afresh, and the
   bodies slow from 1 to 0.5 m/s). The rows' wall time includes the
   output (a row and a contact file per step: ``ms_other``, the wall time
   per step minus its parts, bounds it).

Every size thus starts its timed steps at the same phi_base, from the same
packing, with contacts in place. Per size: tetrahedra, nodes, contact
candidates and active contacts (mean over the timed rows), driver seconds
per step and its split by part (``seconds_*`` columns of raw/steps.csv:
assembly, factorization, solves, Delassus, detection, NLGS), NLGS sweeps
and Newton iterations per step, the median step and the refactorizations
among the timed steps (a refactorization step rebuilds every kept
compliance column: a few of them make most of the Delassus time of a short
window), the peak resident memory of the timed
run's driver (``wait4``), and whether every Newton iteration and contact
solve of the timed steps converged (those of the compaction reported
apart). The NLGS yardstick (``softpack-bench-nlgs``, sweeps per second on
the 2020-contact FCLIB problem; the median of three) is run before and
after, with the load average: this host's speed moves by up to 3x from day
to day, and other jobs share its two cores. The exponents p of cost ~ N^p
(N tetrahedra) are least-squares fits in log-log over the sizes (and
between the two finest meshes): per step, per NLGS sweep, per part, of
the sweeps per step, the contacts and the peak memory.

With a state of examples/paper3d.toml (``--from-state
runs/paper3d.../raw/state.bin``, the paper's 100 cylinders at 4 mm), the
same ``warm`` + ``steps`` steps of that run from it are timed too: the
100-body scene at the targets' scale, reported beside the fit, not in it.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from softpack import paths
from softpack.bench.common import PARTS, WORK, bench_nlgs
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.scene.build import build_scene
from softpack.scene.config import load_config

SCENE_TOML = paths.ROOT / "examples" / "cylinders3d_small.toml"
PAPER3D_TOML = paths.ROOT / "examples" / "paper3d.toml"
#: Element sizes (m) of ``./softpack bench --solids3d``: 2,700 to 42,336
#: tetrahedra.
SIZES = (6e-3, 4e-3, 3e-3, 2.5e-3)
#: The example's contact distances at its 4 mm, scaled with the size.
ALERT_PER_SIZE = 1.3e-3 / 4e-3
PENETRATION_PER_SIZE = 2e-3 / 4e-3
COMPACT_SPEED = 1.0
#: A row at every step of a timed run (each step's sweeps and contacts),
#: no state file
TIMED_OUTPUT = {"output.every_steps": 1, "output.state": False}
TIMED_SPEED = 0.5


def size_overrides(size: float) -> dict:
    """The example's scene at element size ``size`` (m), no fields."""
    return {"mesh.element_size": size,
            "contact.alert_distance": ALERT_PER_SIZE * size,
            "contact.max_penetration": PENETRATION_PER_SIZE * size,
            "output.fields": False}


def bench_solids3d(sizes=SIZES, steps: int = 30, warm: int = 10,
                   compact_to: float = 0.76, work: Path = WORK,
                   scene_toml: Path = SCENE_TOML,
                   paper3d_state: Path | None = None) -> dict:
    """Time each element size (module doc) and, given ``paper3d_state``,
    the paper's 100 cylinders from it (:func:`bench_paper3d_state`); the
    report with the fits."""
    work.mkdir(parents=True, exist_ok=True)
    load = [os.getloadavg()[0]]
    before = yardstick()
    rows = [_one_size(size, steps, warm, compact_to, work, scene_toml)
            for size in sizes]
    paper3d = (bench_paper3d_state(paper3d_state, steps, warm, work)
               if paper3d_state is not None else None)
    after = yardstick()
    load.append(os.getloadavg()[0])
    report = {"scene": str(Path(scene_toml).relative_to(paths.ROOT)
                           if Path(scene_toml).is_relative_to(paths.ROOT)
                           else scene_toml),
              "compact_speed": COMPACT_SPEED, "timed_speed": TIMED_SPEED,
              "compact_to_phi_base": compact_to, "warm_steps": warm,
              "timed_steps": steps, "rows": rows,
              "nlgs_yardstick_before": before, "nlgs_yardstick_after": after,
              "nlgs_yardstick": _mean([before, after]),
              "load_average_before_after": load}
    if len(rows) >= 2:
        report["exponents"] = exponents(rows)
    if paper3d is not None:
        report["paper3d"] = paper3d
    return report


def _one_size(size, steps, warm, compact_to, work, scene_toml) -> dict:
    """Compaction then timed run at one element size."""
    from softpack.simulation import driver

    tag = f"solids3d-h{size * 1e3:g}mm"
    compact = load_config(scene_toml, {
        **size_overrides(size),
        "walls.right.velocity": [-COMPACT_SPEED, 0.0],
        "stop.base_area_fraction": compact_to, "output.every_steps": 10})
    scene = build_scene(compact, work / f"mesh-{tag}")
    record = scene.record()
    first = RunDirectory(work / f"{tag}-compact")
    done_compact = driver.launch(first, compact, record, quiet=True).done
    timed = load_config(scene_toml, {
        **size_overrides(size), "walls.right.velocity": [-TIMED_SPEED, 0.0],
        "stop.steps": warm + steps, "stop.base_area_fraction": 0.0,
        **TIMED_OUTPUT})
    run = RunDirectory(work / f"{tag}-timed")
    finished = driver.launch(run, timed, record, quiet=True,
                             initial_state=first.raw.state_bin)
    return {"element_size": size, **_timed_row(run, finished, scene, warm),
            "compaction_steps": int(done_compact["steps"]),
            "compaction_seconds": float(done_compact["seconds"]),
            "compaction_converged": bool(done_compact["converged"]),
            "compaction_newton_unconverged_steps": int(
                done_compact["newton_unconverged_steps"]),
            "compaction_nlgs_unconverged_steps": int(
                done_compact["nlgs_unconverged_steps"]),
            "compaction_reason": done_compact["reason"]}


def _timed_row(run, finished, scene, warm) -> dict:
    """A timed run's row: :func:`timed_cost`, the mesh, convergence and
    peak memory."""
    row = timed_cost(read_table(run.raw.steps_csv), warm)
    done = finished.done
    row.update(
        tetrahedra=int(scene.mesh.n_triangles),
        nodes=int(sum(scene.mesh.nodes_per_body)),
        bodies=len(scene.mesh.nodes_per_body),
        max_overlap_depth=float(done["max_overlap_depth"]),
        peak_memory_mb=float(finished.peak_memory_mb))
    row["converged"] = not (row["newton_unconverged_steps"]
                            or row["nlgs_unconverged_steps"])
    row["ms_per_sweep"] = (row["ms_nlgs"] / row["sweeps_per_step"]
                           if row["sweeps_per_step"] else math.nan)
    return row


def bench_paper3d_state(state: Path, steps: int = 30, warm: int = 10,
                        work: Path = WORK) -> dict:
    """``warm`` + ``steps`` steps of examples/paper3d.toml (the paper's 100
    cylinders, 4 mm) from ``state``, a state of that run (its
    raw/state.bin), timed as :func:`timed_cost`: a point with the targets'
    100 bodies, outside the fit."""
    from softpack.simulation import driver

    config = load_config(PAPER3D_TOML, {
        "output.fields": False, "stop.steps": warm + steps,
        **TIMED_OUTPUT})
    scene = build_scene(config, work / "mesh-solids3d-paper3d")
    run = RunDirectory(work / "solids3d-paper3d-timed")
    finished = driver.launch(run, config, scene.record(), quiet=True,
                             initial_state=Path(state).resolve())
    return {"scene": str(PAPER3D_TOML.relative_to(paths.ROOT)),
            "state": str(state),
            "element_size": config["mesh"]["element_size"],
            **_timed_row(run, finished, scene, warm)}


def timed_cost(rows: dict, warm: int) -> dict:
    """The cost of the steps after the first ``warm`` of a run from a state
    (``rows``: its raw/steps.csv): from the output row ``warm`` steps after
    the first to the last, from the cumulative ``seconds*`` columns; the
    sweeps and Newton iterations per step, contacts and phi_base of the
    output rows in between (each row's own step: a sample)."""
    step = np.asarray(rows["step"], dtype=int)
    start = int(np.searchsorted(step, step[0] + warm))
    if start >= len(step) - 1:
        raise ValueError(f"no output row after the {warm} warm steps and"
                         f" before the last (steps {step[0]}..{step[-1]})")
    steps = int(step[-1] - step[start])
    span = lambda key: float(rows[key][-1] - rows[key][start])
    out = {"first_step": int(step[0]), "steps": steps,
           "seconds": span("seconds"),
           "ms_per_step": 1e3 * span("seconds") / steps}
    for part in PARTS:
        out[f"ms_{part}"] = 1e3 * span(f"seconds_{part}") / steps
    out["ms_other"] = out["ms_per_step"] - sum(out[f"ms_{p}"] for p in PARTS)
    sample = slice(start + 1, None)
    mean = lambda key: float(np.mean(rows[key][sample]))
    # a refactorization step also rebuilds every kept compliance column
    # (Delassus): the window's cost depends on how many it holds
    wall = (np.diff(np.asarray(rows["seconds"], float)[start:])
            / np.diff(step[start:]))
    out.update(refactorizations=int(np.sum(rows["refactorized"][sample])),
               ms_per_step_median=1e3 * float(np.median(wall)),
               ms_per_step_max=1e3 * float(np.max(wall)))
    # done.json's counts include those a state carries (the run before)
    for key in ("newton_unconverged_steps", "nlgs_unconverged_steps"):
        out[key] = int(rows[key][-1] - rows[key][0])
    out.update(contacts=mean("contacts"),
               active_contacts=mean("active_contacts"),
               sweeps_per_step=mean("nlgs_iterations"),
               newton_per_step=mean("newton_iterations"),
               phi_base_start=float(rows["phi_base"][start]),
               phi_base_end=float(rows["phi_base"][-1]))
    return out


def power_fit(x, y) -> float:
    """The exponent p of y ~ x^p (least squares in log-log)."""
    x, y = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    return float(np.polyfit(x, y, 1)[0])


def exponents(rows: list[dict]) -> dict:
    """Fitted exponents against tetrahedra: per step, per sweep, by part,
    of the contacts and of the peak memory."""
    n = [r["tetrahedra"] for r in rows]
    out = _fits(rows, n)
    if len(rows) > 2:  # the local exponents between the two finest meshes
        finest = sorted(rows, key=lambda r: r["tetrahedra"])[-2:]
        out["finest_two"] = _fits(finest, [r["tetrahedra"] for r in finest])
    return out


def _fits(rows, n) -> dict:
    """:func:`power_fit` of each quantity of ``rows`` against ``n``."""
    keys = (["ms_per_step", "ms_per_step_median", "ms_per_sweep",
             "sweeps_per_step", "contacts",
             "active_contacts", "peak_memory_mb"]
            + [f"ms_{p}" for p in PARTS])
    out = {}
    for key in keys:
        y = [r[key] for r in rows]
        if all(v > 0 and v == v for v in y):
            out[key] = power_fit(n, y)
    return out


def _exponents(fits: dict) -> str:
    return ", ".join(f"{k} {v:.2f}" for k, v in fits.items()
                     if not isinstance(v, dict))


def _line(r: dict) -> str:
    """One row of :func:`table`."""
    return (f"{r['element_size'] * 1e3:5.2g} {r['tetrahedra']:7d}"
            f" {r['nodes']:6d} {r['contacts']:6.0f}"
            f" {r['active_contacts']:5.0f}"
            f" {r['ms_per_step']:8.0f} {r['ms_per_step_median']:6.0f}"
            f" {r['refactorizations']:5d} {r['ms_assembly']:5.0f}"
            f" {r['ms_factorization']:5.0f} {r['ms_solves']:5.0f}"
            f" {r['ms_delassus']:6.0f} {r['ms_detection']:5.0f}"
            f" {r['ms_nlgs']:7.0f} {r['ms_other']:5.0f}"
            f" {r['sweeps_per_step']:6.0f}"
            f" {r['ms_per_sweep']:6.2f} {r['peak_memory_mb']:6.0f}"
            f" {'yes' if r['converged'] else 'NO'}"
            + ("" if r.get("compaction_converged", True) else
               f" (compaction: {r['compaction_newton_unconverged_steps']}"
               f" Newton, {r['compaction_nlgs_unconverged_steps']} NLGS"
               " unconverged steps)"))


def yardstick(repeats: int = 3) -> float:
    """The median of ``repeats`` runs of the NLGS yardstick (sweeps/s; one
    run lasts ~0.05 s, so that another process's burst moves it)."""
    return float(np.median([bench_nlgs().get("sweeps_per_second", math.nan)
                            for _ in range(repeats)]))


def _mean(values) -> float:
    good = [v for v in values if v]
    return sum(good) / len(good) if good else math.nan


def table(report: dict) -> str:
    """A few lines for a person."""
    lines = [f"{report['scene']}: compacted at {report['compact_speed']} m/s"
             f" to phi_base {report['compact_to_phi_base']}, then"
             f" {report['warm_steps']} + {report['timed_steps']} steps at"
             f" {report['timed_speed']} m/s (the last {report['timed_steps']}"
             f" timed; ms per step)",
             f"{'h mm':>5} {'tets':>7} {'nodes':>6} {'cand':>6} {'act':>5}"
             f" {'ms/step':>8} {'median':>6} {'refac':>5}"
             f" {'asm':>5} {'fact':>5} {'solv':>5}"
             f" {'Del':>6} {'det':>5} {'NLGS':>7} {'other':>5} {'sw/st':>6}"
             f" {'ms/sw':>6} {'MB':>6} conv"]
    for r in report["rows"]:
        lines.append(_line(r))
    if "paper3d" in report:
        lines.append(_line(report["paper3d"]) + "  <- " +
                     report["paper3d"]["scene"] + " from "
                     + report["paper3d"]["state"])
    if "exponents" in report:
        fits = report["exponents"]
        lines.append("exponents p of ~ tetrahedra^p: " + _exponents(fits))
        if "finest_two" in fits:
            lines.append("between the two finest meshes: "
                         + _exponents(fits["finest_two"]))
    lines.append(f"NLGS yardstick: {report['nlgs_yardstick_before']:.0f}"
                 f" sweeps/s before, {report['nlgs_yardstick_after']:.0f}"
                 " after; load average (1 min) "
                 + " and ".join(f"{x:.1f}" for x in
                                report.get("load_average_before_after", [])))
    return "\n".join(lines)
