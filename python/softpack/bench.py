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

``--from-state FILE`` times ``--steps`` steps of the paper case (seed 0 mesh)
from a state a run wrote (``runs/<run>/raw/state.bin``), at both settings:
the crowded end of the compaction without recomputing its start.

``--full`` also runs the whole paper case (fast settings, seed 0) with
``./softpack run`` and reports its wall time.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import math
import os
import struct
import subprocess
import sys
from pathlib import Path

from softpack.scene import config as cfg
from softpack.scene.mesh import mesh_disks
from softpack.scene.packing import random_packing

from softpack.paths import BIN, ROOT
WORK = ROOT / "bench" / "work"
RESULTS = ROOT / "bench" / "results"

#: The paper's numerical settings (examples/paper_9us.toml) ...
PAPER = {"time.time_step": 9e-6, "time.theta": 0.5,
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


def _scaled_config(n_scale: int, overrides: dict, steps: int):
    """The paper's config with n_scale times the disks in a box scaled by
    sqrt(n_scale), the piston speed scaled like the box length."""
    base = cfg.load_config(ROOT / "examples" / "paper.toml")
    g = base["geometry"]
    counts = [round(c * n_scale) for c in g["counts"]]
    # box scaled with the disks' total area (not n_scale: counts are
    # rounded), so that every size starts at the same packing fraction
    area = lambda cs: sum(c * d * d for c, d in zip(cs, g["diameters"]))
    s = math.sqrt(area(counts) / area(g["counts"]))
    merged = {"geometry.counts": counts,
              "geometry.length": g["length"] * s,
              "geometry.width": g["width"] * s,
              "loading.piston_speed": base["loading"]["piston_speed"] * s,
              "output.every_steps": steps, "output.fields": False}
    merged.update(overrides)
    config = cfg.load_config(ROOT / "examples" / "paper.toml", merged)
    config["loading"]["max_time"] = steps * config["time"]["time_step"]
    return config


def _mesh_for(config, tag: str) -> Path:
    """Mesh of the config's packing (seed 0), cached under bench/work/."""
    stem = WORK / f"mesh-{tag}"
    xdmf = stem.with_suffix(".xdmf")
    if not Path(str(stem) + ".bodies.csv").exists():
        g = config["geometry"]
        packing = random_packing(g["seed"], counts=tuple(g["counts"]),
                                 diameters=tuple(g["diameters"]),
                                 length=g["length"], width=g["width"],
                                 gap=g["gap"])
        mesh_disks(packing.centres, packing.radii,
                   config["mesh"]["element_size"], stem)
    return xdmf


def state_time(path: Path) -> float:
    """Time (s) of a state file (layout: driver/io/state_file.h)."""
    with open(path, "rb") as f:
        head = f.read(16 + 3 * 8 + 8)
    if len(head) < 48 or head[:16] != b"softpack-state-1":
        raise ValueError(f"{path}: not a softpack state file")
    return struct.unpack("<d", head[40:48])[0]


def run_driver(config, mesh: Path, name: str, initial_state: Path | None = None,
               ) -> dict:
    """Run softpack-simulate; its done.json plus steps, cost and memory."""
    out = WORK / name
    out.mkdir(parents=True, exist_ok=True)
    cfg.to_driver_json(config, mesh, out, initial_state=initial_state)
    proc = subprocess.Popen([str(BIN / "softpack-simulate"),
                             str(out / "driver.json"), "--quiet"],
                            stdout=subprocess.DEVNULL)
    # wait4 gives this child's own peak resident memory (kB on Linux)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"softpack-simulate failed on {out / 'driver.json'}")
    peak_kb = usage.ru_maxrss
    done = json.loads((out / "raw" / "done.json").read_text())
    steps = done["steps"]
    with open(out / "raw" / "steps.csv") as f:
        rows = list(csv.DictReader(f))
    # Time stepping only: from the step-0 output row (written after reading
    # the mesh and building the bodies) to the last.
    stepping = float(rows[-1]["seconds"]) - float(rows[0]["seconds"])
    steps -= int(rows[0]["step"])  # a run from a state starts past 0
    result = {"name": name, "steps": steps, "seconds": stepping,
              "setup_seconds": float(rows[0]["seconds"]),
              "ms_per_step": 1e3 * stepping / steps,
              "factorizations": done["factorizations"],
              "peak_memory_mb": peak_kb / 1024}
    for part in PARTS:
        result[f"ms_{part}"] = 1e3 * done["seconds_by_part"][part] / steps
    return result


def bench_paper(steps: int, state: Path | None = None) -> list[dict]:
    """Per-step cost of the paper case at the paper's settings and at the
    defaults: ``steps`` steps from the initial packing, or from ``state``."""
    t0 = state_time(state) if state is not None else 0.0
    prefix = "late" if state is not None else "paper"
    results = []
    for label, overrides in (("paper-settings", PAPER), ("fast-settings", FAST)):
        config = _scaled_config(1, overrides, steps)
        config["loading"]["max_time"] = t0 + steps * config["time"]["time_step"]
        results.append(run_driver(config, _mesh_for(config, "n100"),
                                  f"{prefix}-{label}", initial_state=state))
    return results


def bench_scaling(target_phi: float) -> dict:
    """Cost per unit strain for 25, 100 and 400 disks, each compressed from
    its initial packing to the packing fraction target_phi."""
    rows = []
    for scale in (0.25, 1, 4):
        config = _scaled_config(scale, FAST, 100)
        config["loading"]["target_packing_fraction"] = target_phi
        config["loading"]["max_time"] = (config["geometry"]["length"] / 2
                                         / config["loading"]["piston_speed"])
        n = sum(config["geometry"]["counts"])
        r = run_driver(config, _mesh_for(config, f"n{n}"), f"scaling-n{n}")
        with open(WORK / f"scaling-n{n}" / "raw" / "steps.csv") as f:
            last = list(csv.DictReader(f))[-1]
        piston = config["geometry"]["length"] - float(last["piston_x"])
        strain = -math.log(1 - piston / config["geometry"]["length"])
        r.update(disks=n, strain=strain, final_phi=float(last["phi"]),
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
            sets["loading.target_packing_fraction"] = to_phi
        config = cfg.load_config(ROOT / "examples" / "paper.toml", sets)
        g, speed = config["geometry"], config["loading"]["piston_speed"]
        if max_strain is not None:
            config["loading"]["max_time"] = (
                g["length"] * (1 - math.exp(-max_strain)) / speed)
        out = WORK / f"invariance-{label}"
        if run(config, out, force=True, initial_state=state) != 0:
            raise RuntimeError(f"invariance run {label} failed")
        with open(out / "series.csv") as f:
            rows = list(csv.DictReader(f))
        series[label] = {k: [float(r[k]) if r[k] not in ("", "nan") else math.nan
                             for r in rows] for k in rows[0]}
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
           str(ROOT / "examples" / "paper.toml"), "--out", str(out), "--force",
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


def main(argv=None) -> int:
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
                        " seed-0 paper case (a run's raw/state.bin)")
    parser.add_argument("--full", action="store_true",
                        help="also run the whole paper case (the defaults)")
    parser.add_argument("--invariance", type=float, metavar="EPS",
                        help="only compare the defaults and the paper's settings"
                        " from the start to this strain")
    parser.add_argument("--invariance-from", type=Path, metavar="STATE",
                        help="only compare the defaults and the paper's settings"
                        " from this state (seed 0) to --to-phi")
    parser.add_argument("--to-phi", type=float, default=0.84,
                        help="packing fraction that ends --invariance-from")
    args = parser.parse_args(argv)
    WORK.mkdir(parents=True, exist_ok=True)
    if args.invariance or args.invariance_from:
        if args.invariance_from:
            result = bench_invariance(state=args.invariance_from,
                                      to_phi=args.to_phi)
            result["from_state"] = str(args.invariance_from)
            name = f"invariance-{args.invariance_from.stem}-to-{args.to_phi:g}.json"
        else:
            result = bench_invariance(args.invariance)
            name = "invariance.json"
        RESULTS.mkdir(parents=True, exist_ok=True)
        path = RESULTS / name
        path.write_text(json.dumps(result, indent=2) + "\n")
        print(json.dumps(result, indent=2))
        return 0
    report = {"date": datetime.datetime.now().isoformat(timespec="seconds"),
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


if __name__ == "__main__":
    sys.exit(main())
