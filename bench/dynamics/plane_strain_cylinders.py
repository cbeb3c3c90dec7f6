"""Plane strain against the standing cylinders (issue 40, 14 particles).

Reads the raw/steps.csv of a 2D run of examples/small.toml and of 3D runs
of examples/cylinders3d_small.toml (any number), and prints, at a few area
fractions Phi (2D: ``phi``, the disks' area over the box's; 3D:
``phi_base``, the bottom faces' area over the box's plan), the piston's
force and the strain energy per unit height: 2D as written (N/m, J/m), 3D
divided by the cylinders' height H (N / H, J / H). Values between two
output rows are interpolated linearly in Phi (rows every 10 steps in 2D,
12 in 3D: ~0.003 in Phi). docs/bodies_3d.md, "Plane strain against the
standing cylinders".

    /usr/bin/python3 bench/dynamics/plane_strain_cylinders.py \\
        2D=runs/ps2d "3D nu 0.49=runs/cyl3d_nu49" ... \\
        --height 0.015 --phi 0.76 0.78 0.80 0.82 0.84 0.86

(the runs before --phi, whose values take every number after it)
"""

import argparse
import csv
import math

import numpy as np


def read_steps(run):
    with open(f"{run}/raw/steps.csv") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) if r[k] != "" else math.nan
                         for r in rows]) for k in rows[0]}


def series(run, height):
    """(Phi, piston force per unit height, strain energy per unit height)
    of a run's output rows; a 3D run is told by its phi_base column."""
    s = read_steps(run)
    if "phi_base" in s:
        return s["phi_base"], s["right_fx"] / height, \
            s["strain_energy"] / height
    return s["phi"], s["right_fx"], s["strain_energy"]


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


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--height", type=float, default=0.015)
    p.add_argument("--phi", type=float, nargs="+",
                   default=[0.72, 0.75, 0.78, 0.80, 0.82, 0.84])
    p.add_argument("runs", nargs="+", help="LABEL=DIR")
    a = p.parse_args()
    runs = [r.split("=", 1) for r in a.runs]
    data = {label: series(d, a.height) for label, d in runs}
    print("| Phi | " + " | ".join(f"F/H {l} (N/m)" for l, _ in runs) + " | "
          + " | ".join(f"E/H {l} (J/m)" for l, _ in runs) + " |")
    print("| ---: " * (1 + 2 * len(runs)) + "|")
    for phi in a.phi:
        f = [at(data[l][0], data[l][1], phi) for l, _ in runs]
        e = [at(data[l][0], data[l][2], phi) for l, _ in runs]
        print(f"| {phi:.2f} | " + " | ".join(f"{v:.4g}" for v in f) + " | "
              + " | ".join(f"{v:.4g}" for v in e) + " |")
    for label, _ in runs:
        phi = data[label][0]
        print(f"{label}: Phi {phi[0]:.4f} -> {np.max(phi):.4f}")


if __name__ == "__main__":
    main()
