"""The height of standing cylinders (3D runs): the out-of-plane strain
that the 2D plane-strain model sets to zero.

At each stored field, each body's axial strain eps_zz = ln(h / h0), h the
extent in z of its nodes' current positions, h0 that of their reference
positions (the cylinder's height H): its free top rising as the piston
squeezes it in plane (a cylinder whose top bulges at the rim counts its
highest node). Read from the fields alone (:mod:`softpack.analysis.fields`).
"""

from __future__ import annotations

import numpy as np

from softpack.analysis import fields


def axial_strains(fields_h5):
    """The stored times and each body's eps_zz at them.

    Parameters
    ----------
    fields_h5 : path-like
        A 3D run's ``fields.h5``.

    Returns
    -------
    (ndarray, ndarray)
        Times ``(k,)`` (s) and strains ``(k, bodies)``.

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
    node_body = np.empty(len(points), dtype=np.int64)
    node_body[cells] = body[:, None]
    count = int(body.max()) + 1
    rest = _extent(points[:, 2], node_body, count)
    times, strains = [], []
    for time, u in fields.read_displacements(fields_h5, dim=3):
        times.append(time)
        strains.append(np.log(_extent(points[:, 2] + u[:, 2], node_body,
                                      count) / rest))
    return np.array(times), np.array(strains)


def _extent(z, node_body, count) -> np.ndarray:
    """Each body's max z - min z over its nodes."""
    top = np.full(count, -np.inf)
    bottom = np.full(count, np.inf)
    np.maximum.at(top, node_body, z)
    np.minimum.at(bottom, node_body, z)
    return top - bottom
