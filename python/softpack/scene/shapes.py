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
from softpack.scene.triangulation import (MeshingError, initialize_gmsh,
                                          mesh_geometry, oriented,
                                          signed_areas)

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


def user_file(spec, where, base=None) -> Path:
    """The ``file`` of a geo/msh species: as given, next to the TOML file
    (``base``), then in ``meshes/``.

    Raises
    ------
    ShapeError
        When it is not found or has the wrong suffix.
    """
    name = spec["file"]
    suffix = "." + spec["shape"]
    if not name:
        raise ShapeError(f"{where} file: missing; shape = {spec['shape']!r}"
                         f" needs a gmsh {suffix} file")
    path = Path(name).expanduser()
    tried = [path] if path.is_absolute() else [
        *([Path(base) / path] if base is not None else []), path,
        MESHES / path]
    for candidate in tried:
        if candidate.is_file():
            if candidate.suffix.lower() != suffix:
                raise ShapeError(f"{where} file = {name!r}: shape ="
                                 f" {spec['shape']!r} needs a {suffix} file")
            return candidate.resolve()
    raise ShapeError(f"{where} file = {name!r}: not found (looked in: "
                     + ", ".join(str(p) for p in tried) + ")")


def templates(species, diameters, index, element_size, base=None,
              known=None) -> dict:
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
    known : dict, optional
        Templates meshed already (a result of this function): reused.

    Returns
    -------
    dict
        :func:`shape_key` -> :class:`Template`.
    """
    import gmsh

    made = dict(known or {})
    wanted = {}
    for d, s in zip(np.asarray(diameters, float).tolist(),
                    np.asarray(index).tolist()):
        key = shape_key(species[s], d)
        if key not in made:
            wanted.setdefault(key, (s, d))
    if not wanted:
        return made
    initialize_gmsh(gmsh)
    gmsh.logger.start()
    try:
        made.update({key: _template(gmsh, species[s], s, d,
                                    float(element_size), base)
                     for key, (s, d) in wanted.items()})
        return made
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
            from softpack.scene.user_shapes import user_mesh

            path = user_file(spec, where, base)
            where = f"{where} file = {str(path)!r}"
            if shape == "msh" and _holds_tetrahedra(path):
                raise ShapeError(f"{where}: a 3D solid (tetrahedra) in a 2D"
                                 " scene ([model] dimension = 2): give its"
                                 " triangles, or set [model] dimension = 3")
            points, triangles = user_mesh(shape, path, exact_area(diameter),
                                          h)
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


def _holds_tetrahedra(path) -> bool:
    """Whether a gmsh mesh file holds tetrahedra (meshio reads it; a file
    meshio cannot read is left to gmsh, whose message is then the one)."""
    try:
        import meshio

        return any(c.type == "tetra" for c in meshio.read(str(path)).cells)
    except Exception:  # meshio raises many kinds on files it cannot read
        return False


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
    points, triangles = oriented(np.asarray(points, float),
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
    areas = signed_areas(points, triangles)
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
