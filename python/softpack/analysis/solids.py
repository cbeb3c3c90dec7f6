"""The packing fractions of 3D scenes (tetrahedral bodies in a box).

Two measures of how full a 3D box is (issue 40, item 3):

- the volume fraction Phi = (sum of the bodies' volumes) / (L W H_box),
  the 3D meaning of the packing fraction (the driver's, from the boundary
  faces by the divergence theorem; here from the tetrahedra, an
  independent sum);
- for cylinders standing on the base z = 0, the area fraction of their
  bottom faces, (sum of the areas of the boundary faces lying on the base)
  / (L W): what the experiment's scanner saw through the glass plate, and
  the packing fraction of the 2D model of the same cylinders.

Every function takes the nodes' coordinates (reference or current: X + u)
with the tetrahedra and each tetrahedron's body, as the scene's mesh and
fields.h5 hold them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softpack.scene.solids import signed_volumes

#: A boundary face lies on the base when its three nodes are within this
#: distance of z = 0 (m): the scene stands its cylinders on z = 0 exactly
#: (up to rounding); a deformed state's caller passes its own (e.g. the
#: contact's alert distance).
BASE_TOLERANCE = 1e-9


def body_volumes(points, tets, body) -> np.ndarray:
    """Each body's volume (m^3), bodies numbered 0..max(body)."""
    body = np.asarray(body, dtype=int).reshape(-1)
    return np.bincount(body, signed_volumes(points, tets))


def boundary_faces(tets, body=None):
    """The faces of the tetrahedra that belong to one tetrahedron only,
    oriented so that (b - a) x (c - a) points out of positively oriented
    tetrahedra, and (with ``body``) each face's body.

    Returns
    -------
    faces : ndarray, shape (m, 3)
    face_body : ndarray, shape (m,) (only with ``body``)
    """
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    # the faces of (a, b, c, d) seen from outside: (a c b), (a b d), (a d c),
    # (b c d)
    local = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    faces = tets[:, local].reshape(-1, 3)
    key = np.sort(faces, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True,
                                return_counts=True)
    once = np.sort(first[count == 1])
    if body is None:
        return faces[once]
    owner = np.repeat(np.asarray(body, dtype=int).reshape(-1), 4)
    return faces[once], owner[once]


def face_areas(points, faces) -> np.ndarray:
    """Areas of triangles."""
    p = np.asarray(points, dtype=float)[np.asarray(faces)]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                                axis=1)


def base_areas(points, tets, body, tolerance=BASE_TOLERANCE) -> np.ndarray:
    """Each body's area on the base: the sum of its boundary faces whose
    three nodes lie within ``tolerance`` of z = 0 (m^2; bodies numbered
    0..max(body))."""
    points = np.asarray(points, dtype=float)
    faces, owner = boundary_faces(tets, body)
    on_base = np.all(np.abs(points[faces][:, :, 2]) <= tolerance, axis=1)
    n = int(np.max(body)) + 1
    return np.bincount(owner[on_base], face_areas(points, faces[on_base]),
                       minlength=n)


def phi_base(reference, current, tets, body, extent) -> float:
    """The base area fraction of a deformed state, as a 3D run's
    ``phi_base`` column (``driver/simulation/box_3d.h``,
    ``base_area_fraction``): the boundary faces on the base in the
    ``reference`` configuration (three nodes within BASE_TOLERANCE of z =
    0: the bottom faces), projected on the base plane in the ``current``
    one, over the box's plan L W (``extent``'s first two edges, the walls'
    current distances). A face lifted off the base still counts: what the
    experiment's scanner saw of the bottom faces through the glass."""
    reference = np.asarray(reference, dtype=float)
    current = np.asarray(current, dtype=float)
    faces, _ = boundary_faces(tets, body)
    on_base = np.all(np.abs(reference[faces][:, :, 2]) <= BASE_TOLERANCE,
                     axis=1)
    p = current[faces[on_base]]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    # outward normal -z: the projected area is -(e1 x e2)_z / 2
    area = -0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    return float(area / (float(extent[0]) * float(extent[1])))


def volume_fraction(points, tets, body, extent) -> float:
    """Phi = (sum of the bodies' volumes) / (L W H_box), ``extent`` the
    box's three edges (m)."""
    length, width, height = (float(e) for e in extent)
    return float(body_volumes(points, tets, body).sum()
                 / (length * width * height))


def base_area_fraction(points, tets, body, extent,
                       tolerance=BASE_TOLERANCE) -> float:
    """(sum of the bodies' areas on the base) / (L W): the bottom faces'
    area fraction of cylinders standing on z = 0 (``extent``: the box's
    edges, its first two used)."""
    length, width = float(extent[0]), float(extent[1])
    return float(base_areas(points, tets, body, tolerance).sum()
                 / (length * width))


def read_scene_mesh(xdmf):
    """The nodes, tetrahedra and body tags of a 3D scene's mesh
    (``STEM.xdmf``: its ``.h5`` beside it, the layout of
    :func:`softpack.scene.mesh.write_xdmf`)."""
    import h5py

    with h5py.File(Path(xdmf).with_suffix(".h5"), "r") as f:
        return (f["Mesh/mesh/geometry"][()], f["Mesh/mesh/topology"][()],
                f["MeshTags/bodies/Values"][()].reshape(-1))


def scene_fractions(xdmf, extent) -> dict:
    """The initial ``volume_fraction`` and ``base_area_fraction`` of a 3D
    scene's mesh in the box of edges ``extent``."""
    points, tets, body = read_scene_mesh(xdmf)
    return {"volume_fraction": volume_fraction(points, tets, body, extent),
            "base_area_fraction": base_area_fraction(points, tets, body,
                                                     extent)}


def scene_summary(xdmf, extent, seed) -> str:
    """A 3D scene's line for the run's log: bodies, tetrahedra, the volume
    fraction and the bottom faces' area fraction."""
    points, tets, body = read_scene_mesh(xdmf)
    return (f"3D scene: {int(body.max()) + 1} bodies, seed {seed}, Phi0 ="
            f" {volume_fraction(points, tets, body, extent):.4f} (volume"
            f" fraction), bottom faces on the base"
            f" {base_area_fraction(points, tets, body, extent):.4f} of its"
            f" area; mesh: {len(tets)} tetrahedra")


def fractions_at(fields_h5, time, extent, tolerance=BASE_TOLERANCE) -> dict:
    """The ``volume_fraction``, ``base_area_fraction`` (the faces on the
    base now, within ``tolerance``) and ``phi_base`` (the bottom faces of
    the reference configuration projected on the base, the run's column)
    of a 3D run's fields (``DIR/fields.h5``) at the stored time nearest
    ``time``, on the current coordinates X + u (the box's ``extent`` at
    that time)."""
    from softpack.analysis.fields import read_snapshot

    snap = read_snapshot(fields_h5, time)
    if snap.cells.shape[1] != 4:
        raise ValueError(f"{fields_h5}: not a mesh of tetrahedra")
    x = snap.current
    return {"time": snap.time,
            "phi_base": phi_base(snap.points, x, snap.cells, snap.body,
                                 extent),
            "volume_fraction": volume_fraction(x, snap.cells, snap.body,
                                               extent),
            "base_area_fraction": base_area_fraction(
                x, snap.cells, snap.body, extent, tolerance)}
