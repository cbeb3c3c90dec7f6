"""``./softpack single-disk --shape square|pentagon``: one rounded polygon
between two rigid plates, softpack against an independent dolfinx solve.

The shape check of issue 13: one soft regular polygon with rounded corners
(a square with two faces on the plates, or a pentagon with a vertex up and
a face down) squeezed between two rigid plates normal to y, computed twice
on the SAME mesh:

softpack (``sim/``)
    the production pipeline exactly as :mod:`softpack.references.single_disk`
    runs it (its module doc lists the overrides): a configuration without a
    box, ``[[species]]`` one ``shape = "polygon"`` (``sides``,
    ``corner_radius``, ``orientation = "fixed"``, ``angle``) of equal-area
    diameter D, meshed by :mod:`softpack.scene.shapes`, both plates starting
    at the mesh's extreme nodes and moving towards each other at
    ``--speed`` each, Moreau–Jean + NLGS node-to-wall contact, friction
    0.01 on the plates, Rayleigh alpha = 200 1/s, theta = 0.5, time step
    1e-4 s, every other setting the production default.

dolfinx reference (:func:`.plates_reference.static_reference`)
    the same triangles read back from the run's mesh file, the same
    plane-strain neo-Hookean energy written out here (paper Eq. 1:
    Psi = mu/2 (tr C + 1 - 3) - mu ln J + lambda/2 (ln J)^2, with mu and
    lambda from the run's configuration), P1 displacements, solved STATICALLY
    (no mass, no damping, no time) by Newton at prescribed plate positions
    (``--reference-steps`` equal increments of eps, halved on failure).
    Contact: a NODAL PENALTY of the boundary nodes against the two plates,
    frictionless, the energy sum_i k l_i <g_i>_+^2 / 2 over the boundary
    nodes i (l_i half the length of its two boundary edges, g_i its
    penetration of a plate), with k = ``--penalty`` mu / D. It is node-to-
    plate like softpack's constraint (same discrete contact kinematics, so
    that the two differ only by how the contact problem is solved) but
    shares no code with it: no Delassus operator, no NLGS, no time
    stepping. Its error is the penetration it allows, g ~ p / k (p the
    contact pressure), ~ 1e-5 (p / mu) D at the default k = 1e5 mu / D;
    it lowers the force by a relative 1.2e-4 to 1.7e-4 on an exactly
    solvable homogeneous compression (tests/python/test_plates.py; the
    error is proportional to 1/k: 1.2e-3 at k = 1e4 mu / D, 1.2e-5 at
    1e6); the penetration is ``max_penetration_over_D`` in the output and
    ``--penalty`` changes k. The x translation, a zero-energy mode between
    frictionless plates, is removed by fixing u_x at the node nearest the
    centroid; its reaction is reported (the shape and the load are mirror-
    symmetric about x = 0, only the mesh is not).

Both give eps = -ln(1 - delta/H0) (H0 the initial height, the distance
between the plates at first contact, delta their approach) and
f_norm = f / (H0 mu), f the mean force of the two plates per unit length
(for a disk H0 = D: the single-disk normalisation).

Outputs in ``--out DIR``: ``force_softpack.csv`` (``eps,f_norm`` per driver
output), ``force_dolfinx.csv`` (``eps,f_norm,f_norm_top,f_norm_bottom,
newton_iterations,max_penetration_over_D,pin_reaction_over_f``),
``plates.json`` (parameters, mesh, the comparison at the reference
strains, the softpack run's plate mismatch, rotation and energies),
``sim/`` (the softpack run directory).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table
from softpack.references import between_plates
from softpack.references.plates_reference import (boundary_weights,
                                                  static_reference)
from softpack.scene.config import validate

#: shape name -> (sides, angle): the orientation of the polygon between the
#: plates (at angle 0 a vertex points along +y, docs/parameters.md).
SHAPES = {"square": (4, math.pi / 4), "pentagon": (5, 0.0)}
#: Strains at which plates.json compares the two computations.
COMPARE_STRAINS = (0.01, 0.02, 0.05, 0.10, 0.15, 0.20)
SOURCE = "plates"


@dataclass
class Params:
    """The protocol's settings (SI units); the rest is the production
    default (module doc)."""

    shape: str = "pentagon"
    diameter: float = 0.020          # equal-area diameter D
    corner_radius: float = 2.0e-3
    element_size: float = 1.0e-3
    max_strain: float = 0.20
    speed: float = 0.01
    time_step: float = 1e-4
    alpha: float = 200.0
    theta: float = 0.5
    friction: float = 1e-2
    every: int = 10
    reference_steps: int = 40        # dolfinx: equal steps in eps
    penalty: float = 1e5             # dolfinx: k = penalty mu / D

    @property
    def sides(self) -> int:
        return SHAPES[self.shape][0]

    @property
    def angle(self) -> float:
        return SHAPES[self.shape][1]


# ---------------------------------------------------------------- softpack

def config_data(params: Params, y_bottom: float, y_top: float,
                height: float) -> dict:
    """single_disk's overrides with a polygon instead of the disk; the stop
    time is that of the approach delta_max = H0 (1 - exp(-max_strain))."""
    data = between_plates.config_data(between_plates.Params(
        diameter=params.diameter, element_size=params.element_size,
        max_strain=params.max_strain, speed=params.speed,
        time_step=params.time_step, alpha=params.alpha, theta=params.theta,
        friction=params.friction, every=params.every), y_bottom, y_top)
    data["species"] = [{"name": params.shape, "shape": "polygon",
                        "sides": params.sides,
                        "corner_radius": params.corner_radius,
                        "diameter": params.diameter, "count": 1,
                        "orientation": "fixed", "angle": params.angle}]
    approach = height * (1 - math.exp(-params.max_strain))
    data["stop"]["max_time"] = (approach / (2 * params.speed)
                                + 2 * params.every * params.time_step)
    return data


def plates_config(params: Params, y_bottom=None, y_top=None, height=None):
    """The validated configuration (plates at +-D/2 unless given)."""
    if y_bottom is None:
        y_bottom, y_top = -params.diameter / 2, params.diameter / 2
    height = height or (y_top - y_bottom)
    return validate(config_data(params, y_bottom, y_top, height), SOURCE)


def simulate(params: Params, sim_dir) -> dict:
    """Scene, driver.json and softpack-simulate in ``sim_dir``
    (:func:`softpack.references.between_plates.simulate`)."""
    return between_plates.simulate(plates_config, params, sim_dir, "body")


def softpack_curve(steps, meta) -> dict:
    """eps and f_norm = f/(H0 mu) of the driver's plates
    (:func:`~softpack.references.between_plates.force_curve` with
    D -> H0)."""
    height = meta["y_top0"] - meta["y_bottom0"]
    mu = meta["config"]["material"]["parameters"]["shear_modulus"]
    return between_plates.force_curve(steps, height, meta["y_bottom0"],
                                      meta["y_top0"], mu)


# ---------------------------------------------------------------- run

def run(params: Params, out_dir) -> dict:
    """Both computations; writes the CSVs and plates.json (module doc)."""
    from softpack.analysis.fields import read_mesh
    from softpack.references.p1_fields import rigid_rotation

    out_dir = Path(out_dir)
    sim = RunDirectory(out_dir / "sim")
    meta = simulate(params, sim.path)
    steps = read_table(sim.raw.steps_csv)
    curve = softpack_curve(steps, meta)
    material = meta["config"]["material"]["parameters"]
    points, cells = read_mesh(meta["mesh_h5"])
    started = time.time()
    ref = static_reference(points, cells, material["shear_modulus"],
                           material["lame_lambda"], meta["y_bottom0"],
                           meta["y_top0"], params.diameter,
                           params.max_strain, params.reference_steps,
                           params.penalty)
    reference_seconds = time.time() - started
    keep = curve["eps"] <= params.max_strain + 0.002
    write_table(out_dir / "force_softpack.csv",
                {"eps": curve["eps"][keep], "f_norm": curve["f_norm"][keep]})
    write_table(out_dir / "force_dolfinx.csv",
                {k: v for k, v in ref.items() if k != "energy"})
    x, fcells, snaps = between_plates.read_fields(sim.fields_h5)
    rotation = max(abs(rigid_rotation(x, fcells, u)) for _, u in snaps)
    comparison = compare(curve, ref, params.max_strain)
    loaded = curve["f_norm"] > 0
    mismatch = np.abs(curve["f_norm_top"] - curve["f_norm_bottom"])[loaded]
    doc = {"params": asdict(params),
           "mesh": {"triangles": meta["triangles"], "nodes": meta["nodes"],
                    "boundary_nodes": int(len(ref_boundary(points, cells)))},
           "height_H0_m": meta["y_top0"] - meta["y_bottom0"],
           "plates_initial_y": [meta["y_bottom0"], meta["y_top0"]],
           "comparison": comparison,
           "softpack": {
               "steps": int(steps["step"][-1]),
               "driver_seconds": round(meta["driver_seconds"], 1),
               "max_plate_force_mismatch_f_norm": float(mismatch.max()),
               "max_rigid_rotation_rad": float(rotation),
               "max_penetration_m": float(np.nanmax(
                   steps["max_penetration"]))},
           "dolfinx": {
               "seconds": round(reference_seconds, 1),
               "max_penetration_over_D": float(
                   ref["max_penetration_over_D"].max()),
               "max_pin_reaction_over_f": float(
                   ref["pin_reaction_over_f"][1:].max()),
               "max_newton_iterations": int(ref["newton_iterations"].max())},
           "eps": "-ln(1 - delta/H0), delta the plates' approach, H0 the"
                  " initial height", "f_norm": "mean plate force per unit"
                  " length / (H0 mu)"}
    (out_dir / "plates.json").write_text(json.dumps(doc, indent=1) + "\n")
    return {"curve": curve, "reference": ref, "doc": doc}


def ref_boundary(points, cells):
    return boundary_weights(points, cells)[0]


def compare(curve, ref, max_strain) -> dict:
    """softpack / dolfinx - 1 at COMPARE_STRAINS and its largest magnitude
    over the reference's strains from 0.02 on (softpack interpolated
    linearly between its outputs)."""
    at = {f"{e:g}": {"softpack": float(np.interp(e, curve["eps"],
                                                  curve["f_norm"])),
                     "dolfinx": float(np.interp(e, ref["eps"],
                                                ref["f_norm"]))}
          for e in COMPARE_STRAINS if e <= max_strain + 1e-12}
    for row in at.values():
        row["relative_difference"] = row["softpack"] / row["dolfinx"] - 1
    sel = ref["eps"] >= 0.02 - 1e-12
    diff = np.interp(ref["eps"][sel], curve["eps"], curve["f_norm"]) \
        / ref["f_norm"][sel] - 1
    return {"at": at, "max_abs_relative_difference_from_0.02":
            float(np.abs(diff).max()) if diff.size else None}


# ---------------------------------------------------------------- refinement

def refinement(directories, strains=(0.02, 0.05, 0.10, 0.15, 0.20)) -> list:
    """Rows (shape, h, eps, softpack, dolfinx, difference) of several
    ``run`` output directories, and per shape and strain the estimated
    discretization error of each mesh, for softpack and dolfinx separately.

    ``vs_finest_*``: f_h / f_finest - 1, the change to the finest mesh
    given (an estimate of f_h's discretization error when the finest is
    converged). ``error_*``, ``order_*``: with three or more meshes
    halving h, Richardson's limit from the three finest, f_0 = f_3 +
    (f_3 - f_2) / (2^p - 1), observed order p = log2((f_1 - f_2) /
    (f_2 - f_3)), and f_h / f_0 - 1; NaN when the two differences have
    opposite signs (no asymptotic convergence visible).
    """
    runs = []
    for d in map(Path, directories):
        doc = json.loads((d / "plates.json").read_text())
        runs.append((doc["params"]["shape"], doc["params"]["element_size"],
                     read_table(d / "force_softpack.csv"),
                     read_table(d / "force_dolfinx.csv"), doc))
    rows = []
    for shape in sorted({r[0] for r in runs}):
        mine = sorted((r for r in runs if r[0] == shape), key=lambda r: -r[1])
        reached = min(min(sp["eps"].max(), dx["eps"].max())
                      for _, _, sp, dx, _ in mine)
        for eps in (e for e in strains if e <= reached + 1e-9):
            values = {"softpack": [], "dolfinx": []}
            for _, h, sp, dx, doc in mine:
                values["softpack"].append(float(np.interp(eps, sp["eps"],
                                                          sp["f_norm"])))
                values["dolfinx"].append(float(np.interp(eps, dx["eps"],
                                                         dx["f_norm"])))
            limits = {k: _richardson(v[-3:]) for k, v in values.items()}
            for i, (_, h, _, _, doc) in enumerate(mine):
                row = {"shape": shape, "element_size": h, "eps": eps,
                       "triangles": doc["mesh"]["triangles"],
                       "height_H0": doc["height_H0_m"]}
                for k in ("softpack", "dolfinx"):
                    row[k] = values[k][i]
                    limit, order = limits[k]
                    row[f"error_{k}"] = (values[k][i] / limit - 1
                                         if limit else float("nan"))
                    row[f"order_{k}"] = order
                    row[f"vs_finest_{k}"] = values[k][i] / values[k][-1] - 1
                row["difference"] = row["softpack"] / row["dolfinx"] - 1
                rows.append(row)
    return rows


def _richardson(values):
    """(limit, observed order) of three values on halved meshes, or
    (None, nan)."""
    if len(values) != 3:
        return None, float("nan")
    d1, d2 = values[0] - values[1], values[1] - values[2]
    if d1 == 0 or d2 == 0 or d1 * d2 < 0:
        return None, float("nan")
    order = math.log2(d1 / d2)
    return values[2] + d2 / (2 ** order - 1), order


def _parser():
    from softpack import cli

    d = Params()
    p = argparse.ArgumentParser(
        prog="softpack single-disk --shape square|pentagon",
        description="One rounded polygon between two rigid plates: softpack"
        " against a static dolfinx computation of the same mesh (writes"
        " DIR/force_softpack.csv, force_dolfinx.csv, plates.json).")
    p.add_argument("--shape", choices=sorted(SHAPES), default=d.shape)
    p.add_argument("--corner-radius", type=cli.nonnegative_float,
                   default=d.corner_radius,
                   help=f"corner radius (m, default {d.corner_radius:g})")
    between_plates.add_plate_arguments(p, d, Path("runs/plates"))
    p.add_argument("--reference-steps", type=cli.positive_int,
                   default=d.reference_steps,
                   help="dolfinx: equal steps in eps (default 40)")
    p.add_argument("--penalty", type=cli.positive_float, default=d.penalty,
                   help="dolfinx: plate stiffness k in mu/D (default 1e5)")
    return p


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    params = Params(**{k: v for k, v in vars(args).items() if k != "out"})
    if between_plates.refused(params, plates_config, args.out):
        return 2
    print(f"softpack single-disk: {params.shape}, D = {params.diameter:g} m,"
          f" corner radius {params.corner_radius:g} m, h ="
          f" {params.element_size:g} m, up to eps = {params.max_strain:g}"
          f" -> {args.out}", flush=True)
    try:
        result = run(params, args.out)
    except RuntimeError as err:  # RunError, SingleDiskError, dolfinx's
        print(f"softpack single-disk: {err}", file=sys.stderr)
        return 1
    doc = result["doc"]
    for e, row in doc["comparison"]["at"].items():
        print(f"  eps = {e}: f_norm softpack {row['softpack']:.5g}, dolfinx"
              f" {row['dolfinx']:.5g} ({100 * row['relative_difference']:+.2f}"
              " %)")
    print(f"softpack single-disk: {doc['mesh']['triangles']} triangles;"
          f" wrote {args.out}/force_softpack.csv, force_dolfinx.csv,"
          " plates.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
