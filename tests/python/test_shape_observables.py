"""Orientation, elongation and asphericity of meshed particles against the
exact values of their shapes."""

import math
from pathlib import Path

import numpy as np
import pytest

from softpack.analysis.shape import particle_shapes
from softpack.scene import shapes

D, H = 0.02, 1.0e-3


def spec(shape, **keys):
    return {"name": "s", "shape": shape, "diameter": D, "count": 1,
            "sides": 5, "corner_radius": 0.0, "aspect_ratio": 2.0,
            "file": "", **keys}


def meshed(tables):
    """Templates of the given species (one particle each)."""
    out = shapes.templates(tables, [D] * len(tables), range(len(tables)), H)
    return [out[shapes.shape_key(t, D)] for t in tables]


def assemble(templates, centres, angles):
    """One mesh of the templates, rotated and placed, with body ids."""
    points, cells, body, offset = [], [], [], 0
    for i, (t, c, a) in enumerate(zip(templates, centres, angles)):
        points.append(shapes.rotated(t.points, a) + c)
        cells.append(t.triangles + offset)
        body.append(np.full(len(t.triangles), i))
        offset += len(t.points)
    return np.vstack(points), np.vstack(cells), np.concatenate(body)


def test_ellipse_square_disk():
    tables = [spec("ellipse", aspect_ratio=2.0), spec("polygon", sides=4),
              spec("disk"), spec("ellipse", aspect_ratio=3.0)]
    templates = meshed(tables)
    centres = np.array([[0.0, 0.0], [0.1, 0.0], [0.0, 0.1], [0.1, 0.1]])
    angles = [0.4, 0.3, 0.0, 2.0]
    out = particle_shapes(*assemble(templates, centres, angles))
    assert np.allclose(np.c_[out["x"], out["y"]], centres, atol=1e-12)
    assert np.allclose(out["area"], [t.area for t in templates], rtol=1e-12)
    # ellipses: the major axis turned by the rotation (measured 2.2e-16
    # off, 2026-12-03); J ratio = k^2 up to the polygon's chords (measured
    # -1.1e-3 and -1.6e-3)
    assert out["orientation"][0] == pytest.approx(0.4, abs=2e-15)
    assert out["orientation"][3] == pytest.approx(2.0, abs=2e-15)
    assert out["elongation"][0] == pytest.approx(2.0, rel=2e-3)
    assert out["elongation"][3] == pytest.approx(3.0, rel=2e-3)
    # square: isotropic moments, no orientation; P^2 / (4 pi A) = 4 / pi
    assert out["elongation"][1] == pytest.approx(1.0, abs=1e-9)
    assert np.isnan(out["orientation"][1])
    assert out["asphericity"][1] == pytest.approx(4 / math.pi, rel=1e-12)
    # the disk's polygon: slightly above 1 (n sides: (n/pi) tan(pi/n);
    # measured exact, 2026-12-03)
    n = len(shapes.boundary_loops(templates[2].triangles)[0])
    assert out["asphericity"][2] == pytest.approx(
        n / math.pi * math.tan(math.pi / n), rel=1e-12)
    # ellipse of aspect 2: Ramanujan's perimeter (measured 5.2e-4 above it:
    # the chords)
    a, b = shapes.ellipse_axes(2.0, D)
    h = ((a - b) / (a + b))**2
    perimeter = math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))
    assert out["asphericity"][0] == pytest.approx(
        perimeter**2 / (4 * math.pi * math.pi * a * b), rel=2e-3)


def test_a_stretch_elongates_a_disk():
    """A disk stretched by (1 + e, 1 / (1 + e)) along an axis at 30 degrees
    is an ellipse of aspect ratio (1 + e)^2 at 30 degrees."""
    (disk,) = meshed([spec("disk")])
    e, t = 0.2, math.pi / 6
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    F = R @ np.diag([1 + e, 1 / (1 + e)]) @ R.T
    points = disk.points @ F.T
    out = particle_shapes(points, disk.triangles,
                          np.zeros(len(disk.triangles), dtype=int))
    # the disk's polygon has isotropic second moments: both exact to
    # round-off (measured 5.6e-16 rad and 2.2e-16, 2026-12-03)
    assert out["orientation"][0] == pytest.approx(t, abs=6e-15)
    assert out["elongation"][0] == pytest.approx((1 + e)**2, rel=2e-15)
    assert out["area"][0] == pytest.approx(disk.area, rel=1e-12)


def test_rotation_of_a_rigid_motion_and_of_a_stretch():
    """A pentagon (no second-moment axis) and an ellipse turned by known
    angles and moved: the rotation is recovered exactly; a symmetric
    stretch about the centroid adds none."""
    tables = [spec("polygon", sides=5, corner_radius=1e-3),
              spec("ellipse", aspect_ratio=1.5)]
    templates = meshed(tables)
    reference, cells, body = assemble(templates, np.zeros((2, 2)), [0, 0])
    centres = np.array([[0.05, 0.02], [-0.03, 0.1]])
    angles = [0.7, -2.5]
    current, _, _ = assemble(templates, centres, angles)
    out = particle_shapes(current, cells, body, reference)
    np.testing.assert_allclose(out["rotation"], angles, atol=1e-12)
    assert np.isnan(out["orientation"][0])
    # a symmetric stretch (1.1, 1/1.1) along 20 degrees of the turned
    # pentagon: still its rotation, to round-off
    t = math.radians(20)
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    F = R @ np.diag([1.1, 1 / 1.1]) @ R.T
    first = body == 0
    nodes = np.unique(cells[first])
    stretched = current.copy()
    stretched[nodes] = (current[nodes] - centres[0]) @ F.T + centres[0]
    out = particle_shapes(stretched, cells, body, reference)
    assert out["rotation"][0] == pytest.approx(0.7, abs=1e-12)
    assert "rotation" not in particle_shapes(current, cells, body)


def test_shapes_plot_summary_interpolates_on_the_compaction_branch():
    from softpack.plots.shapes import at_phi, parse_runs

    series = {"phi": np.array([0.6, 0.7, 0.8, 0.9, 0.85]),
              "eps": np.array([0.0, 0.1, 0.2, 0.3, 0.35]),
              "E_over_WHLmu": np.array([0.0, 0.0, 1.0, 3.0, 2.0]),
              "z": np.array([np.nan, 2.0, 3.0, 4.0, 3.5])}
    rows = {row["phi"]: row for row in at_phi(series, (0.75, 0.88, 0.95))}
    assert set(rows) == {0.75, 0.88}  # 0.95 never reached
    assert rows[0.75]["eps"] == pytest.approx(0.15)
    assert rows[0.88]["E_over_WHLmu"] == pytest.approx(2.6)  # not 0.85's
    assert rows[0.88]["z"] == pytest.approx(3.8)
    assert parse_runs(["a/b=pent", "c/d"]) == [
        (Path("a/b"), "pent"), (Path("c/d"), "d")]
