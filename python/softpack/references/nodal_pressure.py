"""Averaged nodal pressure on P1 triangles: the volumetric energy per node.

P1 triangles lock as nu -> 1/2 (docs/incompressible.md): each triangle's
area change is penalised by lambda, and the displacements cannot keep every
triangle's area. The averaged nodal pressure (Bonet & Burton, Commun. Numer.
Meth. Engng 14:437, 1998, for tetrahedra) moves the volumetric energy to the
nodes: node a owns a third of each of its triangles,

    V0_a = sum_{e at a} A0_e / 3,     V_a(x) = sum_{e at a} A_e(x) / 3,
    J_a = V_a / V0_a,
    U_vol = sum_a V0_a lambda/2 (ln J_a)^2,

which constrains one area per node instead of one per triangle (about half as
many constraints as unknowns' pairs), and the element keeps the rest of the
neo-Hookean energy, mu/2 (tr C + 1 - 3) - mu ln J. The pressure of node a is
p_a = lambda ln J_a / J_a.

This module is the formulation in numpy (energy, residual, tangent, checked
against finite differences in tests/python/test_reference2d.py) and a static
plates reference with it (:class:`NodalPressureReference`): the oracle for a
driver implementation. A triangle's area is bilinear in its nodes'
coordinates, so dA/dx is linear and d2A/dx2 constant.
"""

from __future__ import annotations

import numpy as np

from softpack.references.plates_reference import _Reference


def area_gradients(x, cells):
    """Each triangle's signed area and its gradient, shape (n, 3, 2)."""
    p1, p2, p3 = x[cells[:, 0]], x[cells[:, 1]], x[cells[:, 2]]
    area = 0.5 * ((p2[:, 0] - p1[:, 0]) * (p3[:, 1] - p1[:, 1])
                  - (p3[:, 0] - p1[:, 0]) * (p2[:, 1] - p1[:, 1]))
    g = np.empty((len(cells), 3, 2))
    for i, (b, c) in enumerate(((p2, p3), (p3, p1), (p1, p2))):
        g[:, i, 0] = 0.5 * (b[:, 1] - c[:, 1])
        g[:, i, 1] = 0.5 * (c[:, 0] - b[:, 0])
    return area, g


def _area_hessian() -> np.ndarray:
    """d2A / dx dx over a triangle's 6 coordinates (x1, y1, x2, y2, x3, y3)."""
    h = np.zeros((6, 6))
    for i, j in ((0, 1), (1, 2), (2, 0)):
        h[2 * i, 2 * j + 1] = h[2 * j + 1, 2 * i] = 0.5
        h[2 * j, 2 * i + 1] = h[2 * i + 1, 2 * j] = -0.5
    return h


class NodalVolumetric:
    """U_vol of one mesh (module doc); x the current coordinates, (n, 2)."""

    def __init__(self, reference_x, cells, lam):
        self.cells = np.asarray(cells)
        self.n = len(reference_x)
        self.lam = lam
        self.v0 = self._nodal(area_gradients(np.asarray(reference_x, float),
                                             self.cells)[0])
        self.dofs = np.stack([2 * self.cells, 2 * self.cells + 1],
                             axis=2).reshape(len(self.cells), 6)
        self.hessian = _area_hessian()

    def _nodal(self, per_cell):
        return np.bincount(self.cells.ravel(), np.repeat(per_cell / 3, 3),
                           minlength=self.n)

    def jacobians(self, x):
        """J_a of every node."""
        return self._nodal(area_gradients(x, self.cells)[0]) / self.v0

    def energy(self, x) -> float:
        return float(np.sum(self.v0 * 0.5 * self.lam
                            * np.log(self.jacobians(x)) ** 2))

    def residual(self, x) -> np.ndarray:
        """dU_vol/dx: sum_a p_a dV_a/dx, p_a = lambda ln J_a / J_a."""
        J = self.jacobians(x)
        p = self.lam * np.log(J) / J
        _, g = area_gradients(x, self.cells)
        per_cell = (g / 3).reshape(len(self.cells), 6) \
            * p[self.cells].sum(axis=1)[:, None]
        r = np.zeros(2 * self.n)
        np.add.at(r, self.dofs, per_cell)
        return r

    def tangent(self, x):
        """d2U_vol/dx2 (scipy CSR): sum_a lambda (1 - ln J_a) / (J_a^2 V0_a)
        dV_a (x) dV_a (coupling a node's whole patch) + sum_a p_a d2V_a."""
        import scipy.sparse as sp

        J = self.jacobians(x)
        lnJ = np.log(J)
        _, g = area_gradients(x, self.cells)
        ge = (g / 3).reshape(len(self.cells), 6)
        # dV_a/dx as the rows of a (nodes x dofs) matrix: each triangle adds
        # its ge to the rows of its three nodes
        dv = sp.csr_matrix((np.repeat(ge, 3, axis=0).ravel(),
                            (np.repeat(self.cells.ravel(), 6),
                             np.repeat(self.dofs, 3, axis=0).ravel())),
                           shape=(self.n, 2 * self.n))
        patch = dv.T @ sp.diags(self.lam * (1 - lnJ) / (J ** 2 * self.v0)) @ dv
        p_cell = (self.lam * lnJ / J)[self.cells].sum(axis=1) / 3
        local = p_cell[:, None, None] * self.hessian[None]
        rows = np.repeat(self.dofs, 6, axis=1).ravel()
        cols = np.tile(self.dofs, (1, 6)).ravel()
        curvature = sp.csr_matrix((local.ravel(), (rows, cols)),
                                  shape=patch.shape)
        return (patch + curvature).tocsr()


class NodalPressureReference(_Reference):
    """The static P1 plates reference (:mod:`.plates_reference`) with the
    volumetric energy at the nodes: the element keeps mu/2 (tr C + 1 - 3) -
    mu ln J (its lambda set to 0), :class:`NodalVolumetric` adds the rest."""

    def __init__(self, points, cells, mu, lam, stiffness):
        super().__init__(points, cells, mu, 0.0, stiffness)
        # the dolfinx numbering of the input cells
        self.volumetric = NodalVolumetric(self.X, self.node_of[cells], lam)

    def _x(self):
        return self.X + self.displacement()

    def system(self, bottom, top):
        K, r = super().system(bottom, top)
        x = self._x()
        return (K + self.volumetric.tangent(x)).tocsr(), \
            r + self.volumetric.residual(x)

    def energy_value(self):
        return super().energy_value() + self.volumetric.energy(self._x())
