"""``./softpack bench``'s default runs: the paper case's cost and scaling.

The per-step cost of the paper case at the paper's settings and at the
defaults (:func:`bench_paper`), the cost per unit strain of 25, 100 and
400 disks (:func:`bench_scaling`), the fast settings against the paper's
(:func:`bench_invariance`, :func:`compare_series`) and the whole paper
case through ``./softpack run`` (:func:`bench_full`); the package doc
(:mod:`softpack.bench`) says what each measures.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

from softpack.analysis.strain import approach, cumulative_strain
from softpack.bench.common import (FAST, PAPER, PAPER_TOML, PARTS, PISTON,
                                   WORK, normalised_text, run_driver,
                                   scaled_config, scene_for)
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.scene.config import load_config


def bench_paper(steps: int, state: Path | None = None) -> list[dict]:
    """Per-step cost of the paper case at the paper's settings and at the
    defaults: ``steps`` steps from the initial packing, or from ``state``."""
    prefix = "late" if state is not None else "paper"
    results = []
    for label, overrides in (("paper-settings", PAPER), ("fast-settings", FAST)):
        config = scaled_config(1, {**overrides, "stop.steps": steps,
                                   "output.every_steps": steps})
        results.append(run_driver(config, scene_for(config, "n100"),
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
        r = run_driver(config, scene_for(config, f"n{n}"), f"scaling-n{n}")
        steps = read_table(RunDirectory(WORK / f"scaling-n{n}").raw.steps_csv)
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
        status = run(config, out, force=True, initial_state=state)
        if status != 0:  # 3: finished flagged (run_flags), not comparable
            raise RuntimeError(f"invariance run {label} ended with exit"
                               f" status {status} (see {out}/run.log)")
        series[label] = {k: list(v) for k, v in
                         read_table(RunDirectory(out).series_csv).items()}
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
    done = RunDirectory(out).done()
    return {"steps": done["steps"], "seconds": done["seconds"],
            "minutes": done["seconds"] / 60, "reason": done["reason"]}


def table(report: dict) -> str:
    """A few lines for a person; times also normalised to the reference
    yardstick (the NLGS sweeps per second of the same run)."""
    yardstick = report["nlgs"].get("sweeps_per_second", float("nan"))
    lines = [f"NLGS, 2020 contacts (the yardstick): {yardstick:.0f} sweeps/s"]
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
                         f" {row['seconds']:.0f} s"
                         f" {normalised_text(row['seconds'], yardstick)},"
                         f" {row['steps']} steps,"
                         f" {row['seconds_per_unit_strain']:.0f} s per unit strain")
        lines.append(f"cost per unit strain ~ N^p: p = {s['exponent_25_400']:.2f}"
                     f" (25-400), {s['exponent_100_400']:.2f} (100-400)")
    if "full" in report:
        f = report["full"]
        lines.append(f"full paper case (defaults): {f['minutes']:.1f} min"
                     f" {normalised_text(f['seconds'], yardstick)},"
                     f" {f['steps']} steps")
    return "\n".join(lines)


