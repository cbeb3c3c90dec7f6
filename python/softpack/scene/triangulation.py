"""gmsh and linear triangles: the session, one geometry meshed, their areas.

What the scene's meshing needs below the particle shapes
(:mod:`softpack.scene.shapes`), the one mesh of a run
(:mod:`softpack.scene.mesh`) and a user's shape files
(:mod:`softpack.scene.user_shapes`): a gmsh session that writes nothing
outside the run (:func:`initialize_gmsh`), a ``.geo`` file meshed with its
ONELAB parameters at one element size (:func:`mesh_geometry`), and the
triangles' signed areas, orientation and centroid.
"""

from __future__ import annotations

import numpy as np


def initialize_gmsh(gmsh) -> None:
    """``gmsh.initialize`` that writes nothing outside the run (issue 16).

    gmsh's option defaults set FLTK's tooltip option, and FLTK then reads
    and rewrites its preference files, ``/etc/fltk/fltk.org/fltk.prefs``
    and ``~/.fltk/fltk.org/fltk.prefs``, even without a GUI and with
    ``readConfigFiles=False``. FLTK reads them only once per process (flag
    ``Fl::options_read_``): setting the flag first leaves both untouched.
    """
    import ctypes

    try:
        fltk = ctypes.CDLL("libfltk.so.1.3")
        ctypes.c_bool.in_dll(fltk, "_ZN2Fl13options_read_E").value = True
    except (OSError, ValueError):
        pass  # a gmsh built without FLTK writes no preferences
    gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)


def mesh_options(gmsh, element_size) -> None:
    """One absolute element size, Frontal-Delaunay, linear triangles."""
    for name, value in (("Mesh.MeshSizeMin", element_size),
                        ("Mesh.MeshSizeMax", element_size),
                        ("Mesh.MeshSizeFromPoints", 0),
                        ("Mesh.MeshSizeFromCurvature", 0),
                        ("Mesh.MeshSizeExtendFromBoundary", 0),
                        ("Mesh.Algorithm", 6),  # Frontal-Delaunay
                        ("Mesh.ElementOrder", 1)):
        gmsh.option.setNumber(name, value)


def signed_areas(points, triangles) -> np.ndarray:
    """Signed areas of triangles; positive when counter-clockwise."""
    p = np.asarray(points)[:, :2]
    a = p[triangles[:, 1]] - p[triangles[:, 0]]
    b = p[triangles[:, 2]] - p[triangles[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


class MeshingError(RuntimeError):
    """gmsh failed or returned something other than one triangulated
    surface."""


def mesh_geometry(gmsh, geometry, parameters, element_size):
    """Mesh a geometry file with ONELAB parameters; points and triangles.

    Raises
    ------
    MeshingError
        When gmsh fails or the file defines other than one plane surface.
    """
    for name, value in parameters.items():
        gmsh.onelab.setNumber(f"Parameters/{name}", [float(value)])
    try:
        gmsh.open(str(geometry))  # a new model, the geometry file's
    except Exception as err:  # gmsh raises plain Exception
        raise MeshingError(gmsh_errors(gmsh, err)) from None
    try:
        mesh_options(gmsh, element_size)
        surfaces = gmsh.model.getEntities(2)
        if len(surfaces) != 1:
            raise MeshingError(f"{len(surfaces)} plane surfaces, a particle"
                               " is one (a closed curve loop and a Plane"
                               " Surface)")
        try:
            gmsh.model.mesh.generate(2)
        except Exception as err:
            raise MeshingError(gmsh_errors(gmsh, err)) from None
        return oriented(*surface_mesh(gmsh, surfaces[0][1]))
    finally:
        gmsh.model.remove()


def gmsh_errors(gmsh, err) -> str:
    """gmsh's logged errors (its exception text is often only the last)."""
    lines = [line for line in gmsh.logger.get() if "rror" in line]
    return "; ".join(lines[-3:]) or str(err)


def surface_mesh(gmsh, surface):
    """Nodes (m, 2) and triangles (k, 3) of one meshed surface (or of all
    surfaces, ``surface = -1``)."""
    tags, coords, _ = gmsh.model.mesh.getNodes(
        2, surface, includeBoundary=True, returnParametricCoord=False)
    types, _, nodes = gmsh.model.mesh.getElements(2, surface)
    if list(types) != [2]:  # gmsh type 2: 3-node triangle
        raise MeshingError(f"element types {list(types)}, expected only"
                           " 3-node triangles")
    return _compact(tags, coords.reshape(-1, 3)[:, :2], nodes[0])


def _compact(tags, points, element_nodes):
    """Local numbering of the nodes the triangles use."""
    tags = np.asarray(tags, dtype=np.int64)
    local = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    local[tags] = np.arange(len(tags))
    triangles = local[np.asarray(element_nodes, dtype=np.int64)].reshape(-1, 3)
    if np.any(triangles < 0):
        raise MeshingError("triangles use unknown nodes")
    used, triangles = np.unique(triangles, return_inverse=True)
    return points[used], triangles.reshape(-1, 3)


def oriented(points, triangles):
    """Triangles made counter-clockwise."""
    triangles = triangles.copy()
    flip = signed_areas(points, triangles) < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    return points, triangles


def polygon_area(points, triangles) -> float:
    """Area of a triangulation (orientation ignored)."""
    return float(np.abs(signed_areas(points, triangles)).sum())


def centred(points, triangles) -> np.ndarray:
    """Points moved so that the area centroid is at the origin."""
    areas = np.abs(signed_areas(points, triangles))
    centroids = points[triangles].mean(axis=1)
    return points - (areas[:, None] * centroids).sum(axis=0) / areas.sum()


