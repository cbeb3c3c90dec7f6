"""What the benchmarks share: the paper case scaled, its scene, one timed run.

Every run is a configuration validated like a user's: examples/paper.toml
with overrides (``section.key`` names of the schema) applied BEFORE
validation (:func:`scaled_config`); a fixed number of steps is ``[stop]
steps``. A run goes through the one launch
(:func:`softpack.simulation.driver.launch`) into ``bench/work/NAME``, and
its cost comes from the driver's ``raw/done.json`` and ``raw/steps.csv``
(:func:`stepping_cost`), never from its binary files.
"""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

from softpack import paths
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.scene.config import load_config

#: Where the benchmarks run and cache their meshes.
WORK = paths.ROOT / "bench" / "work"
#: Where their reports are written.
RESULTS = paths.ROOT / "bench" / "results"
PAPER_TOML = paths.ROOT / "examples" / "paper.toml"
#: The loaded wall of the paper's box (the piston).
PISTON = "right"
#: The NLGS yardstick times are normalised to (sweeps per second on the
#: 2020-contact FCLIB problem, this machine idle on 2026-12-02): the host
#: behind it changed speed by 3x between days, the yardstick with it.
REFERENCE_YARDSTICK = 42_800.0


def normalised(seconds: float, yardstick: float) -> float:
    """A time measured when the yardstick ran at ``yardstick`` sweeps/s,
    as it would be at :data:`REFERENCE_YARDSTICK` (NaN if unknown)."""
    if not yardstick or yardstick != yardstick:
        return math.nan
    return seconds * yardstick / REFERENCE_YARDSTICK


def normalised_text(seconds: float, yardstick: float) -> str:
    """``"(123 s at 42,800 sweeps/s)"``: a time in the reference's terms."""
    return (f"({normalised(seconds, yardstick):.0f} s at"
            f" {REFERENCE_YARDSTICK:,.0f} sweeps/s)")

#: The paper's numerical settings (examples/paper_9us.toml) ...
PAPER = {"time.time_step": 9e-6, "time.max_step_factor": 1.0,
         "time.theta": 0.5,
         "time.newton_tolerance": 1e-6, "contact.nlgs_tolerance": 1e-8}
#: ... and softpack's defaults (examples/paper.toml)
FAST = {"time.time_step": 7.2e-5, "time.theta": 0.55,
        "time.newton_tolerance": 1e-4, "contact.nlgs_tolerance": 1e-6}
PARTS = ("assembly", "factorization", "solves", "delassus", "detection",
         "nlgs")


def _json_lines(command) -> list[dict]:
    out = subprocess.run(command, check=True, capture_output=True,
                         text=True).stdout
    return [json.loads(line) for line in out.splitlines()
            if line.startswith("{")]


def bench_nlgs() -> dict:
    """Sweeps per second of the NLGS on the 2020-contact problem."""
    return _json_lines([str(paths.executable("softpack-bench-nlgs"))])[-1]


def bench_detection() -> list[dict]:
    """Detection time against the number of bodies, and the exponent."""
    return _json_lines([str(paths.executable("softpack-bench-detection"))])


def scaled_overrides(base, n_scale: float) -> dict:
    """Overrides of ``base`` (the paper's config) for n_scale times the
    disks in a box scaled with their total area, the piston speed scaled
    like the box length (the same strain rate)."""
    species = base["species"]
    counts = [round(s["count"] * n_scale) for s in species]
    # box scaled with the disks' total area (not n_scale: counts are
    # rounded), so that every size starts at the same packing fraction
    area = lambda cs: sum(c * s["diameter"] ** 2
                          for c, s in zip(cs, species))
    scale = math.sqrt(area(counts) / area([s["count"] for s in species]))
    vx, vy = base["walls"][PISTON]["velocity"]
    out = {f"species.{i}.count": c for i, c in enumerate(counts)}
    out.update({"box.length": base["box"]["length"] * scale,
                "box.width": base["box"]["width"] * scale,
                f"walls.{PISTON}.velocity": [vx * scale, vy * scale]})
    return out


def scaled_config(n_scale: float, overrides: dict, tables=None):
    """The paper's config scaled (:func:`scaled_overrides`), no fields,
    with ``overrides`` on top and ``tables`` (list sections, e.g.
    ``{"friction": [...]}``) added; validated once, never edited after."""
    import tomllib

    from softpack.scene.config import validate

    merged = scaled_overrides(load_config(PAPER_TOML), n_scale)
    merged["output.fields"] = False
    merged.update(overrides)
    if not tables:
        return load_config(PAPER_TOML, merged)
    with open(PAPER_TOML, "rb") as f:
        data = tomllib.load(f)
    return validate({**data, **tables}, PAPER_TOML, merged)


def scene_for(config, tag: str) -> dict:
    """driver.json's scene for the config (seed 0), the mesh cached under
    bench/work/."""
    from softpack.scene.build import build_scene, scene_record
    from softpack.scene.mesh import output_paths

    stem = WORK / f"mesh-{tag}"
    xdmf, _, bodies_csv = output_paths(stem)
    if not bodies_csv.exists():
        return build_scene(config, stem).record()
    return scene_record(config, xdmf)


def stepping_cost(run: RunDirectory, done: dict) -> dict:
    """Steps, seconds and milliseconds per step (whole and by part) of the
    time stepping: from the first output row (written after reading the
    mesh and building the bodies; past step 0 from a state) to the last."""
    rows = read_table(run.raw.steps_csv)
    stepping = float(rows["seconds"][-1] - rows["seconds"][0])
    steps = done["steps"] - int(rows["step"][0])
    cost = {"steps": steps, "seconds": stepping,
            "setup_seconds": float(rows["seconds"][0]),
            "ms_per_step": 1e3 * stepping / steps}
    for part in PARTS:
        cost[f"ms_{part}"] = 1e3 * done["seconds_by_part"][part] / steps
    return cost


def run_driver(config, scene: dict, name: str,
               initial_state: Path | None = None, ranks: int = 1) -> dict:
    """Run softpack-simulate (on ``ranks`` MPI ranks) in ``WORK/name``; its
    cost (:func:`stepping_cost`), factorizations and memory (per rank on
    several)."""
    from softpack.simulation import driver

    run = RunDirectory(WORK / name)
    finished = driver.launch(run, config, scene, initial_state=initial_state,
                             quiet=True, ranks=ranks)
    done = finished.done
    cost = stepping_cost(run, done)
    result = {"name": name, **{k: cost[k] for k in (
        "steps", "seconds", "setup_seconds", "ms_per_step")},
              "factorizations": done["factorizations"],
              "peak_memory_mb": finished.peak_memory_mb, "ranks": ranks}
    if "mpi" in done:
        result["peak_memory_mb_per_rank"] = done["mpi"]["peak_rss_mb"]
        result["nlgs_bytes_per_sweep_per_rank"] = [
            b / max(w, 1) for b, w in zip(done["mpi"]["nlgs_bytes_sent"],
                                          done["mpi"]["nlgs_sweeps"])]
    result.update({f"ms_{part}": cost[f"ms_{part}"] for part in PARTS})
    return result
