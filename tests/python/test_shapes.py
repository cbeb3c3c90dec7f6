"""Particle shapes: sizes from the equal-area diameter, meshes, bad input."""

import math

import numpy as np
import pytest

import softpack.scene.mesh as mesh_module
from softpack.scene import shapes, triangulation
from softpack.scene.shapes import ShapeError

D, H = 0.02, 1.065e-3


def spec(shape, **keys):
    """A [[species]] table with the schema's defaults for the shape keys."""
    return {"name": "s", "shape": shape, "diameter": D, "count": 1,
            "sides": 5, "corner_radius": 0.0, "aspect_ratio": 2.0,
            "file": "", "orientation": "random", "angle": 0.0, **keys}


def template(table, h=H, base=None, diameter=D):
    """The one template of one species."""
    out = shapes.templates([table], [diameter], [0], h, base)
    return out[shapes.shape_key(table, diameter)]


def boundary_points(t):
    """Coordinates of the boundary loop's nodes, in loop order."""
    (loop,) = shapes.boundary_loops(t.triangles)
    return t.points[loop]


def shoelace(xy):
    """Area of a closed polygon given by its vertices."""
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def rounded_polygon_outline(n, rc, apothem, m=20000):
    """Dense outline of the rounded regular polygon, built independently:
    each boundary point is the farthest point in its direction of the
    inner polygon's vertices offset by rc (support function)."""
    inner = (apothem - rc) / math.cos(math.pi / n)
    t = math.pi / 2 + 2 * math.pi * np.arange(n) / n
    vertices = inner * np.stack([np.cos(t), np.sin(t)], axis=1)
    phi = np.linspace(0, 2 * math.pi, m, endpoint=False)
    normals = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    best = np.argmax(normals @ vertices.T, axis=1)
    return vertices[best] + rc * normals


def segment_distance(points, polygon):
    """Distance of each point to a closed polygon's edges."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    ab = b - a
    ap = points[:, None, :] - a[None]
    t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
    return np.linalg.norm(ap - t[..., None] * ab, axis=2).min(axis=1)


@pytest.mark.parametrize("n, rc", [(3, 0.0), (4, 0.0), (5, 0.0), (5, 2e-3),
                                   (6, 1e-3), (4, 5e-3)])
def test_polygon_size_gives_the_equal_area(n, rc):
    apothem, bounding = shapes.polygon_size(n, rc, D)
    outline = rounded_polygon_outline(n, rc, apothem)
    assert shoelace(outline) == pytest.approx(math.pi * D**2 / 4, rel=1e-6)
    assert np.linalg.norm(outline, axis=1).max() == pytest.approx(
        bounding, rel=1e-6)


def test_corner_radius_must_leave_a_polygon():
    with pytest.raises(ValueError, match="D / 2"):
        shapes.polygon_size(5, D / 2, D)
    with pytest.raises(ShapeError, match=r"\[species.0\].*corner_radius"):
        template(spec("polygon", corner_radius=0.6 * D))


def test_sharp_square_mesh_is_the_square():
    t = template(spec("polygon", sides=4))
    side = math.sqrt(math.pi) * D / 2  # area pi D^2 / 4
    assert t.area == pytest.approx(side**2, rel=1e-12)
    assert t.bounding_radius == pytest.approx(side / math.sqrt(2), rel=1e-12)
    b = boundary_points(t)
    # every boundary node on the square |x| + |y| = side / sqrt(2) (a
    # vertex points along +y: the square is a diamond)
    assert np.allclose(np.abs(b).sum(axis=1), side / math.sqrt(2),
                       atol=1e-12)


def test_rounded_pentagon_nodes_on_its_outline():
    rc = 2e-3
    t = template(spec("polygon", sides=5, corner_radius=rc))
    apothem, bounding = shapes.polygon_size(5, rc, D)
    outline = rounded_polygon_outline(5, rc, apothem)
    distance = segment_distance(boundary_points(t), outline)
    assert distance.max() < 1e-9
    assert t.area == pytest.approx(math.pi * D**2 / 4, rel=2e-3)
    assert t.area < math.pi * D**2 / 4  # chords cut the arcs
    # the mesh's extent: its farthest node, inside the exact shape's
    assert t.bounding_radius == np.linalg.norm(t.points, axis=1).max()
    assert bounding * (1 - 1e-2) < t.bounding_radius <= bounding


def test_ellipse_nodes_on_the_ellipse():
    t = template(spec("ellipse", aspect_ratio=2.5))
    a, b = shapes.ellipse_axes(2.5, D)
    assert a / b == pytest.approx(2.5) and a * b == pytest.approx(D**2 / 4)
    xy = boundary_points(t)
    # measured 2026-12-03: nodes on the ellipse to 3.3e-16, area 1.8e-3
    # below it (the chords)
    assert np.allclose((xy[:, 0] / a)**2 + (xy[:, 1] / b)**2, 1, rtol=0,
                       atol=4e-15)
    assert t.area == pytest.approx(math.pi * a * b, rel=5e-3)
    assert t.bounding_radius == pytest.approx(a, rel=1e-9)


def test_disk_template_is_todays_disk():
    t = template(spec("disk"))
    points, triangles = mesh_module.disk_triangulation([D / 2], H)[D / 2]
    assert np.array_equal(t.points, points)
    assert np.array_equal(t.triangles, triangles)
    assert t.bounding_radius == D / 2


def test_geo_file_scaled_and_centred(tmp_path):
    t = template(spec("geo", file="lshape.geo"))  # found in meshes/
    assert t.area == pytest.approx(math.pi * D**2 / 4, rel=1e-9)
    # the L's area centroid is at (5/6, 5/6) of a unit cell: centred
    centroid = (t.points[t.triangles].mean(axis=1)
                * triangulation.signed_areas(t.points, t.triangles)[:, None]).sum(0)
    assert np.allclose(centroid / t.area, 0, atol=1e-12)
    # six straight sides: the boundary is the L of three squares of side c
    c = math.sqrt(t.area / 3)
    xy = boundary_points(t) + 5 * c / 6
    on_lines = np.minimum.reduce([abs(xy[:, 0]), abs(xy[:, 1]),
                                  abs(xy[:, 0] - c), abs(xy[:, 1] - c),
                                  abs(xy[:, 0] - 2 * c),
                                  abs(xy[:, 1] - 2 * c)])
    assert on_lines.max() < 1e-12
    edges = np.linalg.norm(np.diff(boundary_points(t), axis=0), axis=1)
    assert np.median(edges) == pytest.approx(H, rel=0.2)


def test_geo_file_next_to_the_toml_file(tmp_path):
    (tmp_path / "tri.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {3, 0, 0}; Point(3) = {0, 4, 0};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
        "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};\n")
    t = template(spec("geo", file="tri.geo"), base=tmp_path)
    assert t.area == pytest.approx(math.pi * D**2 / 4, rel=1e-9)


def write_msh(path, geo_text, h):
    """A .msh written by gmsh from a geometry (the user's workflow)."""
    import gmsh
    geo = path.with_suffix(".geo")
    geo.write_text(geo_text)
    triangulation.initialize_gmsh(gmsh)
    try:
        gmsh.open(str(geo))
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(path))
        n = len(gmsh.model.mesh.getElements(2)[1][0])
    finally:
        gmsh.finalize()
    return n


def test_msh_file_keeps_its_triangles(tmp_path):
    n = write_msh(tmp_path / "square.msh",
                  "SetFactory(\"OpenCASCADE\"); Rectangle(1) = {2, 2, 0, 1,"
                  " 1};\n", 0.1)
    t = template(spec("msh", file=str(tmp_path / "square.msh")))
    assert len(t.triangles) == n
    assert t.area == pytest.approx(math.pi * D**2 / 4, rel=1e-12)
    centroid = (t.points[t.triangles].mean(axis=1)
                * triangulation.signed_areas(t.points, t.triangles)[:, None]).sum(0)
    assert np.allclose(centroid / t.area, 0, atol=1e-12)
    assert t.bounding_radius == pytest.approx(
        math.sqrt(t.area / 2), rel=1e-9)  # half the square's diagonal


def test_msh_of_two_pieces_is_refused(tmp_path):
    write_msh(tmp_path / "two.msh",
              "SetFactory(\"OpenCASCADE\"); Disk(1) = {0, 0, 0, 1};"
              " Disk(2) = {3, 0, 0, 1};\n", 0.3)
    with pytest.raises(ShapeError, match=r"two\.msh.*bounded by 2 curves"):
        template(spec("msh", file=str(tmp_path / "two.msh")))


def test_open_curve_is_refused_naming_file_and_species(tmp_path):
    (tmp_path / "open.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3};\n"
        "Curve Loop(1) = {1, 2}; Plane Surface(1) = {1};\n")
    with pytest.raises(ShapeError,
                       match=r"\[species.0\].*open\.geo.*gmsh could not.*"
                       "not to be forming a closed loop"):
        template(spec("geo", file=str(tmp_path / "open.geo")))


def test_geo_without_a_surface_is_refused(tmp_path):
    (tmp_path / "curve.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Line(1) = {1, 2};\n")
    with pytest.raises(ShapeError, match=r"curve\.geo.*0 plane surfaces"):
        template(spec("geo", file=str(tmp_path / "curve.geo")))


def test_missing_and_wrong_files_are_refused(tmp_path):
    with pytest.raises(ShapeError, match=r"file = 'nowhere.geo': not found"):
        template(spec("geo", file="nowhere.geo"))
    with pytest.raises(ShapeError, match="file: missing"):
        template(spec("msh"))
    with pytest.raises(ShapeError, match=r"needs a \.msh file"):
        template(spec("msh", file="lshape.geo"))


def test_shape_too_thin_for_the_element_size():
    # minor axis 2 b = 0.63 mm at h = 1.065 mm: flat triangles at the tips
    with pytest.raises(ShapeError, match=r"\[species.0\].*quality.*"
                       "element_size"):
        template(spec("ellipse", aspect_ratio=1000.0))
    # a coarse polygonisation of an exact shape: its area is 5 % off
    with pytest.raises(ShapeError, match="meshed area"):
        template(spec("ellipse", aspect_ratio=1.0), h=D * math.pi / 10)
    # a disk follows today's rule only (8 elements around it)
    assert len(template(spec("disk"), h=D * math.pi / 9).triangles) > 0


def test_shape_too_small_for_the_element_size():
    with pytest.raises(ShapeError, match="fewer than 8"):
        template(spec("polygon", sides=3), h=D)


def test_boundary_loops_of_a_ring():
    """An annulus (a hole) has two boundary curves: refused as a shape."""
    n = 12
    t = 2 * math.pi * np.arange(n) / n
    ring = np.vstack([np.stack([np.cos(t), np.sin(t)], 1),
                      2 * np.stack([np.cos(t), np.sin(t)], 1)])
    tri = []
    for i in range(n):
        j = (i + 1) % n
        tri += [[i, n + i, n + j], [i, n + j, j]]
    assert len(shapes.boundary_loops(np.array(tri))) == 2
    with pytest.raises(ShapeError, match="bounded by 2 curves"):
        shapes.checked_template(ring, np.array(tri), None, "ring", 0.5)


def test_rotation():
    xy = np.array([[1.0, 0.0], [0.0, 2.0]])
    assert np.allclose(shapes.rotated(xy, math.pi / 2), [[0, 1], [-2, 0]])
