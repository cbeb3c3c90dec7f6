"""``./softpack reference2d``: a nearly incompressible disk between plates,
solved by dolfinx with a stable mixed element (issue 39's reference).

The plane-strain twin of :mod:`softpack.references.cylinder3d`: the
neo-Hookean disk of diameter D (paper Eq. 1, the energy per unit thickness
of ``forms/materials/neo_hookean.py``)

    Psi(u) = mu/2 (tr C + 1 - 3) - mu ln J + lambda/2 (ln J)^2,
    lambda = 2 mu nu / (1 - 2 nu)   (the plane-strain Lame parameter),

squeezed STATICALLY between two frictionless rigid plates normal to y,
each moved by delta/2 towards the centre, eps = -ln(1 - delta/D).

Model
  * mixed (the default): Taylor–Hood, P2 displacements and a continuous P1
    pressure p, through the perturbed Lagrangian
    L(u, p) = int [mu/2 (tr C - 2) - mu ln J + p ln J - p^2 / (2 lambda)];
    its stationarity in p gives p = lambda ln J, hence Psi(u) exactly, for
    any nu < 1/2, and it does not lock as nu -> 1/2 (the inf-sup stable
    pair). ``--displacement`` solves the plain P2 displacement form instead.
  * a quarter of the disk (x >= 0, y >= 0; u_x = 0 on x = 0, u_y = 0 on
    y = 0), quadratic triangles whose mid-side nodes lie on the circle,
    refined near the contact point (:func:`build_mesh`).
  * the plate y = R - delta/2 a penalty k/2 <Y + u_y - (R - delta/2)>_+^2 per
    unit reference length of the arc, k = ``--penalty`` mu/R, Newton with
    MUMPS (:mod:`softpack.references.plate_newton`, as in 3D). Penetration
    and penalty energy are recorded.
  * f (per unit thickness, one plate) = 2 x the penalty force on the
    quarter; f_norm = f / (D mu), the normalisation of ``./softpack
    single-disk``'s ``force_2d.csv``.

Outputs in ``--out DIR``: ``force_2d_mixed_<model>.csv`` (eps, f_norm,
f_norm_sym: the same force read as the reaction on y = 0, energy_J_per_m,
penalty_energy_J_per_m) and ``run_2d_mixed_<model>.json`` (settings, mesh,
largest penetration, wall time).
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import sys
import time
from pathlib import Path

import numpy as np

from softpack.analysis import strain
from softpack.contract.tables import write_table
from softpack.references.plate_newton import (PlateSolver,
                                              QuarterUnderPlate, advance)

log = logging.getLogger("softpack.references.disk_mixed")

#: Physical curve tags of the quarter disk.
TAG_X0, TAG_Y0, TAG_ARC = 1, 2, 3


def lame_lambda(mu: float, nu: float) -> float:
    """The plane-strain Lame parameter of a Poisson ratio nu < 1/2."""
    return 2.0 * mu * nu / (1.0 - 2.0 * nu)


def build_mesh(element_size: float, comm=None):
    """A quarter of the unit disk as quadratic triangles (gmsh, OCC).

    Size ``element_size`` (in units of R) within 0.3 of the contact point
    (0, 1), growing to 4 element_size beyond 0.8 from it. Returns (mesh,
    facet_tags).
    """
    import gmsh
    from mpi4py import MPI
    from dolfinx.io import gmshio

    from softpack.scene.triangulation import initialize_gmsh

    comm = MPI.COMM_SELF if comm is None else comm
    initialize_gmsh(gmsh)
    try:
        gmsh.model.add("quarter_disk")
        disk = gmsh.model.occ.addDisk(0, 0, 0, 1.0, 1.0)
        box = gmsh.model.occ.addRectangle(0, 0, 0, 2.0, 2.0)
        gmsh.model.occ.intersect([(2, disk)], [(2, box)])
        gmsh.model.occ.synchronize()
        _tag_curves(gmsh)
        _size_field(gmsh, element_size)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        mesh, _, facets = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    return mesh, facets


def _tag_curves(gmsh):
    surfaces = [tag for _, tag in gmsh.model.getEntities(2)]
    if len(surfaces) != 1:
        raise RuntimeError(f"expected one quarter disk, got {surfaces}")
    gmsh.model.addPhysicalGroup(2, surfaces, 1)
    groups = {}
    for dim, tag in gmsh.model.getBoundary([(2, surfaces[0])],
                                           oriented=False):
        x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(dim, tag)
        if x1 - x0 < 1e-6 and abs(x0) < 1e-6:
            key = TAG_X0
        elif y1 - y0 < 1e-6 and abs(y0) < 1e-6:
            key = TAG_Y0
        else:
            key = TAG_ARC
        groups.setdefault(key, []).append(tag)
    if sorted(groups) != [TAG_X0, TAG_Y0, TAG_ARC]:
        raise RuntimeError(f"unexpected boundary of the quarter disk: {groups}")
    for key, tags in groups.items():
        gmsh.model.addPhysicalGroup(1, tags, key)


def _size_field(gmsh, h):
    """Size h near the contact point (0, 1), up to 4 h far from it."""
    fm = gmsh.model.mesh.field
    point = gmsh.model.occ.addPoint(0.0, 1.0, 0.0)
    gmsh.model.occ.synchronize()
    dist = fm.add("Distance")
    fm.setNumbers(dist, "PointsList", [point])
    thr = fm.add("Threshold")
    fm.setNumber(thr, "InField", dist)
    for key, val in (("SizeMin", h), ("SizeMax", 4 * h), ("DistMin", 0.3),
                     ("DistMax", 0.8)):
        fm.setNumber(thr, key, val)
    fm.setAsBackgroundMesh(thr)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints",
                "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + opt, 0)


class _QuarterDisk(QuarterUnderPlate):
    """The scaled static problem (lengths by R, stresses by mu): the
    interface :mod:`softpack.references.plate_newton` solves."""

    def __init__(self, mesh, facets, nu, mixed, penalty):
        import ufl
        from dolfinx import fem
        from petsc4py import PETSc

        self.mesh = mesh
        cell = mesh.ufl_cell()
        p2 = ufl.VectorElement("Lagrange", cell, 2)
        if mixed:
            p1 = ufl.FiniteElement("Lagrange", cell, 1)
            self.W = fem.FunctionSpace(mesh, ufl.MixedElement([p2, p1]))
            self.U = self.W.sub(0)
        else:
            self.W = fem.FunctionSpace(mesh, p2)
            self.U = self.W
        self.w = fem.Function(self.W)
        self.plate = fem.Constant(mesh, PETSc.ScalarType(1.0))
        self._define_forms(facets, lame_lambda(1.0, nu), mixed, penalty)
        self._locate_dofs(facets, (TAG_X0, TAG_Y0))

    def _define_forms(self, facets, lam, mixed, penalty):
        import ufl
        from dolfinx import fem

        dxq = ufl.dx(metadata={"quadrature_degree": 4})
        ds_arc = ufl.Measure("ds", domain=self.mesh, subdomain_data=facets,
                             metadata={"quadrature_degree": 6})(TAG_ARC)
        u, p = ufl.split(self.w) if mixed else (self.w, None)
        F = ufl.Identity(2) + ufl.grad(u)
        lnJ = ufl.ln(ufl.det(F))
        deviatoric = 0.5 * (ufl.tr(F.T * F) - 2) - lnJ
        psi = deviatoric + 0.5 * lam * lnJ ** 2
        overlap = ufl.max_value(
            ufl.SpatialCoordinate(self.mesh)[1] + u[1] - self.plate, 0.0)
        plate = 0.5 * penalty * overlap ** 2 * ds_arc
        if mixed:
            lagrangian = (deviatoric + p * lnJ - p ** 2 / (2 * lam)) * dxq
        else:
            lagrangian = psi * dxq
        residual = ufl.derivative(lagrangian + plate, self.w,
                                  ufl.TestFunction(self.W))
        self.energy_form = fem.form(psi * dxq)
        self.penalty_energy_form = fem.form(plate)
        self.plate_force_form = fem.form(penalty * overlap * ds_arc)
        self.residual_form = fem.form(residual)
        self.tangent_form = fem.form(
            ufl.derivative(residual, self.w, ufl.TrialFunction(self.W)))


def compress_disk(diameter=0.02, mu=0.15e6, nu=0.499, element_size=5e-4,
                  max_strain=0.2, n_steps=20, mixed=True, penalty=1e4,
                  max_halvings=5) -> dict:
    """The force curve up to eps = max_strain (uniform steps in eps).

    element_size (m) near the contact point; penalty in mu/R. Returns a
    dict of lists (eps, delta, f_norm, f_norm_sym, energy, penalty_energy)
    and the run's settings; raises RuntimeError if a step fails after
    max_halvings halvings.
    """
    from dolfinx import fem

    start = time.perf_counter()
    R = 0.5 * diameter
    mesh, facets = build_mesh(element_size / R)
    prob = _QuarterDisk(mesh, facets, nu, mixed, penalty)
    solver = PlateSolver(prob)
    out = {"eps": [0.0], "delta": [0.0], "f_norm": [0.0],
           "f_norm_sym": [0.0], "energy": [0.0], "penalty_energy": [0.0],
           "newton_its": [0]}
    overlap = 0.0
    for eps in np.linspace(0.0, max_strain, n_steps + 1)[1:]:
        dhat = float(strain.approach(eps, diameter)) / R
        its = advance(prob, solver, out["delta"][-1] / R, dhat, max_halvings)
        f_plate, f_sym = solver.reactions()
        # the quarter carries half of a plate's force; scaled force mu R
        out["eps"].append(float(eps))
        out["delta"].append(dhat * R)
        out["f_norm"].append(2 * f_plate * R / diameter)
        out["f_norm_sym"].append(2 * f_sym * R / diameter)
        out["energy"].append(
            4 * fem.assemble_scalar(prob.energy_form) * mu * R ** 2)
        out["penalty_energy"].append(
            4 * fem.assemble_scalar(prob.penalty_energy_form) * mu * R ** 2)
        out["newton_its"].append(its)
        overlap = max(overlap, prob.max_overlap() * R)
        log.info("nu=%s %s eps=%.3f f_norm=%.5f (y=0: %.5f) newton=%d",
                 nu, "mixed" if mixed else "P2", eps, out["f_norm"][-1],
                 out["f_norm_sym"][-1], its)
    out.update(diameter=diameter, mu=mu, nu=nu, mixed=mixed,
               element_size=element_size, penalty=penalty,
               num_cells=prob.num_cells, num_dofs=int(prob.w.x.array.size),
               max_overlap=overlap, seconds=time.perf_counter() - start)
    return out


def p1_curve(mesh_h5, mu=0.15e6, nu=0.499, nodal_pressure=False,
             max_strain=0.2, n_steps=20, diameter=0.02) -> dict:
    """The static P1 disk on a softpack mesh (``sim/mesh/disk.h5`` of a
    ``./softpack single-disk`` run), the plates at its extreme nodes: the
    element's own volumetric energy (what the driver does today, which
    locks) or the averaged nodal pressure (:mod:`.nodal_pressure`)."""
    from softpack.analysis.fields import read_mesh
    from softpack.references.nodal_pressure import NodalPressureReference
    from softpack.references.plates_reference import static_reference

    start = time.perf_counter()
    points, cells = read_mesh(mesh_h5)
    y = np.asarray(points)[:, 1]
    curve = static_reference(
        points, cells, mu, lame_lambda(mu, nu), float(y.min()),
        float(y.max()), diameter, max_strain, n_steps,
        model=NodalPressureReference if nodal_pressure else None)
    return {"eps": list(curve["eps"]), "f_norm": list(curve["f_norm"]),
            "f_norm_sym": list(curve["f_norm_top"]),
            "energy": list(curve["energy"]),
            "penalty_energy": [math.nan] * len(curve["eps"]),
            "diameter": diameter, "mu": mu, "nu": nu,
            "model": "p1_nodal_pressure" if nodal_pressure else "p1",
            "mesh": str(mesh_h5), "triangles": int(len(cells)),
            "seconds": time.perf_counter() - start}


def model_name(nu: float, mixed: bool) -> str:
    """``nu0499_mixed``, ``nu0333_p2``, ..."""
    digits = f"{nu:.4f}".replace("0.", "").rstrip("0") or "0"
    return f"nu0{digits}_{'mixed' if mixed else 'p2'}"


def write_outputs(result: dict, out_dir) -> Path:
    """The force CSV and the run's JSON; returns the CSV's path."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if "model" in result:   # a P1 curve on a softpack mesh
        name = model_name(result["nu"], True).replace(
            "mixed", result["model"])
        csv = out / f"force_2d_{name}.csv"
    else:
        name = model_name(result["nu"], result["mixed"])
        csv = out / f"force_2d_mixed_{name}.csv"
    write_table(csv, {"eps": result["eps"], "f_norm": result["f_norm"],
                      "f_norm_sym": result["f_norm_sym"],
                      "energy_J_per_m": result["energy"],
                      "penalty_energy_J_per_m": result["penalty_energy"]})
    settings = {k: v for k, v in result.items() if not isinstance(v, list)}
    (out / csv.name.replace("force_", "run_").replace(".csv", ".json")).write_text(
        json.dumps(settings, indent=2) + "\n")
    return csv


def main(argv=None) -> int:
    from softpack.cli import positive_float, positive_int

    parser = argparse.ArgumentParser(prog="softpack reference2d",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--nu", type=float, default=0.499,
                        help="plane-strain Poisson ratio, < 1/2 (default"
                        " 0.499)")
    parser.add_argument("--displacement", action="store_true",
                        help="plain P2 displacements instead of Taylor-Hood")
    parser.add_argument("--element-size", type=positive_float, default=5e-4,
                        help="triangle size near the contact point, m"
                        " (default 5e-4; 4x far from it)")
    parser.add_argument("--max-strain", type=positive_float, default=0.2)
    parser.add_argument("--steps", type=positive_int, default=20)
    parser.add_argument("--penalty", type=positive_float, default=1e4,
                        help="plate stiffness in mu/R (default 1e4)")
    parser.add_argument("--diameter", type=positive_float, default=0.02)
    parser.add_argument("--mu", type=positive_float, default=0.15e6)
    parser.add_argument("--p1-mesh", type=Path, metavar="H5",
                        help="instead: the static P1 disk on this softpack"
                        " mesh (a single-disk run's sim/mesh/disk.h5)")
    parser.add_argument("--nodal-pressure", action="store_true",
                        help="with --p1-mesh: the averaged nodal pressure"
                        " (softpack.references.nodal_pressure)")
    args = parser.parse_args(argv)
    if args.nodal_pressure and args.p1_mesh is None:
        parser.error("--nodal-pressure needs --p1-mesh")
    if args.p1_mesh is not None and not args.p1_mesh.is_file():
        parser.error(f"--p1-mesh {args.p1_mesh}: no such file")
    if not 0.0 <= args.nu < 0.5:
        parser.error(f"--nu {args.nu}: must be in [0, 0.5)")
    if not log.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("%(asctime)s %(message)s",
                                               "%H:%M:%S"))
        log.addHandler(handler)
    log.setLevel(logging.INFO)
    log.propagate = False
    logging.getLogger().setLevel(logging.WARNING)   # FFCx/cffi JIT chatter
    if args.p1_mesh is not None:
        result = p1_curve(args.p1_mesh, args.mu, args.nu, args.nodal_pressure,
                          args.max_strain, args.steps, args.diameter)
        csv = write_outputs(result, args.out)
        log.info("%s on %d triangles, %.0f s; wrote %s", result["model"],
                 result["triangles"], result["seconds"], csv)
        return 0
    result = compress_disk(args.diameter, args.mu, args.nu, args.element_size,
                           args.max_strain, args.steps,
                           not args.displacement, args.penalty)
    csv = write_outputs(result, args.out)
    log.info("%d cells, %d dofs, %.0f s, largest penetration %.2e m; wrote"
             " %s", result["num_cells"], result["num_dofs"],
             result["seconds"], result["max_overlap"], csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
