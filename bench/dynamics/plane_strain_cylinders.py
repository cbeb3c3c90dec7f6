"""Plane strain against the standing cylinders (issue 40, 14 particles).

Reads the series.csv (``./softpack run`` writes it in both dimensions;
``./softpack run --observables-only --out DIR`` for a run made before 3D
runs had one) of a 2D run of examples/small.toml and of 3D runs of
examples/cylinders3d_small.toml (any number), and prints, at a few area
fractions Phi (2D: ``phi``, the disks' area over the box's; 3D:
``phi_base``, the bottom faces' area over the box's plan), the piston's
force and the strain energy per unit height (N/m, J/m: series.csv's N and
J over the run's H, ``scene.model.thickness`` of raw/setup.json, the
cylinders' height in 3D and the 2D model's thickness; the same division in
both dimensions) and Z with the particles it counts (the same exclusion
rule in both, docs/paper/exclusion_rule.md; NaN when every particle is
excluded; 3D: ``z_without_base``, the base and lid being out of the 2D
model's plane). Force and energy between two output rows are interpolated
linearly in Phi (rows every 10 steps in 2D, 12 in 3D: ~0.003 in Phi); Z is
the first row's at or above Phi. docs/bodies_3d.md, "Plane strain against
the standing cylinders".

    /usr/bin/python3 bench/dynamics/plane_strain_cylinders.py \\
        2D=runs/ps2d "3D nu 0.49=runs/cyl3d_nu49" ... \\
        --phi 0.76 0.78 0.80 0.82 0.84 0.86

(the runs before --phi, whose values take every number after it)
"""

import argparse
import csv
import json
import math

import numpy as np


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) if r[k] != "" else math.nan
                         for r in rows]) for k in rows[0]}


def series(run):
    """Phi, F / H, E / H, Z and the particles Z counts of a run's output
    rows; a 3D run is told by its phi_base column."""
    try:
        s = read_csv(f"{run}/series.csv")
    except FileNotFoundError:
        raise SystemExit(f"{run}/series.csv missing: ./softpack run"
                         f" --observables-only --out {run}") from None
    with open(f"{run}/raw/setup.json") as f:
        height = json.load(f)["scene"]["model"]["thickness"]
    planar = "z_without_base" in s  # 3D: the base is out of the plane
    return {"phi": s["phi_base"] if planar else s["phi"],
            "force": s["piston_force"] / height,
            "energy": s["strain_energy"] / height,
            "z": s["z_without_base"] if planar else s["z"],
            "retained": s["retained_without_base"] if planar
            else s["retained"]}


def at(phi, values, target):
    """values interpolated at Phi = target on the rising part (NaN beyond
    the run's range)."""
    if not phi[0] <= target <= np.max(phi):
        return math.nan
    k = int(np.argmax(phi >= target))
    if k == 0:
        return float(values[0])
    f = (target - phi[k - 1]) / (phi[k] - phi[k - 1])
    return float(values[k - 1] + f * (values[k] - values[k - 1]))


def z_at(data, target) -> str:
    """Z of the first row at or above Phi = target, with the particles it
    counts ("-" beyond the run's range)."""
    above = np.flatnonzero(data["phi"] >= target)
    if not len(above):
        return "-"
    k = int(above[0])
    return f"{data['z'][k]:.2f} ({data['retained'][k]:.0f})"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--phi", type=float, nargs="+",
                   default=[0.72, 0.75, 0.78, 0.80, 0.82, 0.84])
    p.add_argument("runs", nargs="+", help="LABEL=DIR")
    a = p.parse_args()
    runs = [r.split("=", 1) for r in a.runs]
    data = {label: series(d) for label, d in runs}
    print("| Phi | " + " | ".join(f"F/H {l} (N/m)" for l, _ in runs) + " | "
          + " | ".join(f"E/H {l} (J/m)" for l, _ in runs) + " | "
          + " | ".join(f"Z {l} (retained)" for l, _ in runs) + " |")
    print("| ---: " * (1 + 3 * len(runs)) + "|")
    for phi in a.phi:
        f = [at(data[l]["phi"], data[l]["force"], phi) for l, _ in runs]
        e = [at(data[l]["phi"], data[l]["energy"], phi) for l, _ in runs]
        z = [z_at(data[l], phi) for l, _ in runs]
        print(f"| {phi:.2f} | " + " | ".join(f"{v:.4g}" for v in f) + " | "
              + " | ".join(f"{v:.4g}" for v in e) + " | " + " | ".join(z)
              + " |")
    for label, _ in runs:
        phi = data[label]["phi"]
        print(f"{label}: Phi {phi[0]:.4f} -> {np.max(phi):.4f}")


if __name__ == "__main__":
    main()
