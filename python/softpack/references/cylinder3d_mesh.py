"""The mesh of the 3D cylinder reference: an eighth of a cylinder (gmsh).

Quadratic tetrahedra of an eighth of a unit-radius cylinder (its three
symmetry planes, the end and the curved surface tagged), refined near the
contact line; :mod:`softpack.references.cylinder3d` solves on it.
"""

from __future__ import annotations

import math

import numpy as np

#: Physical surface tags of the eighth cylinder.
TAG_X0, TAG_Y0, TAG_Z0, TAG_END, TAG_CURVED = 1, 2, 3, 4, 5


def build_mesh(half_length, element_size, comm=None):
    """Eighth of a unit-radius cylinder as quadratic tetrahedra (gmsh, OCC).

    Lengths in units of R. The size is element_size within 0.5 of the contact
    line (x = 0, y = 1) and grows to 2 element_size beyond distance 1.
    Returns (mesh, facet_tags). Opens and closes its own gmsh session (do not
    call it while another gmsh session is in use in the same process).
    """
    import gmsh
    from mpi4py import MPI
    from dolfinx.io import gmshio

    from softpack.scene.triangulation import initialize_gmsh

    comm = MPI.COMM_WORLD if comm is None else comm
    initialize_gmsh(gmsh)
    try:
        gmsh.model.add("cylinder_eighth")
        vol = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, half_length, 1.0,
                                         angle=math.pi / 2)
        gmsh.model.occ.synchronize()
        _tag_surfaces(gmsh, vol)
        _size_field(gmsh, element_size)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        mesh, _, facets = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3)
    finally:
        gmsh.finalize()
    return mesh, facets


def _tag_surfaces(gmsh, vol):
    gmsh.model.addPhysicalGroup(3, [vol], 1)
    groups = {}
    for dim, tag in gmsh.model.getBoundary([(3, vol)], oriented=False):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        if x1 - x0 < 1e-6 and abs(x0) < 1e-6:
            key = TAG_X0
        elif y1 - y0 < 1e-6 and abs(y0) < 1e-6:
            key = TAG_Y0
        elif z1 - z0 < 1e-6:
            key = TAG_Z0 if abs(z0) < 1e-6 else TAG_END
        else:
            key = TAG_CURVED
        groups.setdefault(key, []).append(tag)
    if sorted(groups) != [TAG_X0, TAG_Y0, TAG_Z0, TAG_END, TAG_CURVED]:
        raise RuntimeError(f"unexpected boundary of the eighth cylinder: {groups}")
    for key, tags in groups.items():
        gmsh.model.addPhysicalGroup(2, tags, key)


def _size_field(gmsh, h):
    """Size h near the contact line x = 0, y = 1, up to 2h far from it."""
    lines = [tag for dim, tag in gmsh.model.getEntities(1)
             if np.allclose(gmsh.model.getBoundingBox(dim, tag)[:2], (0.0, 1.0), atol=1e-6)
             and np.allclose(gmsh.model.getBoundingBox(dim, tag)[3:5], (0.0, 1.0), atol=1e-6)]
    if len(lines) != 1:
        raise RuntimeError(f"contact line not found: {lines}")
    fm = gmsh.model.mesh.field
    dist = fm.add("Distance")
    fm.setNumbers(dist, "CurvesList", lines)
    fm.setNumber(dist, "NumPointsPerCurve", 100)
    thr = fm.add("Threshold")
    fm.setNumber(thr, "InField", dist)
    for key, val in (("SizeMin", h), ("SizeMax", 2 * h), ("DistMin", 0.5), ("DistMax", 1.0)):
        fm.setNumber(thr, key, val)
    fm.setAsBackgroundMesh(thr)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber("Mesh." + opt, 0)
