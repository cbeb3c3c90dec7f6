"""The height of standing cylinders (3D runs): the out-of-plane strain
that the 2D plane-strain model sets to zero, and their lift off the base.

At each stored field, each body's axial strain eps_zz = ln(h / h0), h the
mean height of its top face's nodes over the mean height of its bottom
face's (the nodes at its highest and lowest reference z), h0 the same in
the reference configuration (the cylinder's height H): its free top rising
as the piston squeezes it in plane, a tilt of a few degrees changing h by
its cosine only; and its lift, the mean height of its bottom face's nodes
above their reference height (0 while it stands on the base). Read from
the fields alone (:mod:`softpack.analysis.fields`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softpack.analysis import fields


@dataclass(frozen=True)
class Standing:
    """Per stored field (rows) and body (columns)."""

    #: stored times (s), ``(k,)``
    times: np.ndarray
    #: eps_zz = ln(h / h0), ``(k, bodies)``
    axial: np.ndarray
    #: the bottom face's mean height above its rest (m), ``(k, bodies)``
    lift: np.ndarray


def standing(fields_h5) -> Standing:
    """Each body's axial strain and lift at the stored fields.

    Parameters
    ----------
    fields_h5 : path-like
        A 3D run's ``fields.h5``.

    Raises
    ------
    ValueError
        For a 2D run's fields (no height) or fields without body ids.
    KeyError
        When the file holds no displacement.
    """
    points, cells = fields.read_mesh(fields_h5)
    if points.shape[1] != 3:
        raise ValueError(f"{fields_h5}: a 2D run's fields have no height")
    first = fields.stored_times(fields_h5)[0]
    body = fields.read_snapshot(fields_h5, first).body
    if body is None:
        raise ValueError(f"{fields_h5}: no body ids (particle) stored")
    node_body = np.full(len(points), -1, dtype=np.int64)
    node_body[cells] = body[:, None]
    count = int(body.max()) + 1
    bottom, top = _faces(points[:, 2], node_body, count)
    rest_bottom = _mean(points[:, 2], bottom, count)
    rest = _mean(points[:, 2], top, count) - rest_bottom
    times, axial, lift = [], [], []
    for time, u in fields.read_displacements(fields_h5, dim=3):
        z = points[:, 2] + u[:, 2]
        low = _mean(z, bottom, count)
        times.append(time)
        axial.append(np.log((_mean(z, top, count) - low) / rest))
        lift.append(low - rest_bottom)
    return Standing(np.array(times), np.array(axial), np.array(lift))


def _faces(z, node_body, count):
    """(body, node) index pairs of each body's lowest and highest
    reference nodes (its bottom and top faces)."""
    low = np.full(count, np.inf)
    high = np.full(count, -np.inf)
    used = node_body >= 0
    np.minimum.at(low, node_body[used], z[used])
    np.maximum.at(high, node_body[used], z[used])
    nodes = np.flatnonzero(used)
    b = node_body[nodes]
    tol = 1e-9 * (high - low)[b]
    return ((b[np.abs(z[nodes] - low[b]) <= tol],
             nodes[np.abs(z[nodes] - low[b]) <= tol]),
            (b[np.abs(z[nodes] - high[b]) <= tol],
             nodes[np.abs(z[nodes] - high[b]) <= tol]))


def _mean(z, face, count) -> np.ndarray:
    """Each body's mean z over the nodes of ``face``."""
    b, nodes = face
    return np.bincount(b, z[nodes], count) / np.bincount(b, None, count)
