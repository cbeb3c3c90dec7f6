"""Per-particle shape observables from the deformed mesh: orientation and
asphericity, for any particle shape.

From one stored time of ``fields.h5`` (:func:`softpack.analysis.fields.
read_snapshot`: current node positions, triangles, each triangle's body),
each particle's

``area``          of its current triangles (m^2);
``x``, ``y``      area centroid (m);
``orientation``   angle of the major principal axis of its second moment of
                  area, counter-clockwise from +x, in [0, pi) (rad); NaN when
                  the two principal moments are equal to 1e-9 (a disk has no
                  orientation);
``elongation``    sqrt(J_max / J_min) of the principal second moments: the
                  aspect ratio a / b of the ellipse with the same moments (1
                  for a disk or a regular polygon, k for an ellipse of
                  aspect ratio k);
``asphericity``   P^2 / (4 pi A) of its current boundary polygon (perimeter P,
                  area A): 1 for a circle, 4 / pi for a square, growing as
                  the particle deforms away from a disk (the shape factor
                  of the 2D soft-particle literature);
``rotation``      (when the reference positions are given) the particle's
                  rigid rotation from its reference configuration,
                  counter-clockwise, in (-pi, pi] (rad): the polar
                  rotation of its area-averaged deformation gradient
                  (exact for a rigid motion, zero for a symmetric
                  stretch). For a regular polygon or a disk, whose second
                  moment has no axis, this (plus the particle's initial
                  angle) is its orientation.

A new module of the analysis stage (issue 13): the existing observables are
left as they are; these are computed on demand.
"""

from __future__ import annotations

import math

import numpy as np

#: Relative difference of the principal moments below which a particle has
#: no orientation.
ISOTROPIC = 1e-9


def particle_shapes(points, cells, body, reference=None) -> dict:
    """Shape observables of every body (see the module doc).

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Current node positions (m).
    cells : ndarray of int, shape (m, 3)
        Triangles (either orientation).
    body : ndarray of int, shape (m,)
        Each triangle's body id, ``0..B-1``.
    reference : ndarray, shape (n, 2), optional
        Reference node positions (m): adds ``rotation``.

    Returns
    -------
    dict of ndarray, shape (B,)
        ``body, area, x, y, orientation, elongation, asphericity``.
    """
    p = np.asarray(points, dtype=float)[:, :2]
    cells = np.asarray(cells, dtype=np.int64)
    body = np.asarray(body, dtype=np.int64)
    n = int(body.max()) + 1
    v = p[cells]  # (m, 3, 2)
    e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    signed = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    area = np.bincount(body, signed, n)
    first = np.stack([np.bincount(body, signed * v[:, :, k].mean(axis=1), n)
                      for k in (0, 1)], axis=1)
    centre = first / area[:, None]
    # second moment about the body's centroid: for a triangle,
    # int x x^T dA = A / 12 (sum_i v_i v_i^T + s s^T), s = sum_i v_i
    local = v - centre[body][:, None, :]
    s = local.sum(axis=1)
    moment = (np.einsum("mia,mib->mab", local, local)
              + np.einsum("ma,mb->mab", s, s)) * (signed / 12)[:, None, None]
    J = np.stack([np.bincount(body, moment[:, a, b], n)
                  for a, b in ((0, 0), (1, 1), (0, 1))], axis=1)
    mean = 0.5 * (J[:, 0] + J[:, 1])
    half = np.hypot(0.5 * (J[:, 0] - J[:, 1]), J[:, 2])
    orientation = np.mod(0.5 * np.arctan2(2 * J[:, 2], J[:, 0] - J[:, 1]),
                         math.pi)
    orientation[half <= ISOTROPIC * mean] = np.nan
    out = {"body": np.arange(n), "area": np.abs(area), "x": centre[:, 0],
           "y": centre[:, 1], "orientation": orientation,
           "elongation": np.sqrt((mean + half) / (mean - half)),
           "asphericity": _perimeter(p, cells, body, n) ** 2
           / (4 * math.pi * np.abs(area))}
    if reference is not None:
        out["rotation"] = _rotation(np.asarray(reference, float)[:, :2], p,
                                    cells, body, n)
    return out


def _rotation(reference, current, cells, body, n) -> np.ndarray:
    """The polar rotation angle of each body's mean deformation gradient
    F = (1 / A0) sum_t A0_t F_t (P1: F_t maps the triangle's reference
    edges to its current ones): for F = R(theta) U, U symmetric,
    theta = atan2(F21 - F12, F11 + F22)."""
    X, x = reference[cells], current[cells]
    dX = np.stack([X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]], axis=2)
    dx = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=2)
    F = dx @ np.linalg.inv(dX)
    area0 = 0.5 * np.abs(np.linalg.det(dX))
    mean = np.stack([np.bincount(body, area0 * F[:, i, j], n)
                     for i, j in ((0, 0), (0, 1), (1, 0), (1, 1))], axis=1)
    return np.arctan2(mean[:, 2] - mean[:, 1], mean[:, 0] + mean[:, 3])


def _perimeter(points, cells, body, n) -> np.ndarray:
    """Length of each body's boundary: the edges of one triangle only."""
    edges = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]],
                            cells[:, [2, 0]]])
    owner = np.tile(body, 3)
    key = np.sort(edges, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True,
                                 return_counts=True)
    outer = first[counts == 1]
    length = np.linalg.norm(points[edges[outer, 1]] - points[edges[outer, 0]],
                            axis=1)
    return np.bincount(owner[outer], length, n)


def shapes_at(fields_h5, time) -> dict:
    """:func:`particle_shapes` of the stored time of ``fields.h5`` nearest
    ``time`` (s); the dict also holds ``time``, the time read."""
    from softpack.analysis.fields import read_snapshot

    snap = read_snapshot(fields_h5, time)
    if snap.body is None:
        raise KeyError(f"{fields_h5}: no particle field (the body of each"
                       " cell)")
    out = particle_shapes(snap.current, snap.cells, snap.body, snap.points)
    out["time"] = snap.time
    return out
