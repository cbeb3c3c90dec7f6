"""``./softpack bench``: the benchmarks under bench/ and the paper case's cost.

Runs, in order, and prints a table (also written to
``bench/results/bench-<date>.json``):

1. ``softpack-bench-nlgs``: NLGS sweeps per second on the 2020-contact FCLIB
   problem (../shared/data/fclib).
2. ``softpack-bench-detection``: contact detection time for 100, 400 and 1600
   disks and the fitted exponent of time ~ N^p.
3. The paper case (100 disks, 92k triangles): ``--steps`` time steps from the
   initial packing at the paper's settings (h = 9 us, theta 0.5, Newton 1e-6,
   NLGS 1e-8)
   and at the defaults (h = 72 us, theta 0.55, Newton 1e-4, NLGS 1e-6), with the
   per-step cost split by part (assembly, factorization, solves, Delassus,
   detection, NLGS) and the peak memory of the driver.
4. Scaling with the number of disks (25, 100, 400; same element size, box
   scaled with sqrt(N), piston speed scaled with the box length so that the
   strain rate is the same), each compressed from its initial packing to the
   same packing fraction (``--scaling-phi``, 0.80): cost per unit strain and
   the fitted exponents.

Every run is a configuration validated like a user's: examples/paper.toml
with overrides (``section.key`` names of the schema) applied BEFORE
validation; a fixed number of steps is ``[stop] steps``. Results come from
the driver's ``raw/done.json`` and ``raw/steps.csv`` (through
:mod:`softpack.analysis.tables`), never from its binary files.

``--from-state FILE`` times ``--steps`` steps of the paper case (seed 0 mesh)
from a state a run wrote (``runs/<run>/raw/state.bin``), at both settings:
the crowded end of the compaction without recomputing its start.

``--full`` also runs the whole paper case (fast settings, seed 0) with
``./softpack run`` and reports its wall time.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import subprocess
import sys
from pathlib import Path

from softpack.analysis.strain import approach, cumulative_strain
from softpack.analysis.tables import read_table
from softpack.paths import BIN, ROOT
from softpack.scene.build import build_scene, scene_record
from softpack.scene.config import load_config
from softpack.simulation import driver
from softpack.simulation.driver_input import write_driver_json

WORK = ROOT / "bench" / "work"
RESULTS = ROOT / "bench" / "results"
PAPER_TOML = ROOT / "examples" / "paper.toml"
#: The loaded wall of the paper's box (the piston).
PISTON = "right"

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
    return _json_lines([str(BIN / "softpack-bench-nlgs")])[-1]


def bench_detection() -> list[dict]:
    """Detection time against the number of bodies, and the exponent."""
    return _json_lines([str(BIN / "softpack-bench-detection")])


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


def scaled_config(n_scale: float, overrides: dict):
    """The paper's config scaled (:func:`scaled_overrides`), no fields,
    with ``overrides`` on top; validated once, never edited after."""
    merged = scaled_overrides(load_config(PAPER_TOML), n_scale)
    merged["output.fields"] = False
    merged.update(overrides)
    return load_config(PAPER_TOML, merged)


def _scene_for(config, tag: str) -> dict:
    """driver.json's scene for the config (seed 0), the mesh cached under
    bench/work/."""
    stem = WORK / f"mesh-{tag}"
    xdmf = stem.with_suffix(".xdmf")
    if not Path(str(stem) + ".bodies.csv").exists():
        return build_scene(config, stem).record()
    return scene_record(config, xdmf)


def run_driver(config, scene: dict, name: str,
               initial_state: Path | None = None, ranks: int = 1) -> dict:
    """Run softpack-simulate (on ``ranks`` MPI ranks); its done.json plus
    steps, cost and memory (per rank on several)."""
    out = WORK / name
    out.mkdir(parents=True, exist_ok=True)
    write_driver_json(config, scene, out, initial_state)
    status, peak_mb = driver.wait(driver.start(out / "driver.json", None,
                                               quiet=True, ranks=ranks))
    if status != 0:
        raise RuntimeError(f"softpack-simulate failed on {out / 'driver.json'}")
    done = json.loads((out / "raw" / "done.json").read_text())
    rows = read_table(out / "raw" / "steps.csv")
    # Time stepping only: from the first output row (written after reading
    # the mesh and building the bodies) to the last.
    stepping = float(rows["seconds"][-1] - rows["seconds"][0])
    steps = done["steps"] - int(rows["step"][0])  # from a state: past 0
    result = {"name": name, "steps": steps, "seconds": stepping,
              "setup_seconds": float(rows["seconds"][0]),
              "ms_per_step": 1e3 * stepping / steps,
              "factorizations": done["factorizations"],
              "peak_memory_mb": peak_mb, "ranks": ranks}
    if "mpi" in done:
        result["peak_memory_mb_per_rank"] = done["mpi"]["peak_rss_mb"]
        result["nlgs_bytes_per_sweep_per_rank"] = [
            b / max(w, 1) for b, w in zip(done["mpi"]["nlgs_bytes_sent"],
                                          done["mpi"]["nlgs_sweeps"])]
    for part in PARTS:
        result[f"ms_{part}"] = 1e3 * done["seconds_by_part"][part] / steps
    return result


def bench_paper(steps: int, state: Path | None = None) -> list[dict]:
    """Per-step cost of the paper case at the paper's settings and at the
    defaults: ``steps`` steps from the initial packing, or from ``state``."""
    prefix = "late" if state is not None else "paper"
    results = []
    for label, overrides in (("paper-settings", PAPER), ("fast-settings", FAST)):
        config = scaled_config(1, {**overrides, "stop.steps": steps,
                                   "output.every_steps": steps})
        results.append(run_driver(config, _scene_for(config, "n100"),
                                  f"{prefix}-{label}", initial_state=state))
    return results


def bench_scaling(target_phi: float) -> dict:
    """Cost per unit strain for 25, 100 and 400 disks, each compressed from
    its initial packing to the packing fraction target_phi."""
    rows = []
    for scale in (0.25, 1, 4):
        config = scaled_config(scale, {**FAST, "output.every_steps": 100,
                                       "stop.packing_fraction": target_phi})
        n = sum(s["count"] for s in config["species"])
        r = run_driver(config, _scene_for(config, f"n{n}"), f"scaling-n{n}")
        steps = read_table(WORK / f"scaling-n{n}" / "raw" / "steps.csv")
        length = config["box"]["length"]
        piston = config["walls"][PISTON]["point"][0]
        travel = piston - float(steps[f"{PISTON}_x"][-1])
        strain = float(cumulative_strain(travel, length))
        r.update(disks=n, strain=strain, final_phi=float(steps["phi"][-1]),
                 seconds_per_unit_strain=r["seconds"] / strain)
        rows.append(r)

    def exponent(key, a, b):
        return (math.log(rows[b][key] / rows[a][key])
                / math.log(rows[b]["disks"] / rows[a]["disks"]))

    return {"rows": rows,
            "exponent_25_400": exponent("seconds_per_unit_strain", 0, 2),
            "exponent_100_400": exponent("seconds_per_unit_strain", 1, 2)}


def bench_invariance(max_strain: float | None = None,
                     state: Path | None = None,
                     to_phi: float | None = None) -> dict:
    """Phi(eps), E(Phi) and Z(Phi) at the fast settings against the paper's
    settings (seed 0): from the initial packing to eps = max_strain, or from
    a saved state to the packing fraction to_phi."""
    from softpack.simulation.run import run

    series = {}
    for label, overrides in (("paper", PAPER), ("fast", FAST)):
        sets = dict(overrides)
        sets["output.every_steps"] = round(9e-4 / sets["time.time_step"])
        sets["output.fields"] = False
        if to_phi is not None:
            sets["stop.packing_fraction"] = to_phi
        if max_strain is not None:
            base = load_config(PAPER_TOML)
            speed = math.hypot(*base["walls"][PISTON]["velocity"])
            sets["stop.max_time"] = float(approach(
                max_strain, base["box"]["length"])) / speed
        config = load_config(PAPER_TOML, sets)
        out = WORK / f"invariance-{label}"
        if run(config, out, force=True, initial_state=state) != 0:
            raise RuntimeError(f"invariance run {label} failed")
        series[label] = {k: list(v) for k, v in
                         read_table(out / "series.csv").items()}
    return compare_series(series["paper"], series["fast"])


def compare_series(reference: dict, other: dict) -> dict:
    """Largest differences of Phi(eps), E(Phi) and Z(Phi) between two runs,
    on the reference's output points inside the common range."""
    import numpy as np

    def on(x_key, y_key):
        x0, y0 = np.array(reference[x_key]), np.array(reference[y_key])
        x1, y1 = np.array(other[x_key]), np.array(other[y_key])
        keep = (x0 >= x1.min()) & (x0 <= x1.max()) & np.isfinite(y0)
        return x0[keep], y0[keep], np.interp(x0[keep], x1, y1)

    eps, phi0, phi1 = on("eps", "phi")
    _, e0, e1 = on("phi", "E_over_WHLmu")
    big = e0 > 0.05 * np.nanmax(e0)  # relative differences where E matters
    phis, z0, z1 = on("phi", "z")
    both = np.isfinite(z0) & np.isfinite(z1)
    # Z of one output step scatters by a few tenths (rearrangements, the
    # count over the retained particles); its mean over windows of
    # 0.01 in Phi is the curve of Fig. 8.
    edges = np.arange(np.floor(phis.min() * 100) / 100, phis.max() + 0.01, 0.01)
    binned = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        inside = both & (phis >= lo) & (phis < hi)
        if inside.sum() >= 3:
            binned.append(abs(z1[inside].mean() - z0[inside].mean()))
    return {"eps_range": [float(eps.min()), float(eps.max())],
            "energy_mean_relative_difference":
                float(np.mean(np.abs(e1[big] / e0[big] - 1))) if big.any() else None,
            "z_binned_max_difference": float(max(binned)) if binned else None,
            "phi_max_relative_difference": float(np.max(np.abs(phi1 / phi0 - 1))),
            "energy_max_relative_difference":
                float(np.max(np.abs(e1[big] / e0[big] - 1))) if big.any() else None,
            "z_max_difference": float(np.max(np.abs(z1[both] - z0[both])))
                if both.any() else None}


def bench_full() -> dict:
    """The whole paper case, fast settings, seed 0, through ./softpack run."""
    out = WORK / "full-paper-fast-seed0"
    sets = [f"--set={k}={v}" for k, v in FAST.items()]
    # an output every 0.9 ms, as the paper's 100 steps of 9 us
    every = round(9e-4 / FAST["time.time_step"])
    cmd = [sys.executable, "-m", "softpack.cli", "run",
           str(PAPER_TOML), "--out", str(out), "--force",
           f"--set=output.every_steps={every}", *sets]
    subprocess.run(cmd, check=True)
    done = json.loads((out / "raw" / "done.json").read_text())
    return {"steps": done["steps"], "seconds": done["seconds"],
            "minutes": done["seconds"] / 60, "reason": done["reason"]}


def _table(report: dict) -> str:
    lines = [f"NLGS, 2020 contacts: {report['nlgs'].get('sweeps_per_second', report['nlgs'])}"]
    for row in report["detection"]:
        if row.get("bench") == "detection":
            lines.append(f"detection, {row['bodies']:5d} bodies:"
                         f" {1e3 * row['seconds']:8.2f} ms")
        else:
            lines.append(f"detection exponent (100-1600 bodies):"
                         f" {row['exponent']:.3f}")
    header = "case              ms/step " + " ".join(f"{p[:7]:>8}" for p in PARTS)
    lines += ["", header]
    for row in report["paper"] + report.get("scaling", {}).get("rows", []):
        lines.append(f"{row['name']:<17} {row['ms_per_step']:7.1f} "
                     + " ".join(f"{row['ms_' + p]:8.1f}" for p in PARTS)
                     + f"   peak {row['peak_memory_mb']:.0f} MB")
    for row in report.get("late", []):
        lines.append(f"{row['name']:<17} {row['ms_per_step']:7.1f} "
                     + " ".join(f"{row['ms_' + p]:8.1f}" for p in PARTS)
                     + f"   (from {report['late_state']})")
    if "scaling" in report:
        s = report["scaling"]
        for row in s["rows"]:
            lines.append(f"{row['disks']:4d} disks to Phi = {row['final_phi']:.3f}:"
                         f" {row['seconds']:.0f} s, {row['steps']} steps,"
                         f" {row['seconds_per_unit_strain']:.0f} s per unit strain")
        lines.append(f"cost per unit strain ~ N^p: p = {s['exponent_25_400']:.2f}"
                     f" (25-400), {s['exponent_100_400']:.2f} (100-400)")
    if "full" in report:
        f = report["full"]
        lines.append(f"full paper case (defaults): {f['minutes']:.1f} min,"
                     f" {f['steps']} steps")
    return "\n".join(lines)


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack bench``."""
    parser = argparse.ArgumentParser(prog="softpack bench",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=100,
                        help="time steps per paper-case measurement")
    parser.add_argument("--no-scaling", action="store_true",
                        help="skip the 25/100/400-disk scaling runs")
    parser.add_argument("--scaling-phi", type=float, default=0.80,
                        help="packing fraction the scaling runs stop at")
    parser.add_argument("--from-state", type=Path, metavar="FILE",
                        help="also time --steps steps from this state of the"
                        " seed-0 paper case (a run's raw/state.bin); with"
                        " --disks: continue an earlier leg of the same case"
                        " from its state")
    parser.add_argument("--full", action="store_true",
                        help="also run the whole paper case (the defaults)")
    parser.add_argument("--invariance", type=float, metavar="EPS",
                        help="only compare the defaults and the paper's settings"
                        " from the start to this strain")
    parser.add_argument("--invariance-from", type=Path, metavar="STATE",
                        help="only compare the defaults and the paper's settings"
                        " from this state (seed 0) to --to-phi")
    parser.add_argument("--sharing", action="store_true",
                        help="only time the driver alone, beside a busy"
                        " process and beside another run (issue 18)")
    parser.add_argument("--mpi", action="store_true",
                        help="only time --steps steps of the paper case on 1,"
                        " 2 and 4 MPI ranks (from --from-state if given)")
    parser.add_argument("--mpi-to-phi", type=float, metavar="PHI",
                        help="with --mpi: run from --from-state to this"
                        " packing fraction and compare every output step"
                        " and contact file with the 1-rank run")
    parser.add_argument("--disks", type=int, metavar="N",
                        help="only compact N paper disks from a fresh"
                        " packing and mesh to --disks-phi, timed whole with"
                        " the driver's peak memory (issue 17: 1,000)")
    parser.add_argument("--disks-ranks", type=int, default=1, metavar="R",
                        help="run --disks on R MPI ranks (default 1)")
    parser.add_argument("--disks-phi", type=float, default=0.88,
                        help="packing fraction that ends --disks")
    parser.add_argument("--to-phi", type=float, default=0.84,
                        help="packing fraction that ends --invariance-from")
    return parser


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    WORK.mkdir(parents=True, exist_ok=True)
    if args.sharing:
        from softpack.bench_sharing import bench_sharing
        return _save(bench_sharing(WORK),
                     "sharing-" + _now().replace(":", "") + ".json")
    if args.disks:
        from softpack.bench_disks import bench_disks, table
        result = bench_disks(args.disks, args.disks_phi, args.disks_ranks,
                             args.from_state)
        print(table(result))
        ranks = f"r{args.disks_ranks}-" if args.disks_ranks > 1 else ""
        return _save(result, f"disks-{args.disks}-{ranks}"
                     + _now().replace(":", "") + ".json")
    if args.mpi:
        from softpack.bench_mpi import bench_mpi, table
        report = bench_mpi(WORK, args.steps, args.from_state,
                           to_phi=args.mpi_to_phi)
        print(table(report))
        return _save(report, "mpi-" + _now().replace(":", "") + ".json")
    if args.invariance or args.invariance_from:
        if args.invariance_from:
            result = bench_invariance(state=args.invariance_from,
                                      to_phi=args.to_phi)
            result["from_state"] = str(args.invariance_from)
            name = f"invariance-{args.invariance_from.stem}-to-{args.to_phi:g}.json"
        else:
            result = bench_invariance(args.invariance)
            name = "invariance.json"
        return _save(result, name)
    report = {"date": _now(),
              "cores": os.cpu_count(), "nlgs": bench_nlgs(),
              "detection": bench_detection(), "paper": bench_paper(args.steps)}
    if args.from_state:
        report["late_state"] = str(args.from_state)
        report["late"] = bench_paper(args.steps, args.from_state)
    if not args.no_scaling:
        report["scaling"] = bench_scaling(args.scaling_phi)
    if args.full:
        report["full"] = bench_full()
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"bench-{report['date'].replace(':', '')}.json"
    path.write_text(json.dumps(report, indent=2) + "\n")
    print(_table(report))
    print(f"\nwritten: {path}")
    return 0


def _now() -> str:
    """The date and time, to the second (ISO 8601)."""
    return datetime.datetime.now().isoformat(timespec="seconds")


def _save(result: dict, name: str) -> int:
    """Write a result under bench/results/ and print it."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / name).write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
