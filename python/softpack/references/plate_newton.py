"""Newton at a prescribed plate position, for the static references.

A problem (:class:`softpack.references.cylinder3d._EighthCylinder` or
:class:`softpack.references.disk_mixed._QuarterDisk`) exposes its unknown
``w`` (a dolfinx Function, scaled: lengths by R, stresses by mu), ``plate``
(the plate's y, a Constant), the forms ``residual_form``, ``tangent_form``
and ``plate_force_form``, its Dirichlet ``bcs``, ``sym_y_dofs`` (the y
dofs on the symmetry plane y = 0) and ``comp_dofs`` / ``comp_coords`` (the
dofs and reference coordinates of each displacement component); this module
moves its plate and finds the equilibrium, in any dimension.
"""

import logging

import numpy as np

log = logging.getLogger("softpack.references")


class PlateSolver:
    """Newton (PETSc SNES, MUMPS LU) for one plate position."""

    def __init__(self, prob):
        from petsc4py import PETSc
        from dolfinx.fem import petsc as fp

        self.prob = prob
        self.b = fp.create_vector(prob.residual_form)
        self.A = fp.create_matrix(prob.tangent_form)
        self.x = prob.w.vector.copy()
        snes = PETSc.SNES().create(prob.mesh.comm)
        prefix = f"softpack_ref3d_{id(self)}_"
        snes.setOptionsPrefix(prefix)
        PETSc.Options(prefix)["snes_linesearch_type"] = "basic"
        snes.setType("newtonls")
        snes.setFunction(self._residual, self.b)
        snes.setJacobian(self._tangent, self.A)
        snes.setTolerances(rtol=1e-9, atol=1e-10, stol=1e-14, max_it=25)
        ksp = snes.getKSP()
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType("mumps")
        snes.setFromOptions()
        self.snes = snes

    def _residual(self, snes, x, b):
        from petsc4py import PETSc
        from dolfinx.fem import petsc as fp

        prob = self.prob
        x.copy(prob.w.vector)
        prob.w.vector.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        with b.localForm() as bl:
            bl.set(0.0)
        fp.assemble_vector(b, prob.residual_form)
        fp.apply_lifting(b, [prob.tangent_form], bcs=[prob.bcs], x0=[x], scale=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fp.set_bc(b, prob.bcs, x, -1.0)

    def _tangent(self, snes, x, A, P):
        from dolfinx.fem import petsc as fp

        A.zeroEntries()
        fp.assemble_matrix(A, self.prob.tangent_form, bcs=self.prob.bcs)
        A.assemble()

    def solve(self, delta_hat):
        """Equilibrium with the plate at y = 1 - delta_hat/2 (scaled), from prob.w."""
        prob = self.prob
        prob.plate.value = 1.0 - 0.5 * delta_hat
        prob.w.vector.copy(self.x)
        self.snes.solve(None, self.x)
        ok = self.snes.getConvergedReason() > 0 and np.isfinite(self.x.norm())
        if ok:
            self.x.copy(prob.w.vector)
            prob.w.x.scatter_forward()
        return ok, self.snes.getIterationNumber()

    def reactions(self):
        """(plate force, y = 0 reaction) on the eighth, scaled.

        The first is the penalty force integrated over the plate; the second the
        y-residual summed over the nodes of the symmetry plane y = 0 (assembled
        without boundary conditions): equal at equilibrium.
        """
        from petsc4py import PETSc
        from dolfinx import fem
        from dolfinx.fem import petsc as fp

        with self.b.localForm() as bl:
            bl.set(0.0)
        fp.assemble_vector(self.b, self.prob.residual_form)
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        f_sym = self.b.array[self.prob.sym_y_dofs].sum()
        return fem.assemble_scalar(self.prob.plate_force_form), f_sym


def predict(prob, delta_old, delta_new):
    """Guess: homogeneous compression in y (factor s), expansion 1/s in x."""
    s = (1.0 - 0.5 * delta_new) / (1.0 - 0.5 * delta_old)
    a = prob.w.x.array
    for comp, factor in ((0, 1.0 / s), (1, s)):
        dofs, X = prob.comp_dofs[comp], prob.comp_coords[comp][:, comp]
        a[dofs] = (X + a[dofs]) * factor - X
    prob.w.x.scatter_forward()


def advance(prob, solver, dhat_old, dhat_new, max_halvings):
    """Move the plate from dhat_old to dhat_new, halving the increment on failure."""
    backup = prob.w.x.array.copy()
    for level in range(max_halvings + 1):
        n_sub = 2 ** level
        targets = dhat_old + (dhat_new - dhat_old) * np.arange(1, n_sub + 1) / n_sub
        prev, total_its, ok = dhat_old, 0, True
        for target in targets:
            predict(prob, prev, target)
            ok, its = solver.solve(target)
            total_its += its
            if not ok:
                break
            prev = target
        if ok:
            return total_its
        log.warning("step to delta/R=%.5f failed (reason %d), %d substeps next",
                    dhat_new, solver.snes.getConvergedReason(), 2 * n_sub)
        prob.w.x.array[:] = backup
        prob.w.x.scatter_forward()
    raise RuntimeError(f"no equilibrium at delta/R = {dhat_new:.5f}")


class QuarterUnderPlate:
    """What a quarter of a disk or of a sphere's meridian under a plate
    shares (:class:`softpack.references.disk_mixed._QuarterDisk`,
    :class:`softpack.references.sphere_axisym._MeridianQuarter`): the
    displacement space ``U`` (a subspace of ``W`` when mixed), the unknown
    ``w``, the plate's y ``plate``, the unit arc x^2 + y^2 = 1 in scaled
    coordinates, and u_x = 0 on the facets tagged ``tags[0]``, u_y = 0 on
    ``tags[1]``."""

    def _locate_dofs(self, facets, tags):
        from dolfinx import fem
        from petsc4py import PETSc

        self.bcs = []
        for comp, tag in zip((0, 1), tags):
            dofs = fem.locate_dofs_topological(self.U.sub(comp), 1,
                                               facets.find(tag))
            self.bcs.append(fem.dirichletbc(PETSc.ScalarType(0.0), dofs,
                                            self.U.sub(comp)))
        self.comp_dofs, self.comp_coords = [], []
        for comp in range(2):
            Vc, dofs = self.U.sub(comp).collapse()
            self.comp_dofs.append(np.asarray(dofs, dtype=np.int32))
            self.comp_coords.append(Vc.tabulate_dof_coordinates())
        y = self.comp_coords[1]
        self.sym_y_dofs = self.comp_dofs[1][np.abs(y[:, 1]) < 1e-10]
        on_arc = np.abs(np.hypot(y[:, 0], y[:, 1]) - 1.0) < 1e-8
        self.arc_y = (self.comp_dofs[1][on_arc], y[on_arc, 1])

    @property
    def num_cells(self) -> int:
        return self.mesh.topology.index_map(2).size_local

    def max_overlap(self) -> float:
        """Largest penetration of an arc node into the plate (scaled)."""
        dofs, Y = self.arc_y
        return max(0.0, float(np.max(Y + self.w.x.array[dofs]
                                     - self.plate.value)))
