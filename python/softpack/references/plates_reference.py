"""The plates check's independent computation: a static dolfinx solve.

The same triangles as the softpack run, the plane-strain neo-Hookean
energy written out here (paper Eq. 1), P1 displacements, solved
STATICALLY by Newton at prescribed plate positions, the contact a nodal
penalty of the boundary nodes against the two plates, the x translation
pinned at the node nearest the centroid; :mod:`softpack.references.plates`
(its module doc) says why each choice and what its error is.
"""

from __future__ import annotations

import math

import numpy as np


def boundary_weights(points, cells):
    """Boundary nodes and their tributary lengths (half of each adjacent
    boundary edge)."""
    edges = np.sort(np.vstack([cells[:, [0, 1]], cells[:, [1, 2]],
                               cells[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = unique[counts == 1]
    lengths = np.linalg.norm(points[boundary[:, 0]] - points[boundary[:, 1]],
                             axis=1)
    weight = np.zeros(len(points))
    np.add.at(weight, boundary[:, 0], 0.5 * lengths)
    np.add.at(weight, boundary[:, 1], 0.5 * lengths)
    nodes = np.flatnonzero(weight > 0)
    return nodes, weight[nodes]


class _Reference:
    """The static problem on one mesh: energy forms, nodal plate penalty."""

    def __init__(self, points, cells, mu, lam, stiffness):
        import ufl
        from dolfinx import fem, mesh
        from mpi4py import MPI
        from scipy.spatial import cKDTree

        domain = mesh.create_mesh(
            MPI.COMM_SELF, cells.astype(np.int64), points.astype(float),
            ufl.Mesh(ufl.VectorElement("Lagrange", ufl.triangle, 1)))
        V = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
        self.u = fem.Function(V)
        self._build_forms(V, mu, lam)
        # the dolfinx node of each input point (create_mesh reorders them)
        x = V.tabulate_dof_coordinates()[:, :2]
        distance, self.node_of = cKDTree(x).query(points)
        if distance.max() > 1e-12 * np.ptp(points):
            raise RuntimeError("dolfinx mesh nodes do not match the input")
        self.X = x
        nodes, weight = boundary_weights(points, cells)
        self.contact = self.node_of[nodes]
        self.k_weight = stiffness * weight
        # u_x = 0 at the node nearest the centroid (the x translation)
        self.pin = int(self.node_of[np.argmin(np.hypot(*points.T))])
        self.pinned = [2 * self.pin]
        self.n = len(x)

    def _build_forms(self, V, mu, lam):
        """The energy, residual and tangent forms (plane-strain
        neo-Hookean, paper Eq. 1)."""
        import ufl
        from dolfinx import fem

        v, du = ufl.TestFunction(V), ufl.TrialFunction(V)
        F = ufl.Identity(2) + ufl.grad(self.u)
        J = ufl.det(F)
        psi = (mu / 2 * (ufl.tr(F.T * F) + 1 - 3) - mu * ufl.ln(J)
               + lam / 2 * ufl.ln(J) ** 2)
        self.energy = fem.form(psi * ufl.dx)
        residual = ufl.derivative(psi * ufl.dx, self.u, v)
        self.residual = fem.form(residual)
        self.tangent = fem.form(ufl.derivative(residual, self.u, du))

    def displacement(self):
        return self.u.x.array.reshape(-1, 2)

    def gaps(self, bottom, top):
        """Penetrations of the contact nodes into the bottom and top plates
        (positive = overlap)."""
        y = self.X[self.contact, 1] + self.displacement()[self.contact, 1]
        return bottom - y, y - top

    def system(self, bottom, top):
        """Tangent (scipy CSR) and residual with the penalty, no pin."""
        import scipy.sparse as sp
        from dolfinx.fem import petsc as fp

        A = fp.assemble_matrix(self.tangent)
        A.assemble()
        indptr, indices, data = A.getValuesCSR()
        K = sp.csr_matrix((data, indices, indptr), shape=A.getSize())
        A.destroy()
        b = fp.assemble_vector(self.residual)
        r = b.array.copy()
        b.destroy()
        g_bottom, g_top = self.gaps(bottom, top)
        rows = 2 * self.contact + 1
        r[rows] += self.k_weight * (np.maximum(g_top, 0)
                                    - np.maximum(g_bottom, 0))
        active = (g_top > 0) | (g_bottom > 0)
        K = K + sp.csr_matrix((self.k_weight * active, (rows, rows)),
                              shape=K.shape)
        return K, r

    def plate_forces(self, bottom, top):
        """Force per unit length the body exerts on each plate (>= 0)."""
        g_bottom, g_top = self.gaps(bottom, top)
        return (float(np.sum(self.k_weight * np.maximum(g_bottom, 0))),
                float(np.sum(self.k_weight * np.maximum(g_top, 0))))

    def solve(self, bottom, top, tolerance, max_iterations=30):
        """Newton at fixed plates; returns iterations or None (diverged)."""
        import scipy.sparse.linalg as spla

        for iteration in range(1, max_iterations + 1):
            K, r = self.system(bottom, top)
            K = K.tolil()
            for pin in self.pinned:
                r[pin] = 0.0
                K[pin, :] = 0.0
                K[:, pin] = 0.0
                K[pin, pin] = 1.0
            step = spla.spsolve(K.tocsc(), -r)
            if not np.all(np.isfinite(step)):
                return None
            self.u.x.array[:] += step
            if not np.isfinite(self.energy_value()):
                return None
            if np.abs(step).max() < tolerance:
                return iteration
        return None

    def energy_value(self):
        from dolfinx import fem

        return fem.assemble_scalar(self.energy)

    def pin_reaction(self, bottom, top):
        """The largest |force| a pin exerts (the residual at the pinned
        dofs)."""
        _, r = self.system(bottom, top)
        return float(np.abs(r[self.pinned]).max())


def static_reference(points, cells, mu, lam, y_bottom0, y_top0, diameter,
                     max_strain, n_steps=40, penalty=1e5, max_halvings=6,
                     model=None):
    """The dolfinx curve (module doc): eps, f_norm (mean of the plates) and
    each plate's, Newton iterations, penetration and pin reaction. ``model``
    another problem class with _Reference's interface (e.g.
    :class:`softpack.references.nodal_pressure.NodalPressureReference`)."""
    ref = (model or _Reference)(np.asarray(points, float), np.asarray(cells),
                                mu, lam, penalty * mu / diameter)
    height = y_top0 - y_bottom0
    middle = 0.5 * (y_top0 + y_bottom0)
    tolerance = 1e-10 * diameter
    rows = [dict(eps=0.0, f_norm=0.0, f_norm_top=0.0, f_norm_bottom=0.0,
                 newton_iterations=0, max_penetration_over_D=0.0,
                 pin_reaction_over_f=0.0, energy=0.0)]
    eps_done = 0.0
    for eps in np.linspace(0.0, max_strain, n_steps + 1)[1:]:
        iterations = _advance(ref, eps_done, eps, height, middle, tolerance,
                              max_halvings)
        delta = height * (1 - math.exp(-eps))
        bottom, top = y_bottom0 + delta / 2, y_top0 - delta / 2
        f_bottom, f_top = ref.plate_forces(bottom, top)
        f = 0.5 * (f_bottom + f_top)
        penetration = max(0.0, *[float(g.max()) for g in ref.gaps(bottom,
                                                                 top)])
        rows.append(dict(
            eps=float(eps), f_norm=f / (height * mu),
            f_norm_top=f_top / (height * mu),
            f_norm_bottom=f_bottom / (height * mu),
            newton_iterations=iterations,
            max_penetration_over_D=penetration / diameter,
            pin_reaction_over_f=ref.pin_reaction(bottom, top) / f,
            energy=float(ref.energy_value())))
        eps_done = eps
    return {key: np.array([row[key] for row in rows]) for key in rows[0]}


def _advance(ref, eps_old, eps_new, height, middle, tolerance, halvings):
    """Move the plates from eps_old to eps_new, halving on failure."""
    backup = ref.u.x.array.copy()
    for level in range(halvings + 1):
        targets = np.linspace(eps_old, eps_new, 2 ** level + 1)[1:]
        total, previous = 0, eps_old
        for target in targets:
            _predict(ref, previous, target, height, middle)
            delta = height * (1 - math.exp(-target))
            its = ref.solve(middle - height / 2 + delta / 2,
                            middle + height / 2 - delta / 2, tolerance)
            if its is None:
                break
            total, previous = total + its, target
        else:
            return total
        ref.u.x.array[:] = backup
    raise RuntimeError(f"dolfinx reference: no equilibrium at eps ="
                       f" {eps_new:.4f}")


def _predict(ref, eps_old, eps_new, height, middle):
    """Guess: the current shape compressed in y about the plates' middle by
    the plates' ratio and stretched in x by its inverse."""
    s = math.exp(eps_old - eps_new)  # (H0 - delta_new) / (H0 - delta_old)
    x = ref.X + ref.displacement()
    centre = x[:, 0].mean()
    new = np.column_stack([centre + (x[:, 0] - centre) / s,
                           middle + (x[:, 1] - middle) * s])
    ref.u.x.array[:] = (new - ref.X).ravel()
