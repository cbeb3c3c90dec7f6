"""Scenes of any shape: the written mesh holds every particle, its true
boundary clear of the others by the gap; bad input stops before any file."""

import math
from pathlib import Path

import dolfinx.io
import numpy as np
import pytest
from mpi4py import MPI

from softpack.scene.build import build_scene
from softpack.scene.config import ConfigError, load_config, validate
from softpack.scene.packing import PackingError
from softpack.scene.shapes import ShapeError, boundary_loops

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def read_bodies_mesh(xdmf):
    """Each body's (points, triangles) read back as the driver reads them."""
    with dolfinx.io.XDMFFile(MPI.COMM_SELF, str(xdmf), "r") as f:
        mesh = f.read_mesh(name="mesh")
        mesh.topology.create_connectivity(2, 0)
        tags = f.read_meshtags(mesh, name="bodies")
    cells = mesh.geometry.dofmap.array.reshape(-1, 3)
    body = np.empty(len(cells), dtype=int)
    body[tags.indices] = tags.values
    x = mesh.geometry.x[:, :2]
    return [(x, cells[body == b]) for b in range(body.max() + 1)]


def clearance(a, b):
    """Smallest distance from the boundary nodes of one polygon to the
    boundary edges of another, both ways (m)."""
    def one_way(p, q):
        a, b = q, np.roll(q, -1, axis=0)
        ab = b - a
        ap = p[:, None] - a[None]
        t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
        return np.linalg.norm(ap - t[..., None] * ab, axis=2).min()
    return min(one_way(a, b), one_way(b, a))


def inside(p, polygon):
    """Whether points lie inside a closed polygon (ray casting)."""
    x, y = p[:, 0:1], p[:, 1:2]
    x1, y1 = polygon[:, 0], polygon[:, 1]
    x2, y2 = np.roll(x1, -1), np.roll(y1, -1)
    crosses = ((y1 > y) != (y2 > y)) & (
        x < x1 + (y - y1) * (x2 - x1) / np.where(y2 == y1, 1, y2 - y1))
    return crosses.sum(axis=1) % 2 == 1


@pytest.mark.parametrize("example", ["pentagons_small", "ellipses_small",
                                     "polydisperse_small"])
def test_true_shapes_are_apart(example, tmp_path):
    config = load_config(EXAMPLES / f"{example}.toml")
    scene = build_scene(config, tmp_path / "m")
    gap = config["packing"]["gap"]
    bodies = read_bodies_mesh(scene.mesh.xdmf)
    assert len(bodies) == sum(s["count"] for s in config["species"])
    outlines = []
    for x, cells in bodies:
        (loop,) = boundary_loops(cells)
        outlines.append(x[loop])
    area = sum(0.5 * abs(np.cross(x[c[:, 1]] - x[c[:, 0]],
                                  x[c[:, 2]] - x[c[:, 0]])).sum()
               for x, c in bodies)
    assert area == pytest.approx(sum(scene.mesh.reference_areas), rel=1e-12)
    length, width = config["box"]["length"], config["box"]["width"]
    for i, a in enumerate(outlines):
        assert a[:, 0].min() >= gap and a[:, 1].min() >= gap
        assert a[:, 0].max() <= length - gap and a[:, 1].max() <= width - gap
        for b in outlines[i + 1:]:
            assert clearance(a, b) >= gap
            assert not inside(a, b).any() and not inside(b, a).any()


def test_rotations_follow_the_seed(tmp_path):
    config = load_config(EXAMPLES / "pentagons_small.toml")
    scene = build_scene(config, tmp_path / "m")
    table = np.genfromtxt(scene.mesh.bodies_csv, delimiter=",", names=True)
    assert len(set(np.round(table["angle"], 12))) == len(table)
    again = build_scene(config, tmp_path / "again")
    assert np.array_equal(again.packing.centres, scene.packing.centres)
    assert scene.packing.packing_fraction == pytest.approx(
        10 * math.pi * 0.01**2 / (0.085 * 0.067), rel=1e-12)


def config_of(text, tmp_path):
    path = tmp_path / "run.toml"
    path.write_text(text)
    return load_config(path)


def test_particles_that_cannot_fit_are_refused(tmp_path):
    # ellipses of aspect 3: bounding circles of 3 x their area, more than
    # hexagonal disks could hold, although the ellipses fill only 0.3
    config = config_of(
        "[box]\nlength = 0.1\nwidth = 0.1\n[[species]]\nshape = \"ellipse\"\n"
        "aspect_ratio = 3.0\ndiameter = 0.02\ncount = 10\n"
        "[walls.right]\nvelocity = [-0.1, 0.0]\n", tmp_path)
    with pytest.raises(PackingError, match=r"bounding circles.*\[\[species"):
        build_scene(config, tmp_path / "out" / "m")
    assert not (tmp_path / "out").exists()


def test_a_distribution_that_cannot_fit_is_refused_by_the_config(tmp_path):
    with pytest.raises(ConfigError, match=r"run\.toml.*fill"):
        config_of("[box]\nlength = 0.1\nwidth = 0.1\n[[species]]\n"
                  "distribution = \"uniform\"\ndiameter_min = 0.02\n"
                  "diameter_max = 0.04\ncount = 14\n[walls.right]\n"
                  "velocity = [-0.1, 0.0]\n", tmp_path)
    with pytest.raises(ConfigError, match=r"run\.toml.*\[species.0\]"
                       ".*diameter_min"):
        config_of("[[species]]\ndistribution = \"uniform\"\ncount = 3\n"
                  "[walls.right]\nvelocity = [-0.1, 0.0]\n", tmp_path)


def test_a_bad_geo_file_writes_nothing(tmp_path):
    (tmp_path / "open.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3};\n"
        "Curve Loop(1) = {1, 2}; Plane Surface(1) = {1};\n")
    config = config_of(
        "[[species]]\nshape = \"geo\"\nfile = \"open.geo\"\ncount = 4\n"
        "[walls.right]\nvelocity = [-0.1, 0.0]\n", tmp_path)
    with pytest.raises(ShapeError, match=r"\[species.0\].*open\.geo"):
        build_scene(config, tmp_path / "out" / "m")
    assert not (tmp_path / "out").exists()


BAD_INPUTS = {
    # a .geo whose curve loop is not closed: gmsh aborts in the child
    "open_geo": ("[[species]]\nshape = \"geo\"\nfile = \"open.geo\"\n"
                 "count = 4\n", r"\[species.0\].*open\.geo.*closed loop"),
    # an ellipse of minor axis 0.63 mm at h = 1.065 mm: flat triangles
    "unmeshable": ("[[species]]\nshape = \"ellipse\"\n"
                   "aspect_ratio = 1000.0\ncount = 4\n",
                   r"\[species.0\].*quality.*element_size"),
    # ellipses whose bounding circles cannot be placed in the box
    "cannot_fit": ("[box]\nlength = 0.1\nwidth = 0.1\n[[species]]\n"
                   "shape = \"ellipse\"\naspect_ratio = 3.0\n"
                   "diameter = 0.02\ncount = 10\n",
                   r"bounding circles.*\[\[species\]\] count"),
    # a size distribution that fills more than the box can hold
    "distribution_too_full": (
        "[box]\nlength = 0.1\nwidth = 0.1\n[[species]]\n"
        "distribution = \"uniform\"\ndiameter_min = 0.02\n"
        "diameter_max = 0.04\ncount = 14\n", r"bad\.toml.*fill"),
}


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_input_through_the_run_command_leaves_no_run(case, tmp_path,
                                                         capsys):
    """``./softpack run`` on each bad input of issue 13: a nonzero exit,
    one error line naming the key (and the file), and nothing that looks
    like a run (no driver.json, no raw/, no series.csv)."""
    from softpack.simulation.run import main

    (tmp_path / "open.geo").write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3};\n"
        "Curve Loop(1) = {1, 2}; Plane Surface(1) = {1};\n")
    text, message = BAD_INPUTS[case]
    config = tmp_path / "bad.toml"
    config.write_text(text + "[walls.right]\nvelocity = [-0.1, 0.0]\n")
    out = tmp_path / "out"
    assert main([str(config), "--out", str(out)]) != 0
    errors = [line for line in capsys.readouterr().err.splitlines()
              if line.strip()]
    assert len(errors) == 1
    assert __import__("re").search(message, errors[0]), errors[0]
    for name in ("driver.json", "raw", "series.csv", "particles.csv",
                 "fields.h5", "mesh"):
        assert not (out / name).exists(), name
