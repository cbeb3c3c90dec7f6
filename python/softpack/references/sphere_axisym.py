"""``./softpack reference-sphere``: the neo-Hookean sphere between two rigid
frictionless plates, axisymmetric, solved by dolfinx (issue 40's reference).

The continuum answer the 3D step's Hertz check (``Hertz3D`` in
``tests/cpp/dynamics3d``) converges to, free of its linear tetrahedra:

  * law (METHOD.md §2, the 3D law of ``forms/materials/neo_hookean.py``):
    Psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2, default lambda = 2 mu
    (nu = 1/3, the 3D test's material).
  * axisymmetric about the loading axis y: the meridian quarter r >= 0,
    y >= 0 (u_r = 0 on the axis r = 0, u_y = 0 on the equator y = 0),
    F = [[1 + du_r/dr, du_r/dy, 0], [du_y/dr, 1 + du_y/dy, 0],
    [0, 0, 1 + u_r/r]], every integral weighted by 2 pi r. Quadratic
    triangles (P2; their mid-side nodes on the circle), ``--element-size``
    within ``--fine-radius`` of the pole (0, R), growing to 0.05 R.
  * the plate y = R - closure/2: a penalty k/2 <Y + u_y - plate>_+^2 per unit
    reference area, k = ``--penalty`` mu/R; Newton with MUMPS
    (:mod:`softpack.references.plate_newton`, as the other references). The
    force is the penalty force (one plate, the whole sphere) and, as a
    check, the reaction summed over the equator's nodes.
  * the strain is eps = closure / D (the C++ test's), not the log strain.

Against Hertz (K. L. Johnson, Contact Mechanics, 1985, eq. 4.22-4.23):
F = (4/3) E* sqrt(R) delta^(3/2), delta = closure/2 at each plate,
E* = E / (1 - nu^2). Outputs in ``--out DIR``: ``force_sphere_<tag>.csv``
(eps, closure_m, force_N, force_sym_N, hertz_N, error_vs_hertz, a_m: the
contact radius, penetration_m) and ``run_sphere_<tag>.json``.
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

from softpack.contract.tables import write_table
from softpack.references.plate_newton import (PlateSolver,
                                              QuarterUnderPlate, advance)

log = logging.getLogger("softpack.references.sphere_axisym")

#: Physical curve tags of the meridian quarter (as disk_mixed's).
TAG_AXIS, TAG_EQUATOR, TAG_ARC = 1, 2, 3

#: The strains of the Hertz check
HERTZ_STRAINS = (0.0025, 0.005, 0.0075, 0.01, 0.015, 0.02)


def hertz_force(closure, diameter, mu, lam):
    """Hertz's force (N) at each plate for the plates' closure (m)."""
    E = mu * (3 * lam + 2 * mu) / (lam + mu)
    nu = lam / (2 * (lam + mu))
    e_star = E / (1 - nu * nu)
    delta = 0.5 * np.asarray(closure, dtype=float)
    return 4.0 / 3.0 * e_star * math.sqrt(0.5 * diameter) * delta ** 1.5


def build_mesh(element_size, fine_radius, comm=None):
    """The meridian quarter of the unit sphere, quadratic triangles (gmsh).

    ``element_size`` (units of R) within ``fine_radius`` of the pole (0, 1),
    growing linearly to 0.05 at 2 fine_radius + 0.2 from it.
    """
    import gmsh
    from mpi4py import MPI
    from dolfinx.io import gmshio

    from softpack.references.disk_mixed import _tag_curves
    from softpack.scene.triangulation import initialize_gmsh

    comm = MPI.COMM_SELF if comm is None else comm
    initialize_gmsh(gmsh)
    try:
        gmsh.model.add("sphere_meridian")
        disk = gmsh.model.occ.addDisk(0, 0, 0, 1.0, 1.0)
        box = gmsh.model.occ.addRectangle(0, 0, 0, 2.0, 2.0)
        gmsh.model.occ.intersect([(2, disk)], [(2, box)])
        gmsh.model.occ.synchronize()
        _tag_curves(gmsh)
        fm = gmsh.model.mesh.field
        pole = gmsh.model.occ.addPoint(0.0, 1.0, 0.0)
        gmsh.model.occ.synchronize()
        dist = fm.add("Distance")
        fm.setNumbers(dist, "PointsList", [pole])
        thr = fm.add("Threshold")
        fm.setNumber(thr, "InField", dist)
        for key, val in (("SizeMin", element_size),
                         ("SizeMax", max(0.05, element_size)),
                         ("DistMin", fine_radius),
                         ("DistMax", 2 * fine_radius + 0.2)):
            fm.setNumber(thr, key, val)
        fm.setAsBackgroundMesh(thr)
        for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints",
                    "MeshSizeFromCurvature"):
            gmsh.option.setNumber("Mesh." + opt, 0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        mesh, _, facets = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    return mesh, facets


class _MeridianQuarter(QuarterUnderPlate):
    """The scaled problem (lengths by R, stresses by mu) in the interface of
    :mod:`softpack.references.plate_newton` (y is the loading axis)."""

    def __init__(self, mesh, facets, lam, penalty):
        import ufl
        from dolfinx import fem
        from petsc4py import PETSc

        self.mesh = mesh
        self.W = fem.FunctionSpace(mesh, ufl.VectorElement(
            "Lagrange", mesh.ufl_cell(), 2))
        self.U = self.W
        self.w = fem.Function(self.W)
        self.plate = fem.Constant(mesh, PETSc.ScalarType(1.0))
        self._define_forms(facets, lam, penalty)
        self._locate_dofs(facets, (TAG_AXIS, TAG_EQUATOR))

    def _define_forms(self, facets, lam, penalty):
        import ufl
        from dolfinx import fem

        x = ufl.SpatialCoordinate(self.mesh)
        r, u = x[0], self.w
        weight = 2 * math.pi * r
        dxq = ufl.dx(metadata={"quadrature_degree": 4})
        ds_arc = ufl.Measure("ds", domain=self.mesh, subdomain_data=facets,
                             metadata={"quadrature_degree": 6})(TAG_ARC)
        F = ufl.as_matrix([[1 + u[0].dx(0), u[0].dx(1), 0],
                           [u[1].dx(0), 1 + u[1].dx(1), 0],
                           [0, 0, 1 + u[0] / r]])
        lnJ = ufl.ln(ufl.det(F))
        psi = 0.5 * (ufl.tr(F.T * F) - 3) - lnJ + 0.5 * lam * lnJ ** 2
        overlap = ufl.max_value(x[1] + u[1] - self.plate, 0.0)
        plate = 0.5 * penalty * overlap ** 2 * weight * ds_arc
        residual = ufl.derivative(psi * weight * dxq + plate, self.w,
                                  ufl.TestFunction(self.W))
        self.energy_form = fem.form(psi * weight * dxq)
        self.penalty_energy_form = fem.form(plate)
        self.plate_force_form = fem.form(penalty * overlap * weight * ds_arc)
        contact = ufl.conditional(ufl.gt(overlap, 0.0), 1.0, 0.0)
        self.contact_area_form = fem.form(contact * weight * ds_arc)
        self.residual_form = fem.form(residual)
        self.tangent_form = fem.form(
            ufl.derivative(residual, self.w, ufl.TrialFunction(self.W)))

    def contact_radius(self) -> float:
        """The radius of the pressed disk (scaled): from its reference area
        (the reference and current areas differ at large strain)."""
        from dolfinx import fem
        area = fem.assemble_scalar(self.contact_area_form)
        # the reference cap of area A has the base radius sqrt(A (1 - A / 4 pi) / pi)
        return math.sqrt(max(0.0, area * (1 - area / (4 * math.pi)) / math.pi))


def strain_schedule(max_strain, step):
    """The Hertz strains, then steps of ``step`` up to ``max_strain``."""
    eps = [e for e in HERTZ_STRAINS if e <= max_strain + 1e-12]
    eps += list(np.arange(0.03, max_strain + 1e-9, step))
    return sorted(set(round(e, 10) for e in eps))


def compress_sphere(diameter=0.02, mu=0.15e6, lam=0.3e6, element_size=5e-5,
                    fine_radius=0.25, penalty=1e5, max_strain=0.02,
                    step=0.01, max_halvings=6) -> dict:
    """The force at each strain of :func:`strain_schedule`.

    element_size in m, fine_radius in units of R, penalty in mu/R.
    """
    from dolfinx import fem

    start = time.perf_counter()
    R = 0.5 * diameter
    mesh, facets = build_mesh(element_size / R, fine_radius)
    prob = _MeridianQuarter(mesh, facets, lam / mu, penalty)
    solver = PlateSolver(prob)
    keys = ("eps", "closure_m", "force_N", "force_sym_N", "hertz_N",
            "error_vs_hertz", "a_m", "penetration_m", "energy_J",
            "penalty_energy_J", "newton_its")
    out = {k: [] for k in keys}
    dhat = 0.0
    for eps in strain_schedule(max_strain, step):
        # the plate at y = 1 - dhat/2: dhat is the scaled closure
        new = 2 * eps
        its = advance(prob, solver, dhat, new, max_halvings)
        dhat = new
        f_plate, f_sym = solver.reactions()
        closure = eps * diameter
        force = f_plate * mu * R ** 2
        hertz = float(hertz_force(closure, diameter, mu, lam))
        row = (eps, closure, force, f_sym * mu * R ** 2, hertz,
               force / hertz - 1, prob.contact_radius() * R,
               prob.max_overlap() * R,
               2 * fem.assemble_scalar(prob.energy_form) * mu * R ** 3,
               2 * fem.assemble_scalar(prob.penalty_energy_form) * mu * R ** 3,
               its)
        for k, v in zip(keys, row):
            out[k].append(float(v) if k != "newton_its" else int(v))
        log.info("eps=%.4f F=%.6g N (equator %.6g) Hertz %+.3f %% a/R=%.4f"
                 " penetration/closure %.1e newton %d", eps, force,
                 out["force_sym_N"][-1], 100 * (force / hertz - 1),
                 out["a_m"][-1] / R, out["penetration_m"][-1] / closure, its)
    out.update(diameter=diameter, mu=mu, lame_lambda=lam,
               element_size=element_size, fine_radius=fine_radius,
               penalty=penalty, num_cells=prob.num_cells,
               num_dofs=int(prob.w.x.array.size),
               seconds=time.perf_counter() - start)
    return out


def write_outputs(result: dict, out_dir, tag: str) -> Path:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    csv = out / f"force_sphere_{tag}.csv"
    write_table(csv, {k: v for k, v in result.items()
                      if isinstance(v, list) and k != "newton_its"})
    settings = {k: v for k, v in result.items() if not isinstance(v, list)}
    settings["newton_iterations"] = int(sum(result["newton_its"]))
    (out / f"run_sphere_{tag}.json").write_text(
        json.dumps(settings, indent=2) + "\n")
    return csv


def main(argv=None) -> int:
    from softpack.cli import positive_float

    parser = argparse.ArgumentParser(prog="softpack reference-sphere",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="output directory")
    parser.add_argument("--tag", default="ref", help="output name tag")
    parser.add_argument("--element-size", type=positive_float, default=5e-5,
                        help="triangle size near the pole, m (default 5e-5)")
    parser.add_argument("--fine-radius", type=positive_float, default=0.25,
                        help="radius of the fine zone around the pole, in R")
    parser.add_argument("--penalty", type=positive_float, default=1e5,
                        help="plate stiffness in mu/R (default 1e5)")
    parser.add_argument("--max-strain", type=positive_float, default=0.02)
    parser.add_argument("--step", type=positive_float, default=0.01,
                        help="strain step beyond 0.03 (default 0.01)")
    parser.add_argument("--diameter", type=positive_float, default=0.02)
    parser.add_argument("--mu", type=positive_float, default=0.15e6)
    parser.add_argument("--lame-lambda", type=positive_float, default=0.3e6)
    args = parser.parse_args(argv)
    if not log.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("%(asctime)s %(message)s",
                                               "%H:%M:%S"))
        log.addHandler(handler)
    log.setLevel(logging.INFO)
    log.propagate = False
    logging.getLogger().setLevel(logging.WARNING)
    result = compress_sphere(args.diameter, args.mu, args.lame_lambda,
                             args.element_size, args.fine_radius,
                             args.penalty, args.max_strain, args.step)
    csv = write_outputs(result, args.out, args.tag)
    log.info("%d cells, %d dofs, %.0f s; wrote %s", result["num_cells"],
             result["num_dofs"], result["seconds"], csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
