"""The viscoelastic disk check's independent computation: dolfinx, in time.

The law of ``forms/materials/viscoelastic_neo_hookean.py`` (neo-Hookean
equilibrium part plus two Maxwell branches on the isochoric part, plane
strain) written out again here from its STRESS, not from the material
file's energy, and integrated in time by another scheme:

    P = mu (F - F^-T) + lambda ln J F^-T + sum_k tau_k F^-T,
    tau_k = mu_k dev(Fbar A_k Fbar^T),  Fbar = J^(-1/3) F  (3x3, F33 = 1),
    dA_k/dt = -(A_k - Cbar^-1) / tau_k,  Cbar = Fbar^T Fbar.

The driver holds A_k at its value of the step's start while it finds the
step's configuration and relaxes it afterwards (an explicit update). Here
the update is IMPLICIT in the configuration: the step's A_k is the exact
relaxation over the step at the step's END configuration,

    A_k(n+1) = Cbar^-1(n+1) + (A_k(n) - Cbar^-1(n+1)) exp(-h / tau_k),

a function of the unknown displacement inside Newton (the tangent is
UFL's derivative of the residual through it, unsymmetric). Both schemes
are first order in h with errors of opposite sign, so their difference
measures the time discretisation. Quasi-static (no mass, no damping); the
plates, the contact penalty and the pinned centre (u_x) are those of
:mod:`softpack.references.plates_reference`; the top node's u_x is pinned
as well (the rotation); the pins' largest reaction is reported.
"""

from __future__ import annotations

import numpy as np

from softpack.references.plates_reference import _Reference

#: The branches of the law: (ratio, relaxation time) parameter names.
BRANCHES = (("branch_ratio_1", "relaxation_time_1"),
            ("branch_ratio_2", "relaxation_time_2"))


class MaxwellReference(_Reference):
    """Quasi-static P1 disk with DG0 branch variables (module doc)."""

    def __init__(self, points, cells, material: dict, stiffness,
                 time_step: float):
        self.material = material
        self.time_step = time_step
        super().__init__(points, cells, material["shear_modulus"],
                         material["lame_lambda"], stiffness)
        # u_x at the top node (on the loading axis, the mesh turned
        # node-up): the rotation, which a frictionless static problem leaves
        # to the polygon's corners (Newton's active set then cycles when a
        # plate touches one node; the driver has friction 0.01 there)
        self.pinned.append(2 * int(np.argmax(self.X[:, 1])))

    def _build_forms(self, V, mu, lam):
        import ufl
        from dolfinx import fem

        domain = V.mesh
        Q = fem.FunctionSpace(domain, ufl.TensorElement(
            "DG", ufl.triangle, 0, shape=(3, 3)))
        self.previous = [fem.Function(Q) for _ in BRANCHES]
        self.step = fem.Constant(domain, float(self.time_step))
        for A in self.previous:  # the virgin state
            A.x.array[:] = np.tile(np.eye(3).ravel(), A.x.array.size // 9)
        g = ufl.grad(self.u)
        F = ufl.as_matrix([[1 + g[0, 0], g[0, 1], 0],
                           [g[1, 0], 1 + g[1, 1], 0], [0, 0, 1]])
        I3 = ufl.Identity(3)
        J = ufl.det(F)
        F_inv_T = ufl.inv(F).T
        Fbar = J ** (-1.0 / 3.0) * F
        Cbar_inv = ufl.inv(Fbar.T * Fbar)
        P = mu * (F - F_inv_T) + lam * ufl.ln(J) * F_inv_T
        psi = (mu / 2 * (ufl.tr(F.T * F) - 3) - mu * ufl.ln(J)
               + lam / 2 * ufl.ln(J) ** 2)
        self.relaxed = []
        for A_old, (ratio, tau) in zip(self.previous, BRANCHES):
            mu_k = self.material[ratio] * mu
            decay = ufl.exp(-self.step / self.material[tau])
            A = Cbar_inv + (A_old - Cbar_inv) * decay
            self.relaxed.append(A)
            B = Fbar * A * Fbar.T
            P = P + mu_k * (B - ufl.tr(B) / 3 * I3) * F_inv_T
            psi = psi + mu_k / 2 * (ufl.tr(Fbar.T * Fbar * A) - 3
                                    - ufl.ln(ufl.det(A)))
        v, du = ufl.TestFunction(V), ufl.TrialFunction(V)
        P2 = ufl.as_matrix([[P[i, j] for j in range(2)] for i in range(2)])
        # every integrand is constant over a P1 cell: one point is exact
        dx = ufl.dx(metadata={"quadrature_degree": 1})
        residual = ufl.inner(P2, ufl.grad(v)) * dx
        self.energy = fem.form(psi * dx)
        self.residual = fem.form(residual)
        self.tangent = fem.form(ufl.derivative(residual, self.u, du))
        points = Q.element.interpolation_points()
        self._relax = [fem.Expression(A, points) for A in self.relaxed]

    def set_time_step(self, h: float):
        """The step the next solve relaxes the branches over (s)."""
        self.step.value = h

    def commit(self):
        """End of an accepted step: A_k(n) <- A_k(n+1) at the converged
        displacement."""
        values = []
        for A_old, relax in zip(self.previous, self._relax):
            new = A_old.copy()
            new.interpolate(relax)
            values.append(new.x.array.copy())
        for A_old, value in zip(self.previous, values):
            A_old.x.array[:] = value
