"""``./softpack bench --disks N``: N paper disks compacted, timed whole.

Issue 17 item 2 asks for 1,000 disks from Phi 0.75 to 0.88 in at most an
hour, packing and meshing included, under 1 GB of peak memory. This runs
that case as ``./softpack bench`` scales the paper's (same species, element
size and initial packing fraction, box scaled with the disks' area, piston
speed with the box length: the same strain rate), at the defaults, from a
fresh packing and mesh (timed: the scene stage is part of the target) to
``--disks-phi``, and reports

- the seconds of the scene stage (packing and meshing, Python and gmsh),
- the driver's wall time, steps, the per-step split by part and the peak
  resident memory (``wait4``; per rank from done.json with
  ``--disks-ranks R``, issue 14's 4,000-disk case),
- the cost per unit strain, to compare with the 25/100/400-disk scaling
  rows of ``./softpack bench``,
- the NLGS yardstick of the day (sweeps per second on the FCLIB problem),
  since this host's speed moves by 1.5-3x from day to day.

A case longer than a sitting runs in legs: ``--from-state STATE`` continues
from the state file of an earlier leg (copied out of ``bench/work`` first:
the leg writes there again); the scene is built again from the same seed
and the driver refuses a state of another mesh. A leg reports its own
steps, time and strain (from its first output row).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from softpack.analysis.strain import cumulative_strain
from softpack.bench.common import (FAST, PISTON, WORK, bench_nlgs,
                                   normalised_text, run_driver,
                                   scaled_config)
from softpack.bench.periodic import periodic_config
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.scene.build import build_scene


def bench_disks(count: int, to_phi: float, ranks: int = 1,
                state: Path | None = None, periodic: bool = False) -> dict:
    """Compact ``count`` disks to ``to_phi`` on ``ranks`` MPI ranks (from
    ``state``, a leg of a longer case, if given), in the box or, with
    ``periodic``, in a cell (:func:`.periodic.periodic_config`); see the
    module doc."""
    config = scaled_config(count / 100, {
        **FAST, "output.every_steps": 100,
        "stop.packing_fraction": to_phi})
    if periodic:
        config = periodic_config(config, to_phi=to_phi)
    n = sum(s["count"] for s in config["species"])
    name = (f"disks-n{n}" + ("-periodic" if periodic else "")
            + (f"-r{ranks}" if ranks > 1 else ""))
    start = time.perf_counter()
    scene = build_scene(config, WORK / f"mesh-{name}").record()
    scene_seconds = time.perf_counter() - start
    start = time.perf_counter()
    result = run_driver(config, scene, name, initial_state=state,
                        ranks=ranks)
    driver_seconds = time.perf_counter() - start
    steps = read_table(RunDirectory(WORK / name).raw.steps_csv)
    strain = _cell_strain(steps) if periodic else _piston_strain(steps,
                                                                 config)
    result.update(
        disks=n, periodic=periodic, target_phi=to_phi, final_phi=float(steps["phi"][-1]),
        initial_phi=float(steps["phi"][0]),
        from_state=str(state) if state is not None else None,
        scene_seconds=scene_seconds, driver_seconds=driver_seconds,
        whole_seconds=scene_seconds + driver_seconds, strain=strain,
        seconds_per_unit_strain=result["seconds"] / strain,
        nlgs_yardstick=bench_nlgs().get("sweeps_per_second"))
    return result


def _piston_strain(steps, config) -> float:
    """The piston's strain over this leg: from its first output row (step
    0 of a fresh run), where the box is shorter than its initial length by
    the piston's travel so far."""
    piston = steps[f"{PISTON}_x"]
    x0 = config["walls"][PISTON]["point"][0]
    length = config["box"]["length"] - (x0 - float(piston[0]))
    return float(cumulative_strain(float(piston[0] - piston[-1]), length))


def _cell_strain(steps) -> float:
    """ln(A_first / A_last) of the cell over this leg: its volumetric
    strain, which is the piston's strain for a box (its area is
    proportional to its length)."""
    area = np.abs(steps["cell_a1x"] * steps["cell_a2y"]
                  - steps["cell_a1y"] * steps["cell_a2x"])
    return float(np.log(area[0] / area[-1]))


def table(r: dict) -> str:
    """A few lines for a person."""
    parts = ", ".join(f"{p} {r['ms_' + p]:.0f}" for p in
                      ("assembly", "factorization", "solves", "delassus",
                       "detection", "nlgs"))
    return "\n".join([
        f"{r['disks']} disks{' in a periodic cell' if r.get('periodic') else ''} to Phi = {r['final_phi']:.3f}"
        f" (target {r['target_phi']}): {r['steps']} steps"
        + (f" from Phi = {r['initial_phi']:.4f} (a leg, from {r['from_state']})"
           if r.get("from_state") else ""),
        f"scene (packing + meshing): {r['scene_seconds']:.1f} s",
        f"driver: {r['driver_seconds']:.0f} s wall, {r['ms_per_step']:.0f}"
        f" ms per step ({parts})",
        f"whole: {r['whole_seconds'] / 60:.1f} min"
        f" {normalised_text(r['whole_seconds'], r['nlgs_yardstick'])};"
        f" {r['seconds_per_unit_strain']:.0f} s per unit strain",
        f"peak memory of the driver: {r['peak_memory_mb']:.0f} MB"
        + (f" (per rank: {', '.join(f'{m:.0f}' for m in r['peak_memory_mb_per_rank'])}"
           f" MB on {r['ranks']} ranks)" if r.get("ranks", 1) > 1 else ""),
        f"NLGS yardstick today: {r['nlgs_yardstick']:.0f} sweeps/s"])
