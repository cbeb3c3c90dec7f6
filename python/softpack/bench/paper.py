"""``./softpack bench``'s default runs: the paper case's cost and scaling.

The per-step cost of the paper case at the paper's settings and at the
defaults (:func:`bench_paper`), the cost per unit strain of 25, 100 and
400 disks (:func:`bench_scaling`) and the whole paper case through
``./softpack run`` (:func:`bench_full`); the package doc
(:mod:`softpack.bench`) says what each measures. The defaults' accuracy
against a reference: :mod:`softpack.bench.invariance`.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

from softpack.analysis.strain import cumulative_strain
from softpack.bench.common import (FAST, PAPER, PAPER_TOML, PARTS, PISTON,
                                   WORK, normalised_text, run_driver,
                                   scaled_config, scene_for)
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table


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
        if row.get("bench") in ("detection", "detection_periodic"):
            cell = " (periodic)" if row["bench"] != "detection" else ""
            lines.append(f"detection, {row['bodies']:5d} bodies:"
                         f" {1e3 * row['seconds']:8.2f} ms{cell}")
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


