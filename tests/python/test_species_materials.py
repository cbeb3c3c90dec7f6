"""Materials and friction per species (docs/materials.md): the TOML forms,
their one-line errors, the resolved config.toml and driver.json."""

import tomllib
from pathlib import Path

import pytest

from softpack.scene.build import scene_record
from softpack.scene.config import ConfigError, load_config, to_toml, validate
from softpack.simulation.driver_input import driver_document

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

MIXTURE = """
[walls.right]
velocity = [-0.1, 0.0]

[materials.stiff]
law = "saint_venant_kirchhoff"
density = 2500.0
[materials.stiff.parameters]
shear_modulus = 1.5e6

[[species]]
name = "soft"
diameter = 0.02
count = 4
[[species]]
name = "hard"
diameter = 0.03
count = 2
material = "stiff"

[[friction]]
species = "soft"
against = "hard"
coefficient = 0.5
[[friction]]
species = "hard"
against = "walls"
coefficient = 0.1
"""


pytestmark = pytest.mark.usefixtures("registry")


def load(tmp_path, text):
    path = tmp_path / "mix.toml"
    path.write_text(text)
    return load_config(path)


def error_of(tmp_path, text):
    with pytest.raises(ConfigError) as err:
        load(tmp_path, text)
    message = str(err.value)
    assert "\n" not in message and "mix.toml" in message
    return message


def test_named_materials_species_and_pairs(tmp_path):
    config = load(tmp_path, MIXTURE)
    stiff = config["materials"]["stiff"]
    assert stiff["law"] == "saint_venant_kirchhoff"
    assert stiff["density"] == 2500.0
    # The law's defaults are resolved from the given parameters.
    assert stiff["parameters"] == {"shear_modulus": 1.5e6,
                                   "lame_lambda": 3.0e6}
    assert [s["material"] for s in config["species"]] == ["", "stiff"]
    coulomb = {"law": "coulomb", "cohesion": 0.0, "cohesive_distance": 0.0,
               "tensile_strength": 0.0, "shear_strength": 0.0,
               "bonding_distance": 0.0}
    assert config["friction"] == [
        {"species": "soft", "against": "hard", "coefficient": 0.5, **coulomb},
        {"species": "hard", "against": "walls", "coefficient": 0.1,
         **coulomb}]
    # The resolved copy reloads to the same configuration.
    assert validate(tomllib.loads(to_toml(config))) == config


def test_existing_configurations_are_unchanged():
    config = load_config(EXAMPLES / "paper.toml")
    assert config["materials"] == {} and config["friction"] == []
    assert all(s["material"] == "" for s in config["species"])


def test_driver_json_carries_materials_and_pairs(tmp_path):
    config = load(tmp_path, MIXTURE)
    record = scene_record(config, tmp_path / "mesh" / "packing.xdmf")
    doc = driver_document(config, record, tmp_path / "out")
    assert doc["materials"] == [{"name": "stiff",
                                 "law": "saint_venant_kirchhoff",
                                 "density": 2500.0, "rigid": False,
                                 "parameters": {"shear_modulus": 1.5e6,
                                                "lame_lambda": 3.0e6}}]
    assert doc["friction"] == config["friction"]
    assert [s["material"] for s in doc["scene"]["species"]] == ["", "stiff"]
    assert doc["scene"]["bodies"]["species"] == [0, 0, 0, 0, 1, 1]
    assert list(doc["material"]) == ["law", "density", "rigid", "parameters"]


@pytest.mark.parametrize("change, expected", [
    (('material = "stiff"', 'material = "stif"'),
     "[species.1] material = 'stif': no [materials.stif] table (named"
     " materials: 'stiff'; empty: [material])"),
    (("shear_modulus = 1.5e6", "shear_moduls = 1.5e6"),
     "unknown key [materials.stiff.parameters] shear_moduls (allowed:"
     " shear_modulus, lame_lambda)"),
    (("density = 2500.0", "density = -1.0"),
     "[materials.stiff] density = -1.0: must be > 0"),
    (('law = "saint_venant_kirchhoff"', 'law = "rubber"'),
     "[materials.stiff] law = \"rubber\": must be one of"),
    (('against = "hard"', 'against = "rigid"'),
     "[friction.0] against = 'rigid': not a species, a wall or 'walls'"),
    (('species = "hard"', 'species = "left"'),
     "[friction.1] species = 'left': not a species"),
    (('against = "walls"', 'against = "soft"'),
     "[friction.1] species = 'hard', against = 'soft': the pair (hard, soft)"
     " is already given by [friction.0]"),
    (("coefficient = 0.1", "coefficient = -0.1"),
     "[friction.1] coefficient = -0.1: must be >= 0"),
    (("coefficient = 0.1", "coefficent = 0.1"),
     "unknown key [friction.1] coefficent (allowed: species, against,"
     " coefficient, law, cohesion, cohesive_distance, tensile_strength,"
     " shear_strength, bonding_distance)"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "glue"'),
     '[friction.1] law = "glue": must be one of'),
    (("coefficient = 0.1", "coefficient = 0.1\ncohesion = 100.0"),
     "[friction.1] cohesion = 100.0: only law = \"cohesive\" has a"
     " cohesion"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "cohesive"'),
     "[friction.1] cohesion = 0.0: law = \"cohesive\" needs a cohesion > 0"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "cohesive"\n'
      "cohesion = 100.0\ncohesive_distance = 1.0"),
     "[friction.1] cohesive_distance = 1.0: must be <= [contact]"
     " alert_distance"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "cohesive"\n'
      "cohesion = -1.0"),
     "[friction.1] cohesion = -1.0: must be >= 0"),
    # the bonded law (docs/contact_laws.md)
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "bonded"\n'
      "shear_strength = 1.0e3"),
     "[friction.1] tensile_strength = 0.0: law = \"bonded\" needs a"
     " tensile_strength > 0"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "bonded"\n'
      "tensile_strength = 1.0e3"),
     "[friction.1] shear_strength = 0.0: law = \"bonded\" needs a"
     " shear_strength > 0"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "bonded"\n'
      "tensile_strength = -1.0\nshear_strength = 1.0e3"),
     "[friction.1] tensile_strength = -1.0: must be >= 0"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "bonded"\n'
      "tensile_strength = 1.0e3\nshear_strength = 1.0e3\n"
      "bonding_distance = 1.0"),
     "[friction.1] bonding_distance = 1.0: must be <= [contact]"
     " alert_distance"),
    (("coefficient = 0.1", "coefficient = 0.1\ntensile_strength = 1.0e3"),
     "[friction.1] tensile_strength = 1000.0: only law = \"bonded\" has a"
     " tensile_strength"),
    (("coefficient = 0.1", 'coefficient = 0.1\nlaw = "bonded"\n'
      "tensile_strength = 1.0e3\nshear_strength = 1.0e3\ncohesion = 5.0"),
     "[friction.1] cohesion = 5.0: only law = \"cohesive\" has a cohesion"
     " (this pair's law is \"bonded\""),
    (('species = "hard"\nagainst = "walls"', 'species = "hard"\n'
      'against = "floor"'),
     "[friction.1] against = 'floor': not a species, a wall or 'walls'"),
])
def test_bad_input_is_refused_in_one_line(tmp_path, change, expected):
    old, new = change
    assert old in MIXTURE
    assert expected in error_of(tmp_path, MIXTURE.replace(old, new, 1))


def test_a_cohesive_pair_reaches_driver_json(tmp_path):
    text = MIXTURE.replace("coefficient = 0.1", 'coefficient = 0.1\nlaw ='
                           ' "cohesive"\ncohesion = 2.0e3\n'
                           "cohesive_distance = 5.0e-5", 1)
    config = load(tmp_path, text)
    assert config["friction"][1] == {
        "species": "hard", "against": "walls", "coefficient": 0.1,
        "law": "cohesive", "cohesion": 2.0e3, "cohesive_distance": 5.0e-5,
        "tensile_strength": 0.0, "shear_strength": 0.0,
        "bonding_distance": 0.0}
    assert validate(tomllib.loads(to_toml(config))) == config


def test_a_wall_given_twice_for_a_species_is_refused(tmp_path):
    text = MIXTURE + ('[[friction]]\nspecies = "hard"\nagainst = "right"\n'
                      "coefficient = 0.2\n")
    assert ("[friction.2] species = 'hard', against = 'right': the pair"
            " (hard, right) is already given by [friction.1]"
            in error_of(tmp_path, text))


def test_a_species_named_like_a_wall_is_refused(tmp_path):
    text = MIXTURE.replace('name = "soft"', 'name = "left"').replace(
        'species = "soft"', 'species = "left"')
    assert "'left' names both a species and a wall" in error_of(tmp_path, text)
