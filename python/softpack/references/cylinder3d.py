"""3D reference for the single-cylinder check (paper Figs. 2 and 3, METHOD.md §5).

A neo-Hookean cylinder of diameter D and length l (axis along z, both end faces
traction-free) is squeezed between two frictionless rigid plates normal to y,
each moving by delta/2 towards the centre; eps = -ln(1 - delta/D).

Model
  * law (METHOD.md §2): Psi = mu/2 (I1 - 3) - mu ln J + lmbda/2 (ln J)^2 with
    lmbda = 2 mu nu / (1 - 2 nu) (nu = 0.495: lmbda = 99 mu), P2 tetrahedra; or
    exactly incompressible: Psi = mu/2 (I1 - 3) - mu ln J subject to J = 1,
    enforced by a pressure multiplier p (Taylor–Hood P2-P1, Lagrangian
    L = int Psi - p (J - 1)); the -mu ln J term makes the reference state
    stress-free at p = 0 and vanishes where J = 1.
  * quadrature degree 4 everywhere (FFCx would pick hundreds of points per cell).
  * symmetry: one eighth, x >= 0, y >= 0, 0 <= z <= l/2, with u_x = 0 on x = 0,
    u_y = 0 on y = 0, u_z = 0 on z = 0.  Here z = 0 is the cylinder's MID-PLANE
    and z = l/2 one of its (free) end faces.  Quadratic (10-node) tetrahedra,
    so the P2 nodes of the curved surface lie on the true circle.
  * frictionless rigid plate y = R - delta/2: a penalty on the curved surface,
    k/2 <Y + u_y - (R - delta/2)>_+^2 per unit reference area, k = 1e4 mu/R
    (the force is along y only: frictionless). Newton (PETSc SNES, MUMPS LU),
    load stepping in delta with a homogeneous-compression predictor and step
    halving on failure. (Node-wise bounds with SNES vinewtonrsls were tried
    first: with P2 the corner nodes of a loaded face take zero or negative
    consistent forces and the active set cycled without converging.)
    Penetration stays below 1e-3 delta and the penalty energy below 1e-3 of
    the strain energy (both recorded).
  * plate force f (total, one plate, full cylinder) = 4 x the penalty force on
    the eighth; the reaction summed over the nodes of the symmetry plane y = 0
    (residual assembled without boundary conditions) is kept as an
    equilibrium check.
  * internally lengths are scaled by R and stresses by mu (all unknowns O(1)).

Profile (Fig. 3): u_x along the Lagrangian transverse diameter (Y = 0), i.e.
the material line perpendicular to the loading through the centre, on the
mid-plane z = 0 (the default CSV) and on the end face z = l/2 (extra CSV).
w = X/R in [-1, 1] (the antisymmetry u_x(-X) = -u_x(X) gives the half x < 0);
ux_over_D = u_x/D.

Mid-plane vs bottom face. The paper's DIC sees the bottom face of the
cylinders; with both ends free (as here) that is the end-face CSV, not the
mid-plane one, and the two differ: the cylinder is not in plane strain. It
lengthens (the end faces bulge out, u_z/D ~ 0.05 next to the contact lines,
~ 0.02 at the centre and ~ 0 at x = +-R at eps = 0.2) and its lateral surface
flares towards the ends: at eps = 0.2, u_x(R)/D = 0.029 on the mid-plane and
0.040 on the end face: the end-face profile is ~ 1.37 x the mid-plane one
along the whole diameter, at every strain (0.05-0.20) and mesh. (The
mid-plane profile is also very slightly non-monotonic next to w = +-1 at
eps = 0.2.) If the real bottom slid on the glass
without lifting (u_z = 0 there), it would be the mid-plane of a cylinder of
length 2l instead: not computed here.
"""

import argparse
import json
import logging
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from softpack.analysis import strain
from softpack.contract.tables import write_table
from softpack.references.plate_newton import PlateSolver, advance
from softpack.references.cylinder3d_mesh import (TAG_CURVED, TAG_X0, TAG_Y0,
                                                 TAG_Z0, build_mesh)

log = logging.getLogger("softpack.references.cylinder3d")

PROFILE_STRAINS = (0.05, 0.10, 0.15, 0.20)


@dataclass
class Results:
    """Output of compress_cylinder_3d. Forces in N, energies in J, SI lengths."""
    model: str                      # "nu0495", "incompressible", ...
    diameter: float
    length: float
    mu: float
    nu: float | None
    element_size: float
    num_cells: int = 0
    num_dofs: int = 0
    eps: list = field(default_factory=list)          # compressive strain
    delta: list = field(default_factory=list)        # plate approach (m)
    force: list = field(default_factory=list)        # plate force (N)
    force_sym: list = field(default_factory=list)    # same, read on y = 0
    energy: list = field(default_factory=list)       # strain energy (J)
    penalty_energy: list = field(default_factory=list)  # k/2 overlap^2 (J)
    newton_its: list = field(default_factory=list)
    penalty: float = 0.0            # plate penalty stiffness / (mu/R)
    n_steps: int = 0
    max_overlap: float = 0.0        # largest nodal penetration of the plate (m)
    profiles_mid: dict = field(default_factory=dict)  # eps -> (w, ux/D)
    profiles_end: dict = field(default_factory=dict)
    wall_time: float = 0.0

    @property
    def f_norm(self):
        return np.asarray(self.force) / (self.diameter * self.length * self.mu)

    @property
    def work(self):
        """Work of the two plates, trapezoidal integral of f d(delta)."""
        f, d = np.asarray(self.force), np.asarray(self.delta)
        return np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(d))])


def model_name(nu):
    return "incompressible" if nu is None else "nu" + f"{nu:g}".replace(".", "")


# ---------------------------------------------------------------- problem

class _EighthCylinder:
    """Spaces, forms and symmetry conditions of the scaled problem (R = mu = 1)."""

    def __init__(self, mesh, facets, nu, penalty):
        import ufl
        from dolfinx import fem
        from petsc4py import PETSc

        self.mesh, self.nu = mesh, nu
        cell = mesh.ufl_cell()
        p2 = ufl.VectorElement("Lagrange", cell, 2)
        if nu is None:
            self.W = fem.FunctionSpace(mesh, ufl.MixedElement([p2, ufl.FiniteElement("Lagrange", cell, 1)]))
            self.U = self.W.sub(0)
        else:
            self.W = fem.FunctionSpace(mesh, p2)
            self.U = self.W
        self.w = fem.Function(self.W)
        self.plate = fem.Constant(mesh, PETSc.ScalarType(1.0))   # plate position y
        self.penalty = penalty
        self._define_forms(facets)
        self._locate_dofs(facets)

    def _define_forms(self, facets):
        import ufl
        from dolfinx import fem

        dxq = ufl.dx(metadata={"quadrature_degree": 4})
        ds_plate = ufl.Measure("ds", domain=self.mesh, subdomain_data=facets,
                               metadata={"quadrature_degree": 6})(TAG_CURVED)
        u, p = ufl.split(self.w) if self.nu is None else (self.w, None)
        F = ufl.Identity(3) + ufl.grad(u)
        J = ufl.det(F)
        psi = 0.5 * (ufl.tr(F.T * F) - 3) - ufl.ln(J)
        if self.nu is not None:
            psi = psi + self.nu / (1 - 2 * self.nu) * ufl.ln(J) ** 2   # lmbda/2 (ln J)^2
        # penetration of the plate, penalised: k/2 <y + u_y - plate>_+^2
        overlap = ufl.max_value(ufl.SpatialCoordinate(self.mesh)[1] + u[1] - self.plate, 0.0)
        lagrangian = psi * dxq + 0.5 * self.penalty * overlap ** 2 * ds_plate
        if self.nu is None:
            lagrangian = lagrangian - p * (J - 1) * dxq
        residual = ufl.derivative(lagrangian, self.w, ufl.TestFunction(self.W))
        self.energy_form = fem.form(psi * dxq)
        self.penalty_energy_form = fem.form(0.5 * self.penalty * overlap ** 2 * ds_plate)
        self.plate_force_form = fem.form(self.penalty * overlap * ds_plate)
        self.residual_form = fem.form(residual)
        self.tangent_form = fem.form(ufl.derivative(residual, self.w, ufl.TrialFunction(self.W)))

    def _locate_dofs(self, facets):
        from dolfinx import fem
        from petsc4py import PETSc

        fdim = self.mesh.topology.dim - 1
        self.bcs = []
        for comp, tag in ((0, TAG_X0), (1, TAG_Y0), (2, TAG_Z0)):
            dofs = fem.locate_dofs_topological(self.U.sub(comp), fdim, facets.find(tag))
            self.bcs.append(fem.dirichletbc(PETSc.ScalarType(0.0), dofs, self.U.sub(comp)))
        # dof indices (in W) and reference coordinates of each displacement component
        self.comp_dofs, self.comp_coords = [], []
        for comp in range(3):
            Vc, dofs = self.U.sub(comp).collapse()
            self.comp_dofs.append(np.asarray(dofs, dtype=np.int32))
            self.comp_coords.append(Vc.tabulate_dof_coordinates())
        ycoord = self.comp_coords[1]
        self.sym_y_dofs = self.comp_dofs[1][np.abs(ycoord[:, 1]) < 1e-10]
        on_circle = np.abs(np.hypot(ycoord[:, 0], ycoord[:, 1]) - 1.0) < 1e-8
        self.surface_y = (self.comp_dofs[1][on_circle], ycoord[on_circle, 1])
        log.info("mesh: %d cells, %d dofs", self.num_cells, self.w.x.array.size)

    @property
    def num_cells(self):
        return self.mesh.topology.index_map(self.mesh.topology.dim).size_local

    def max_overlap(self):
        """Largest penetration of a curved-surface node into the plate (scaled)."""
        dofs, Y = self.surface_y
        return max(0.0, float(np.max(Y + self.w.x.array[dofs] - self.plate.value)))

    def transverse_profile(self, z):
        """(X, u_x) at the nodes of the material line Y = 0, Z = z, sorted by X."""
        c = self.comp_coords[0]
        sel = np.flatnonzero((np.abs(c[:, 1]) < 1e-10) & (np.abs(c[:, 2] - z) < 1e-10))
        sel = sel[np.argsort(c[sel, 0])]
        return c[sel, 0], self.w.x.array[self.comp_dofs[0][sel]].copy()


# ---------------------------------------------------------------- driver

def strain_schedule(max_strain, n_steps):
    """Uniform steps in eps, plus the profile strains (so they are hit exactly)."""
    eps = list(np.linspace(0.0, max_strain, n_steps + 1))
    eps += [e for e in PROFILE_STRAINS if e <= max_strain + 1e-12]
    eps = np.unique(np.round(eps, 12))
    return eps[eps > 0]


def compress_cylinder_3d(diameter=0.02, length=0.015, mu=0.15e6, nu=0.495,
                         element_size=0.001, max_strain=0.25, n_steps=25,
                         penalty=1e4, max_halvings=5):
    """Compress the cylinder between frictionless plates up to eps = max_strain.

    nu=None is the exactly incompressible (Taylor–Hood) model. element_size (m)
    is the tetrahedron size near the contact line (twice that far from it).
    penalty is the plate stiffness per unit reference area in units of mu/R.
    Returns a Results; raises RuntimeError if a step fails after max_halvings.
    """
    t0 = time.perf_counter()
    R = 0.5 * diameter
    mesh, facets = build_mesh(0.5 * length / R, element_size / R)
    prob = _EighthCylinder(mesh, facets, nu, penalty)
    solver = PlateSolver(prob)
    res = Results(model_name(nu), diameter, length, mu, nu, element_size,
                  num_cells=prob.num_cells, num_dofs=prob.w.x.array.size)
    res.eps, res.delta, res.force, res.force_sym = [0.0], [0.0], [0.0], [0.0]
    res.energy, res.penalty_energy, res.newton_its = [0.0], [0.0], [0]
    res.penalty, res.n_steps = penalty, n_steps
    for eps in strain_schedule(max_strain, n_steps):
        dhat = float(strain.approach(eps, diameter)) / R
        its = advance(prob, solver, res.delta[-1] / R, dhat, max_halvings)
        _record(prob, solver, res, eps, dhat * R, its)
        log.info("%s eps=%.4f f_norm=%.5f (y=0: %.5f) newton=%d  %.1fs", res.model, eps,
                 res.f_norm[-1], res.force_sym[-1] / (diameter * length * mu), its,
                 time.perf_counter() - t0)
    res.wall_time = time.perf_counter() - t0
    return res


def _record(prob, solver, res, eps, delta, its):
    from dolfinx import fem

    R, mu = 0.5 * res.diameter, res.mu
    f_plate, f_sym = solver.reactions()
    res.eps.append(float(eps))
    res.delta.append(float(delta))
    res.force.append(4.0 * f_plate * mu * R ** 2)
    res.force_sym.append(4.0 * f_sym * mu * R ** 2)
    res.energy.append(8.0 * fem.assemble_scalar(prob.energy_form) * mu * R ** 3)
    res.penalty_energy.append(8.0 * fem.assemble_scalar(prob.penalty_energy_form) * mu * R ** 3)
    res.max_overlap = max(res.max_overlap, prob.max_overlap() * R)
    res.newton_its.append(its)
    for e in PROFILE_STRAINS:
        if abs(eps - e) < 1e-9:
            res.profiles_mid[e] = _full_diameter(*prob.transverse_profile(0.0))
            res.profiles_end[e] = _full_diameter(*prob.transverse_profile(0.5 * res.length / R))


def _full_diameter(X, ux):
    """w = X/R over [-1, 1] by antisymmetry, and u_x/D (inputs scaled by R)."""
    keep = X > 1e-12
    w = np.concatenate([-X[keep][::-1], X[~keep], X[keep]])
    u = np.concatenate([-ux[keep][::-1], ux[~keep], ux[keep]])
    return w, 0.5 * u


# ---------------------------------------------------------------- estimates

def johnson_line_contact(eps, nu, plane_strain=True):
    """Small-strain f/(D l mu) of a linear elastic cylinder between rigid plates.

    Johnson, Contact Mechanics (1985), line contact, both plates (eq. 5.36):
        delta = 2 P / (pi E*) (2 ln(4 R / a) - 1),   a^2 = 4 P R / (pi E*),
    P = f/l the force per unit length, delta the plate approach (here
    delta = D (1 - exp(-eps))). E* = E/(1 - nu^2) (plane strain) or E* = E
    (plane stress), E = 2 mu (1 + nu). With p = P/(D mu) and k = E*/mu this is
    delta/D = 2p/(pi k) (ln(2 pi k / p) - 1), solved for p by bisection
    (monotonic for p < 2 pi k / e^2, far beyond the range of use).
    """
    eps = np.atleast_1d(np.asarray(eps, dtype=float))
    E = 2.0 * (1.0 + nu)
    k = E / (1.0 - nu ** 2) if plane_strain else E
    target = strain.approach(eps, 1.0)

    def approach(p):
        return 2 * p / (np.pi * k) * (np.log(2 * np.pi * k / p) - 1)

    lo, hi = np.full_like(eps, 1e-300), np.full_like(eps, 2 * np.pi * k / np.e ** 2)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        too_big = approach(mid) > target
        hi, lo = np.where(too_big, mid, hi), np.where(too_big, lo, mid)
    return np.where(eps > 0, 0.5 * (lo + hi), 0.0)


# ---------------------------------------------------------------- output

def write_csvs(res, out_dir):
    """force_3d_<model>.csv, profile_3d_<model>[_endface].csv, energy_3d_<model>.csv, run json."""
    os.makedirs(out_dir, exist_ok=True)
    tag = res.model
    eps = np.asarray(res.eps)
    scale = res.diameter * res.length * res.mu
    write_table(os.path.join(out_dir, f"force_3d_{tag}.csv"),
                {"eps": eps, "f_norm": res.f_norm})
    e_scale = scale * res.diameter
    write_table(os.path.join(out_dir, f"energy_3d_{tag}.csv"), {
        "eps": eps, "f_norm": res.f_norm,
        "f_norm_sym_plane": np.asarray(res.force_sym) / scale,
        "work_norm": res.work / e_scale,
        "energy_norm": np.asarray(res.energy) / e_scale,
        "penalty_energy_norm": np.asarray(res.penalty_energy) / e_scale})
    for suffix, profiles in (("", res.profiles_mid), ("_endface", res.profiles_end)):
        rows = np.array([(e, w, u) for e in sorted(profiles)
                         for w, u in zip(*profiles[e])]).reshape(-1, 3)
        write_table(os.path.join(out_dir, f"profile_3d_{tag}{suffix}.csv"),
                    dict(zip(("eps", "w", "ux_over_D"), rows.T)))
    meta = {"model": tag, "nu": res.nu, "diameter": res.diameter, "length": res.length,
            "mu": res.mu, "element_size": res.element_size, "num_cells": res.num_cells,
            "num_dofs": res.num_dofs, "wall_time_s": round(res.wall_time, 1),
            "newton_iterations": int(sum(res.newton_its)),
            "energy_balance_rel": energy_balance(res), "penalty": res.penalty,
            "n_steps": res.n_steps, "max_overlap_over_delta": res.max_overlap / res.delta[-1],
            "w": "X/R along the transverse diameter Y = 0 (profile: mid-plane; _endface: z = l/2)",
            "energy_norm": "E/(mu D^2 l)", "work_norm": "int f d(delta) / (mu D^2 l)"}
    with open(os.path.join(out_dir, f"run_3d_{tag}.json"), "w") as fh:
        json.dump(meta, fh, indent=1)


def energy_balance(res):
    """(plate work - stored energy) / stored energy at the last step.

    Stored = strain energy + the (small) penalty energy of the plate contact.
    """
    stored = res.energy[-1] + res.penalty_energy[-1]
    return float((res.work[-1] - stored) / stored)


def main(argv=None):
    from softpack.cli import positive_float, positive_int

    parser = argparse.ArgumentParser(prog="softpack reference3d", description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="directory for the CSV files")
    parser.add_argument("--element-size", type=positive_float, default=0.001,
                        help="tetrahedron size near the contact line, m (default 0.001; 2x far from it)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--incompressible", action="store_true", help="J = 1, Taylor-Hood P2-P1")
    group.add_argument("--nu", type=float, default=0.495, help="Poisson ratio (default 0.495)")
    parser.add_argument("--max-strain", type=positive_float, default=0.25)
    parser.add_argument("--steps", type=positive_int, default=25, help="uniform steps in eps")
    parser.add_argument("--penalty", type=positive_float, default=1e4, help="plate stiffness in mu/R (default 1e4)")
    parser.add_argument("--diameter", type=positive_float, default=0.02)
    parser.add_argument("--length", type=positive_float, default=0.015)
    parser.add_argument("--mu", type=positive_float, default=0.15e6)
    args = parser.parse_args(argv)
    if not log.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S"))
        log.addHandler(handler)
    log.setLevel(logging.INFO)
    log.propagate = False
    logging.getLogger().setLevel(logging.WARNING)   # FFCx/cffi JIT chatter
    res = compress_cylinder_3d(args.diameter, args.length, args.mu,
                               None if args.incompressible else args.nu,
                               args.element_size, args.max_strain, args.steps, args.penalty)
    write_csvs(res, args.out)
    log.info("%s: %d cells, %d dofs, %.0f s; energy balance (work-E)/E = %.2e; wrote %s",
             res.model, res.num_cells, res.num_dofs, res.wall_time, energy_balance(res), args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
