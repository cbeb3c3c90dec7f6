"""``./softpack bench --sharing``: the driver alone and beside other work.

Issue 18: with OpenMP threads spinning at barriers, a run slowed down 6-20
times when another process shared the cores. This measures, on a 26-disk case
(the paper's box and species scaled to 0.26, 2 mm triangles, ``STEPS`` steps
from the initial packing), the driver's wall and CPU time

``alone``
    nothing else started by the benchmark (the machine should be idle);
``beside_busy``
    beside one single-threaded busy loop (a CPU-fair share is half the
    machine, so the target is wall <= 2.2 x alone);
``two_runs``
    two drivers side by side (each should take <= ~2.2 x alone);
``beside_busy_spinning``
    as ``beside_busy`` with ``OMP_WAIT_POLICY=ACTIVE``, libgomp spinning at
    every barrier: the behaviour before the fix, for comparison.

The driver sets ``OMP_WAIT_POLICY=PASSIVE`` itself when the variable is unset
(driver/apps/threads.h); the benchmark clears it for the first three cases.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from softpack.bench.common import scaled_config, scene_for
from softpack.contract.run_directory import RunDirectory
from softpack.simulation import driver
from softpack.simulation.driver_input import write_driver_json

STEPS = 1500
#: Scale of the paper's assembly: 18 small and 8 large disks.
SCALE = 0.26
ELEMENT_SIZE = 2e-3


def _prepare(work: Path) -> list[Path]:
    """driver.json of the 26-disk case in ``work/sharing-a`` and
    ``work/sharing-b`` (two runs of it side by side; mesh cached)."""
    config = scaled_config(SCALE, {
        "mesh.element_size": ELEMENT_SIZE, "stop.steps": STEPS,
        "output.every_steps": STEPS, "output.state": False})
    scene = scene_for(config, "sharing-n26")
    runs = [RunDirectory(work / name) for name in ("sharing-a", "sharing-b")]
    for run in runs:
        write_driver_json(config, scene, run.path, None)
    return [run.driver_json for run in runs]


def _start(driver_json: Path, policy: str | None) -> subprocess.Popen:
    """Start the driver with OMP_WAIT_POLICY set to ``policy`` or unset."""
    saved = os.environ.pop("OMP_WAIT_POLICY", None)
    try:
        if policy is not None:
            os.environ["OMP_WAIT_POLICY"] = policy
        return driver.start(driver_json, None, quiet=True)
    finally:
        os.environ.pop("OMP_WAIT_POLICY", None)
        if saved is not None:
            os.environ["OMP_WAIT_POLICY"] = saved


def _finish(proc: subprocess.Popen, started: float) -> dict:
    """Wait for one driver: wall and CPU seconds (its own rusage)."""
    status, usage = driver.wait_usage(proc)
    wall = time.monotonic() - started
    if status != 0:
        raise RuntimeError("softpack-simulate failed in the sharing bench")
    return {"wall_s": round(wall, 2),
            "cpu_s": round(usage.ru_utime + usage.ru_stime, 2)}


def _timed(jsons, policy=None, busy=False) -> list[dict]:
    """Run the drivers of ``jsons`` together (beside a busy loop if asked)."""
    loop = (subprocess.Popen([sys.executable, "-c", "while True: pass"])
            if busy else None)
    try:
        started = time.monotonic()
        procs = [_start(j, policy) for j in jsons]
        return [_finish(p, started) for p in procs]
    finally:
        if loop is not None:
            loop.kill()
            loop.wait()


def bench_sharing(work: Path) -> dict:
    """The four cases; ratios of wall time to the run alone."""
    work.mkdir(parents=True, exist_ok=True)
    first, second = _prepare(work)
    alone = _timed([first])[0]
    result = {"case": f"26 disks, {ELEMENT_SIZE * 1e3:g} mm mesh, {STEPS}"
              " steps", "cores": os.cpu_count(), "alone": alone,
              "beside_busy": _timed([first], busy=True)[0],
              "two_runs": _timed([first, second]),
              "beside_busy_spinning": _timed([first], "ACTIVE", busy=True)[0]}
    base = alone["wall_s"]
    result["ratios"] = {
        "beside_busy": round(result["beside_busy"]["wall_s"] / base, 2),
        "two_runs": round(max(r["wall_s"] for r in result["two_runs"])
                          / base, 2),
        "beside_busy_spinning": round(
            result["beside_busy_spinning"]["wall_s"] / base, 2)}
    return result
