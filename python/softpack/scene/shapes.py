"""Particle shapes: one triangulation per distinct shape and size.

A species' ``shape`` (docs/parameters.md, ``[[species]]``) and a particle's
diameter D give a :class:`Template`: linear triangles centred on the shape's
centre, meshed once by gmsh at the run's element size and then copied
(rotated, translated) to every particle of that shape and size
(:mod:`softpack.scene.mesh`).

``diameter`` has one meaning for every shape: the diameter of the circle of
EQUAL AREA, so the shape's area is pi D^2 / 4 (the exact shape's for disk,
polygon and ellipse; the meshed polygon's for .geo and .msh files, which are
scaled to it). The placement uses each template's bounding radius (the
largest distance of a node from the centre).

Shapes:

``disk``      ``meshes/disk.geo`` with ``Parameters/radius`` = D / 2.
``polygon``   ``meshes/polygon.geo``: a regular polygon of ``sides`` sides,
              corners rounded with ``corner_radius`` (apothem computed from
              the area).
``ellipse``   ``meshes/ellipse.geo``: semi-axes a = k b along x, b along y,
              k = ``aspect_ratio``, a b = (D / 2)^2.
``geo``       a user's gmsh geometry (one plane surface), meshed in its own
              units at element size h / s and scaled by s so that its meshed
              area is pi D^2 / 4, centred on its area centroid.
``msh``       a user's gmsh mesh of one particle: its triangles, scaled and
              centred the same way (the element size is the file's).

(User files: :mod:`softpack.scene.user_shapes`, read in a child process.)

Every template is checked: one connected body bounded by one closed curve,
at least ``MIN_BOUNDARY_ELEMENTS`` boundary edges, no flat triangles, and
(for polygons and ellipses) a meshed area within ``AREA_TOLERANCE`` of the
shape's; a failure is a :class:`ShapeError` naming the species key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.paths import MESHES
from softpack.scene.packing import PackingError

#: Fewest boundary edges of a particle's mesh.
MIN_BOUNDARY_ELEMENTS = 8
#: Meshed area of an exact shape within this fraction of its area.
AREA_TOLERANCE = 0.05
#: Smallest triangle quality 4 sqrt(3) A / (sum of squared edges), in (0, 1].
MIN_QUALITY = 0.1


class ShapeError(PackingError):
    """A particle shape that cannot be meshed; the message names the key.

    A :class:`~softpack.scene.packing.PackingError`, so that the run
    command reports it as a scene failure before anything else is written.
    """


@dataclass(frozen=True)
class Template:
    """One shape at one size, centred at the origin (SI units).

    Attributes
    ----------
    points : ndarray, shape (m, 2)
    triangles : ndarray of int, shape (k, 3)
        Counter-clockwise.
    area : float
        Area of the meshed polygon (m^2).
    bounding_radius : float
        Largest distance of a node from the origin (m).
    """

    points: np.ndarray
    triangles: np.ndarray
    area: float
    bounding_radius: float


def shape_key(spec, diameter) -> tuple:
    """What makes two particles' meshes the same: shape, its keys, size."""
    shape = spec["shape"]
    extra = {"polygon": ("sides", "corner_radius"), "ellipse": ("aspect_ratio",),
             "geo": ("file",), "msh": ("file",)}.get(shape, ())
    return (shape, *(spec[k] for k in extra), float(diameter))


def exact_area(diameter) -> float:
    """The area of every shape of equal-area diameter D (m^2)."""
    return math.pi * float(diameter) ** 2 / 4


def polygon_size(sides, corner_radius, diameter) -> tuple[float, float]:
    """Apothem and bounding radius of a rounded regular polygon of area
    pi D^2 / 4.

    The rounded polygon is the sharp polygon of apothem ``a' = a - rc``
    offset by ``rc``: its area is ``n t a'^2 + 2 n t rc a' + pi rc^2``
    with ``t = tan(pi / n)`` (Steiner's formula).

    Raises
    ------
    ValueError
        When ``rc >= D / 2``: no polygon is left inside the corners.
    """
    n, rc = int(sides), float(corner_radius)
    t = math.tan(math.pi / n)
    residual = exact_area(diameter) - math.pi * rc ** 2
    if residual <= 0:
        raise ValueError(f"must be < D / 2 = {diameter / 2:g} m (the"
                         " rounded corners would leave no polygon)")
    inner = (-rc + math.sqrt(rc ** 2 + residual / (n * t)))  # a' >= 0 root
    return inner + rc, inner / math.cos(math.pi / n) + rc


def ellipse_axes(aspect_ratio, diameter) -> tuple[float, float]:
    """Semi-axes ``(a, b)``, ``a = k b``, of the ellipse of area pi D^2/4."""
    b = float(diameter) / (2 * math.sqrt(float(aspect_ratio)))
    return float(aspect_ratio) * b, b


def shape_file(shape: str = "disk") -> Path:
    """The gmsh geometry of a built-in shape: ``meshes/SHAPE.geo``."""
    path = MESHES / f"{shape}.geo"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no geometry for the particle shape"
                                f" {shape!r} (meshes/README.md)")
    return path


def templates(species, diameters, index, element_size, base=None) -> dict:
    """Mesh every distinct (shape, size) of a scene once.

    Parameters
    ----------
    species : list of dict
        ``config["species"]``.
    diameters, index : ndarray, shape (n,)
        Each particle's diameter (m) and species index.
    element_size : float
        The run's element size h (m).
    base : path-like, optional
        Directory of the run's TOML file (relative ``file`` keys).

    Returns
    -------
    dict
        :func:`shape_key` -> :class:`Template`.
    """
    import gmsh

    from softpack.scene.mesh import initialize_gmsh

    wanted = {}
    for d, s in zip(np.asarray(diameters, float).tolist(),
                    np.asarray(index).tolist()):
        wanted.setdefault(shape_key(species[s], d), (s, d))
    initialize_gmsh(gmsh)
    gmsh.logger.start()
    try:
        return {key: _template(gmsh, species[s], s, d, float(element_size),
                               base)
                for key, (s, d) in wanted.items()}
    finally:
        gmsh.logger.stop()
        gmsh.finalize()


def _template(gmsh, spec, s, diameter, h, base) -> Template:
    """One shape at one size (see the module doc)."""
    where = f"[species.{s}] (species {spec['name']!r}, D = {diameter:g} m)"
    shape = spec["shape"]
    exact = True
    try:
        if shape == "disk":
            points, triangles = mesh_geometry(
                gmsh, shape_file("disk"), {"radius": diameter / 2}, h)
        elif shape == "polygon":
            try:
                apothem, _ = polygon_size(spec["sides"], spec["corner_radius"],
                                          diameter)
            except ValueError as err:
                raise ShapeError(f"{where} corner_radius ="
                                 f" {spec['corner_radius']!r}: {err}") from None
            points, triangles = mesh_geometry(
                gmsh, shape_file("polygon"),
                {"sides": spec["sides"], "apothem": apothem,
                 "corner_radius": spec["corner_radius"]}, h)
        elif shape == "ellipse":
            a, b = ellipse_axes(spec["aspect_ratio"], diameter)
            points, triangles = mesh_geometry(
                gmsh, shape_file("ellipse"),
                {"semi_major": a, "semi_minor": b}, h)
        elif shape in ("geo", "msh"):
            exact = False
            from softpack.scene.user_shapes import user_file, user_mesh

            path = user_file(spec, where, base)
            where = f"{where} file = {str(path)!r}"
            points, triangles = user_mesh(shape, path, diameter, h)
        else:
            raise ShapeError(f"{where} shape = {shape!r}: unknown")
    except MeshingError as err:
        raise ShapeError(f"{where}: gmsh could not mesh it at [mesh]"
                         f" element_size = {h!r}: {err}") from None
    # a disk's polygonisation error is bounded by the config's rule (at
    # least MIN_BOUNDARY_ELEMENTS around it), as before shapes existed
    template = checked_template(
        points, triangles, diameter if exact and shape != "disk" else None,
        where, h)
    if shape == "disk":  # its nodes lie on the circle, up to rounding
        template = Template(points=template.points,
                            triangles=template.triangles, area=template.area,
                            bounding_radius=diameter / 2)
    return template


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
    from softpack.scene.mesh import _mesh_options

    for name, value in parameters.items():
        gmsh.onelab.setNumber(f"Parameters/{name}", [float(value)])
    try:
        gmsh.open(str(geometry))  # a new model, the geometry file's
    except Exception as err:  # gmsh raises plain Exception
        raise MeshingError(_gmsh_errors(gmsh, err)) from None
    try:
        _mesh_options(gmsh, element_size)
        surfaces = gmsh.model.getEntities(2)
        if len(surfaces) != 1:
            raise MeshingError(f"{len(surfaces)} plane surfaces, a particle"
                               " is one (a closed curve loop and a Plane"
                               " Surface)")
        try:
            gmsh.model.mesh.generate(2)
        except Exception as err:
            raise MeshingError(_gmsh_errors(gmsh, err)) from None
        return _oriented(*_surface_mesh(gmsh, surfaces[0][1]))
    finally:
        gmsh.model.remove()


def _gmsh_errors(gmsh, err) -> str:
    """gmsh's logged errors (its exception text is often only the last)."""
    lines = [line for line in gmsh.logger.get() if "rror" in line]
    return "; ".join(lines[-3:]) or str(err)


def _surface_mesh(gmsh, surface):
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


def _oriented(points, triangles):
    """Triangles made counter-clockwise."""
    triangles = triangles.copy()
    flip = _signed_areas(points, triangles) < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    return points, triangles


def _signed_areas(points, triangles) -> np.ndarray:
    """Signed areas of triangles; positive when counter-clockwise."""
    a = points[triangles[:, 1]] - points[triangles[:, 0]]
    b = points[triangles[:, 2]] - points[triangles[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def _polygon_area(points, triangles) -> float:
    """Area of a triangulation (orientation ignored)."""
    return float(np.abs(_signed_areas(points, triangles)).sum())


def _centred(points, triangles) -> np.ndarray:
    """Points moved so that the area centroid is at the origin."""
    areas = np.abs(_signed_areas(points, triangles))
    centroids = points[triangles].mean(axis=1)
    return points - (areas[:, None] * centroids).sum(axis=0) / areas.sum()


def boundary_loops(triangles) -> list:
    """The closed boundary curves of a triangulation, as node lists.

    Boundary edges are those of one triangle only; each loop follows them
    from node to node. A node on two loops (two bodies touching at a point)
    makes the walk ambiguous and is reported as a separate loop.
    """
    edges = np.sort(np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]],
                               triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = unique[counts == 1]
    neighbours = {}
    for a, b in boundary.tolist():
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    seen, loops = set(), []
    for start in neighbours:
        if start in seen:
            continue
        loop, previous, node = [start], None, start
        seen.add(start)
        while True:
            options = [m for m in neighbours[node] if m != previous]
            if not options or options[0] == start or options[0] in seen:
                break
            previous, node = node, options[0]
            seen.add(node)
            loop.append(node)
        loops.append(loop)
    if any(len(v) != 2 for v in neighbours.values()):
        loops.append([])  # a pinched boundary: not one simple curve
    return loops


def checked_template(points, triangles, diameter, where, h) -> Template:
    """A :class:`Template` once the mesh passed the checks of the module
    doc (``diameter`` None: no exact area to compare with).

    Raises
    ------
    ShapeError
    """
    points, triangles = _oriented(np.asarray(points, float),
                                  np.asarray(triangles, np.int64))
    loops = boundary_loops(triangles)
    if len(loops) != 1:
        raise ShapeError(f"{where}: the mesh is bounded by {len(loops)}"
                         " curves; a particle is one body inside one closed"
                         " curve (no holes, one piece)")
    if len(loops[0]) < MIN_BOUNDARY_ELEMENTS:
        raise ShapeError(f"{where}: {len(loops[0])} boundary elements at"
                         f" [mesh] element_size = {h!r}, fewer than"
                         f" {MIN_BOUNDARY_ELEMENTS}: the element size is too"
                         " large for this shape")
    areas = _signed_areas(points, triangles)
    edges = points[triangles] - points[np.roll(triangles, 1, axis=1)]
    quality = 4 * math.sqrt(3) * areas / (edges ** 2).sum(axis=(1, 2))
    if quality.min() < MIN_QUALITY:
        raise ShapeError(f"{where}: triangles of quality {quality.min():.3f}"
                         f" < {MIN_QUALITY} at [mesh] element_size = {h!r}:"
                         " the shape has features thinner than the elements")
    area = float(areas.sum())
    if diameter is not None and abs(area / exact_area(diameter) - 1) \
            > AREA_TOLERANCE:
        raise ShapeError(f"{where}: meshed area {area:.4g} m^2 differs from"
                         f" the shape's {exact_area(diameter):.4g} m^2 by more"
                         f" than {AREA_TOLERANCE:.0%} at [mesh] element_size"
                         f" = {h!r}: the element size is too large for it")
    radius = float(np.linalg.norm(points, axis=1).max())
    return Template(points=points, triangles=triangles, area=area,
                    bounding_radius=radius)


def rotated(points, angle) -> np.ndarray:
    """Points rotated counter-clockwise by ``angle`` (rad) about the
    origin."""
    c, s = math.cos(angle), math.sin(angle)
    return points @ np.array([[c, s], [-s, c]])
