"""P1 fields on triangle meshes: point interpolation and the mean rotation.

Helpers of the single-disk check (:mod:`softpack.references.single_disk`):
the displacement along a material line is interpolated in the reference
triangles (:func:`line_interpolator`, :func:`interpolate`), and the rolling
of the disk is the rotation of its area-averaged deformation gradient
(:func:`rigid_rotation`).
"""

from __future__ import annotations

import numpy as np


def line_interpolator(x, cells, points):
    """(cell, barycentric weights) of each point, for P1 interpolation.

    A point outside every triangle (a boundary point a hair outside the
    polygon) takes the triangle where its smallest barycentric coordinate
    is largest (a tiny extrapolation).
    """
    a, b, c = x[cells[:, 0]], x[cells[:, 1]], x[cells[:, 2]]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) \
        - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    out = []
    for p in np.atleast_2d(points):
        l1 = ((p[0] - a[:, 0]) * (c[:, 1] - a[:, 1])
              - (c[:, 0] - a[:, 0]) * (p[1] - a[:, 1])) / det
        l2 = ((b[:, 0] - a[:, 0]) * (p[1] - a[:, 1])
              - (p[0] - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
        lam = np.column_stack([1 - l1 - l2, l1, l2])
        k = int(np.argmax(lam.min(axis=1)))
        out.append((k, lam[k]))
    return out


def interpolate(u, cells, stencil) -> np.ndarray:
    """P1 values (m, 2) of a nodal field at the stencil's points."""
    return np.array([w @ u[cells[k]] for k, w in stencil])


def rigid_rotation(x, cells, u) -> float:
    """Rotation angle (rad) of the area-averaged deformation gradient.

    F_mean = (1/A) int F dA (P1: one F per triangle); the angle is
    atan2(F21 - F12, F11 + F22): zero for any deformation symmetric about
    the axes (whatever the mesh), the rolling angle of a disk that rolls.
    """
    p = x[cells]
    q = p + u[cells]
    dX = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]], axis=2)
    dx = np.stack([q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]], axis=2)
    area = 0.5 * np.abs(np.linalg.det(dX))
    F = np.einsum("k,kij->ij", area, dx @ np.linalg.inv(dX)) / area.sum()
    return float(np.arctan2(F[1, 0] - F[0, 1], F[0, 0] + F[1, 1]))
