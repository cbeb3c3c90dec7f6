"""A 3D scene through the driver and back (issue 40): softpack-simulate
reads the tetrahedral bodies into a BodySet of dimension 3, writes
raw/setup.json and the fields at t = 0 (meshio reads them) with
--initial-only, and refuses, naming the key, what the 3D time loop lacks
(tests/python/test_run_3d.py steps a 3D scene)."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from softpack.analysis import solids as fractions
from softpack.scene.build import build_scene
from softpack.scene.config import load_config, validate
from softpack.simulation.driver_input import write_driver_json

meshio = pytest.importorskip("meshio")


@pytest.fixture(scope="module")
def scene_3d(tmp_path_factory):
    """Two small cylinders and a large one standing in a box, at 6 mm, and
    their driver.json (no driver run yet)."""
    out = tmp_path_factory.mktemp("scene3d")
    data = {
        "model": {"dimension": 3, "thickness": 0.015},
        "box": {"length": 0.08, "width": 0.05, "height": 0.02},
        "species": [{"name": "small", "shape": "cylinder",
                     "diameter": 0.02, "count": 2},
                    {"name": "large", "shape": "cylinder",
                     "diameter": 0.03, "count": 1}],
        "mesh": {"element_size": 0.006},
        "contact": {"max_penetration": 0.003},
        "material": {"parameters": {"shear_modulus": 0.15e6,
                                    "lame_lambda": 7.35e6}},
        "stop": {"packing_fraction": 0.6, "max_time": 0.06},
    }
    config = validate(data, "scene3d.toml")
    scene = build_scene(config, out / "mesh" / "packing")
    write_driver_json(config, scene.record(), out)
    return out, scene


def simulate(directory, *flags):
    return subprocess.run([str(require_driver()), "driver.json", "--quiet",
                           *flags], cwd=directory, capture_output=True,
                          text=True, timeout=120)


@pytest.fixture(scope="module")
def initial_run(scene_3d):
    out, scene = scene_3d
    done = simulate(out, "--initial-only")
    assert done.returncode == 0, done.stderr
    return out, scene


def test_setup_json_describes_the_tetrahedral_bodies(initial_run):
    out, scene = initial_run
    setup = json.loads((out / "raw" / "setup.json").read_text())
    bodies = setup["bodies"]
    points, tets, body = fractions.read_scene_mesh(scene.mesh.xdmf)
    assert bodies["count"] == 3 and bodies["species"] == [0, 0, 1]
    assert bodies["tetrahedra"] == np.bincount(body).tolist()
    assert bodies["nodes"] == [len(np.unique(tets[body == b]))
                               for b in range(3)]
    # the driver's volumes (boundary faces, divergence theorem) against the
    # scene's sum over the tetrahedra
    assert np.allclose(bodies["reference_area"],
                       fractions.body_volumes(points, tets, body),
                       rtol=1e-12, atol=0)
    assert setup["units"]["force"] == "N"
    assert setup["scene"]["model"]["dimension"] == 3
    # the fractions of the fields at t = 0 are the scene's
    extent = scene.packing.extent
    at_start = fractions.fractions_at(out / "fields.h5", 0.0, extent)
    assert at_start["volume_fraction"] == pytest.approx(
        fractions.volume_fraction(points, tets, body, extent), rel=1e-12)
    assert at_start["base_area_fraction"] == pytest.approx(
        fractions.base_area_fraction(points, tets, body, extent), rel=1e-12)


def test_meshio_reads_the_tetrahedral_fields(initial_run):
    out, scene = initial_run
    with meshio.xdmf.TimeSeriesReader(out / "fields.xdmf") as reader:
        points, cells = reader.read_points_cells()
        t, point_data, cell_data = reader.read_data(0)
    assert reader.num_steps == 1 and t == 0.0
    assert points.shape[1] == 3 and [c.type for c in cells] == ["tetra"]
    tets = cells[0].data
    particle = cell_data["particle"][0].reshape(-1).astype(int)
    mesh_points, mesh_tets, mesh_body = fractions.read_scene_mesh(
        scene.mesh.xdmf)
    # the same bodies: their volumes and positions, whatever the numbering
    assert np.allclose(fractions.body_volumes(points, tets, particle),
                       fractions.body_volumes(mesh_points, mesh_tets,
                                              mesh_body), rtol=1e-12)
    # (the driver's coordinates are dolfinx's, rounded once: 1e-17 m)
    assert np.allclose(np.sort(points, axis=0), np.sort(mesh_points, axis=0),
                       rtol=0, atol=1e-15)
    assert np.all(point_data["displacement"] == 0.0)
    assert np.all(cell_data["Psi"][0] == 0.0)  # at rest, no strain energy


def _cell(document):
    document["cell"]["enabled"] = True
    document["scene"]["box"]["enabled"] = False
    document["walls"] = []


@pytest.mark.parametrize("edit, key", [(_cell, "cell.enabled")])
def test_what_3d_runs_lack_is_refused_naming_the_key(scene_3d, tmp_path,
                                                      edit, key):
    """The 3D time loop refuses what it does not have yet (docs/
    bodies_3d.md): a periodic cell; before anything is written. (A start
    from a state is no longer refused: test_run_3d.py resumes one; nor are
    servo walls and stages: test_servo_3d.py; nor gravity:
    test_gravity_3d.py.)"""
    out, _ = scene_3d
    document = json.loads((out / "driver.json").read_text())
    document["directory"] = str(tmp_path)
    edit(document)
    (tmp_path / "driver.json").write_text(json.dumps(document))
    refused = simulate(tmp_path)
    assert refused.returncode == 1
    assert key in refused.stderr and "3D" in refused.stderr, refused.stderr
    assert not (tmp_path / "raw").exists()


def test_initial_only_in_2d_writes_the_first_row_and_stops(tmp_path):
    examples = Path(__file__).resolve().parents[2] / "examples"
    config = load_config(examples / "small.toml")
    scene = build_scene(config, tmp_path / "mesh" / "packing")
    write_driver_json(config, scene.record(), tmp_path)
    done = simulate(tmp_path, "--initial-only")
    assert done.returncode == 0, done.stderr
    rows = (tmp_path / "raw" / "steps.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[1].startswith("0,0,")  # step 0 at t = 0
    finish = json.loads((tmp_path / "raw" / "done.json").read_text())
    assert finish["reason"] == "initial_only" and finish["steps"] == 0
    assert (tmp_path / "raw" / "state.bin").is_file()


@pytest.mark.parametrize("section, key, value, words", [
    ("model", "dimension", 4, "must be 2 or 3"),
    ("box", "height", 0.0, "must be > 0 in 3D"),
    ("box", "height", -1.0, "must be a number >= 0")])
def test_the_driver_refuses_a_bad_dimension_naming_the_key(
        scene_3d, tmp_path, section, key, value, words):
    out, _ = scene_3d
    document = json.loads((out / "driver.json").read_text())
    document["directory"] = str(tmp_path)
    document["scene"][section][key] = value
    (tmp_path / "driver.json").write_text(json.dumps(document))
    refused = simulate(tmp_path)
    assert refused.returncode == 1
    assert f"scene.{section}.{key}" in refused.stderr and words in \
        refused.stderr, refused.stderr
    assert not (tmp_path / "raw").exists()  # refused before anything


def test_a_3d_scene_takes_ranks_up_to_its_bodies():
    from softpack.scene.config import ConfigError
    from softpack.simulation.driver import check_ranks

    config = load_config(Path(__file__).resolve().parents[2] / "examples"
                         / "cylinders3d_small.toml")
    check_ranks(2, config)  # distributed as 2D scenes (docs/mpi_design.md)
    bodies = sum(int(s["count"]) for s in config["species"])
    with pytest.raises(ConfigError, match="--ranks .*: must be between 1"):
        check_ranks(bodies + 1, config)
