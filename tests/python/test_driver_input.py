"""The one driver.json writer against docs/contract.md section 4, and the
scene it records (walls, species, bodies)."""

import json
from pathlib import Path

import numpy as np
import pytest

from softpack.scene.build import scene_record
from softpack.scene.config import load_config, validate
from softpack.contract.schema import load_schema
from softpack.scene.species import particle_table
from softpack.scene.walls import BOX_WALLS, box_geometry, scene_walls
from softpack.simulation.driver_input import driver_document, write_driver_json

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TOP_KEYS = ["schema_version", "directory", "initial_state", "scene",
            "material", "materials", "walls", "cell", "stages", "stop",
            "contact", "friction", "time", "damping", "gravity", "output",
            "parallel"]


pytestmark = pytest.mark.usefixtures("registry")


@pytest.fixture
def paper_document(tmp_path):
    config = load_config(EXAMPLES / "paper.toml")
    record = scene_record(config, tmp_path / "mesh" / "packing.xdmf")
    doc = write_driver_json(config, record, tmp_path / "out")
    return config, doc, tmp_path


def test_every_key_is_explicit_and_named_as_in_the_schema(paper_document):
    config, doc, tmp_path = paper_document
    written = json.loads((tmp_path / "out" / "driver.json").read_text())
    assert written == doc
    assert list(doc) == TOP_KEYS
    assert doc["schema_version"] == 2 and doc["initial_state"] is None
    assert doc["directory"] == str((tmp_path / "out").resolve())
    schema = load_schema()
    for name in ("stop", "contact", "time", "damping", "output", "parallel"):
        assert list(doc[name]) == list(schema[name].parameters), name
        assert all(v is not None for v in doc[name].values())
    assert doc["material"] == {"law": "neo_hookean", "density": 1180.0,
                               "rigid": False, "parameters": {"shear_modulus": 0.15e6,
                                              "lame_lambda": 0.3e6}}
    assert doc["contact"]["delassus_drop_tolerance"] == pytest.approx(1e-9)
    assert doc["stop"] == {"packing_fraction": 0.88,
                           "max_time": pytest.approx(1.43), "steps": 0,
                           "base_area_fraction": 0.0}
    assert doc["time"]["tangent_reuse_steps"] == 50
    assert doc["output"] == {"every_steps": 12, "fields": True,
                             "fields_every": 10, "state": True}


def test_the_paper_box_and_its_piston(paper_document):
    _, doc, _ = paper_document
    assert [w["name"] for w in doc["walls"]] == list(BOX_WALLS)
    walls = {w["name"]: w for w in doc["walls"]}
    assert walls["right"] == {"name": "right", "point": [0.286, 0.0],
                              "normal": [-1.0, 0.0], "velocity": [-0.1, 0.0],
                              "control": "velocity", "pressure": 0.0,
                              "force": 0.0, "mass": walls["right"]["mass"]}
    # the particles' mass per unit length: density x their area
    assert walls["right"]["mass"] > 0
    assert walls["top"]["point"] == [0.0, 0.202]
    assert walls["left"]["velocity"] == [0.0, 0.0]
    # every box wall's normal points into the box
    centre = np.array([0.143, 0.101])
    for w in doc["walls"]:
        assert np.dot(centre - w["point"], w["normal"]) > 0


def test_the_scene_record(paper_document):
    _, doc, tmp_path = paper_document
    scene = doc["scene"]
    assert list(scene) == ["model", "box", "packing", "species", "mesh",
                           "bodies"]
    assert scene["box"] == {"enabled": True, "length": 0.286, "width": 0.202,
                            "height": 0.0}
    assert scene["model"] == {"dimension": 2, "thickness": 0.015}
    assert [(s["name"], s["diameter"], s["count"])
            for s in scene["species"]] == [("small", 0.02, 70),
                                           ("large", 0.03, 30)]
    assert scene["bodies"]["mesh"] == str(
        (tmp_path / "mesh" / "packing.xdmf").resolve())
    assert scene["bodies"]["species"] == [0] * 70 + [1] * 30


def test_species_table_keeps_the_files_order():
    species = [{"diameter": 0.03, "count": 2}, {"diameter": 0.01, "count": 0},
               {"diameter": 0.02, "count": 3}]
    diameters, index = particle_table(species)
    assert diameters.tolist() == [0.03, 0.03, 0.02, 0.02, 0.02]
    assert index.tolist() == [0, 0, 2, 2, 2]


def test_free_walls_follow_the_box_walls_in_the_files_order(tmp_path):
    config = validate({"walls": {
        "lid": {"point": [0.0, 0.15], "normal": [0.0, -3.0],
                "velocity": [0.0, -0.05]},
        "right": {"velocity": [-0.1, 0.0]},
        "ramp": {"point": [0.0, 0.0], "normal": [1.0, 1.0]}}}, "walls.toml")
    doc = driver_document(config, {}, tmp_path)
    assert [w["name"] for w in doc["walls"]] == [*BOX_WALLS, "lid", "ramp"]
    assert doc["walls"][4]["normal"] == [0.0, -1.0]
    assert doc["walls"][5]["normal"] == pytest.approx([2 ** -0.5] * 2)
    assert [w.name for w in scene_walls(config)] == [w["name"]
                                                     for w in doc["walls"]]
    assert box_geometry(1.0, 2.0)["top"] == ((0.0, 2.0), (0.0, -1.0))


def test_an_initial_state_is_an_absolute_path(tmp_path):
    config = load_config(EXAMPLES / "small.toml")
    doc = driver_document(config, {}, "rel/out", initial_state="s/state.bin")
    assert Path(doc["initial_state"]).is_absolute()
    assert Path(doc["directory"]).is_absolute()
