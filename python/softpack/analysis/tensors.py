"""Second-order tensors of the observables in 2D and 3D: their component
names in the CSV files and the scalar size of their deviator.

One definition for both dimensions: a d x d tensor T (d = 2 or 3) is
written as columns ``PREFIX_ij`` (i, j in x, y[, z]), and its deviator
T' = T - tr(T) I / d has the size

    |T'|_d = sqrt(c_d T':T'),  c_2 = 1/2,  c_3 = 3/2,

of the symmetric part of T: in 2D the largest eigenvalue of T' (for a
stress the maximum shear stress sqrt(((xx - yy) / 2)^2 + xy^2)), in 3D the
von Mises size sqrt(3/2 s:s) (for a stress the deviator q of soil
mechanics; for an axisymmetric T, |T_1 - T_3|). The stress's q and the
fabric's anisotropy are this size (:mod:`softpack.analysis.stress`,
:func:`softpack.analysis.network.fabric`).
"""

from __future__ import annotations

import numpy as np

AXES = "xyz"


def axes(dimension: int) -> str:
    """The axes of a run of that dimension: ``"xy"`` or ``"xyz"``."""
    if dimension not in (2, 3):
        raise ValueError(f"dimension must be 2 or 3, got {dimension!r}")
    return AXES[:dimension]


def components(dimension: int) -> tuple:
    """The d x d components in row-major order (``xx, xy, yx, yy`` in 2D;
    ``xx, xy, xz, yx, ..., zz`` in 3D): the order of ``M.flat``."""
    a = axes(dimension)
    return tuple(i + j for i in a for j in a)


def symmetric_components(dimension: int) -> tuple:
    """The independent components of a symmetric tensor: ``xx, yy, xy`` in
    2D, ``xx, yy, zz, xy, xz, yz`` in 3D."""
    a = axes(dimension)
    return (tuple(i + i for i in a)
            + tuple(a[i] + a[j] for i in range(len(a))
                    for j in range(i + 1, len(a))))


def stack(columns: dict, dimension: int) -> np.ndarray:
    """Tensors ``(rows, d, d)`` from the columns ``ij`` of ``columns``;
    a symmetric tensor's missing ``ji`` is its ``ij``."""
    a = axes(dimension)
    first = np.asarray(columns[a[0] * 2], dtype=float)
    out = np.empty(first.shape + (len(a), len(a)))
    for i, p in enumerate(a):
        for j, q in enumerate(a):
            key = p + q if p + q in columns else q + p
            out[..., i, j] = columns[key]
    return out


def trace_mean(tensors: np.ndarray) -> np.ndarray:
    """tr(T) / d of each tensor ``(..., d, d)`` (the mean normal value: a
    stress's pressure)."""
    d = tensors.shape[-1]
    return np.trace(tensors, axis1=-2, axis2=-1) / d


def deviator_size(tensors: np.ndarray) -> np.ndarray:
    """|T'|_d (module doc) of the symmetric part of each ``(..., d, d)``.

    The 2D case is written in closed form, hypot((T_xx - T_yy) / 2,
    (T_xy + T_yx) / 2): the same number, and the same bits as the 2D
    observables before 3D existed.
    """
    t = np.asarray(tensors, dtype=float)
    d = t.shape[-1]
    if d == 2:
        shear = 0.5 * (t[..., 0, 1] + t[..., 1, 0])
        return np.hypot(0.5 * (t[..., 0, 0] - t[..., 1, 1]), shear)
    sym = 0.5 * (t + np.swapaxes(t, -1, -2))
    dev = sym - trace_mean(sym)[..., None, None] * np.eye(d)
    return np.sqrt(1.5 * np.sum(dev * dev, axis=(-2, -1)))
