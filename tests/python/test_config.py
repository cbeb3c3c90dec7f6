"""Configuration: the schema's defaults, the examples, and the promised
error messages (file, [section] key = value, what is allowed)."""

import math
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from material_registry import use_registry
from softpack import paths
from softpack.scene import materials
from softpack.scene.config import (ConfigError, initial_packing_fraction,
                                   load_config, to_toml, validate)
from softpack.contract.schema import load_schema, markdown, parse_range

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: The piston of the paper's case, as examples/paper.toml sets it.
PISTON = {"walls": {"right": {"velocity": [-0.1, 0.0]}}}


pytestmark = pytest.mark.usefixtures("registry")


def write(tmp_path, text, name="x.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def error_of(tmp_path, text, piston=True):
    """The message of a file refused; the paper's piston added unless
    the text sets walls itself."""
    if piston and "[walls" not in text:
        text = "[walls.right]\nvelocity = [-0.1, 0.0]\n" + text
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_config(path)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    return message


def test_paper_example_is_the_schema_defaults_plus_the_piston():
    """Every value of examples/paper.toml is the schema's default; the
    only other key is the piston's velocity."""
    paper = load_config(EXAMPLES / "paper.toml")
    assert dict(paper) == dict(validate(PISTON, "piston"))
    schema = load_schema()
    for name, section in schema.items():
        if section.is_list or section.is_map:
            continue
        for key, spec in section.parameters.items():
            if spec.derived is None:
                assert paper[name][key] == spec.default, (name, key)
            else:  # the rule's value in the paper's case
                assert paper[name][key] == pytest.approx(spec.default)
    keys = schema["species"].parameters  # the list's other keys: defaults
    assert paper["species"] == [
        {**{k: p.default for k, p in keys.items()}, **dict(s)}
        for s in schema["species"].default_list]
    text = (EXAMPLES / "paper.toml").read_text()
    for name, section in schema.items():
        if not (section.is_list or section.is_map):
            assert f"\n[{name}]" in text, name
            for key in section.parameters:
                assert f"\n{key} =" in text or f"\n# {key} =" in text, key


def test_derived_values_and_material_defaults():
    paper = load_config(EXAMPLES / "paper.toml")
    # max_time: the piston would have crossed half the box
    assert paper["stop"]["max_time"] == pytest.approx(0.286 / (2 * 0.1))
    assert paper["contact"]["delassus_drop_tolerance"] == pytest.approx(
        1e-3 * paper["contact"]["nlgs_tolerance"])
    law = paper["material"]["parameters"]
    assert law["lame_lambda"] == pytest.approx(2 * law["shear_modulus"])
    c = validate({**PISTON, "material": {"parameters":
                                         {"shear_modulus": 1e5}}}, "a.toml")
    assert c["material"]["parameters"]["lame_lambda"] == 2e5
    assert initial_packing_fraction(paper) == pytest.approx(0.7477, abs=1e-4)


def test_the_paper_settings_file_changes_only_the_numerics():
    paper, slow = (load_config(EXAMPLES / f"{n}.toml")
                   for n in ("paper", "paper_9us"))
    assert slow["time"]["time_step"] == 9e-6 and slow["time"]["theta"] == 0.5
    assert (slow["time"]["newton_tolerance"],
            slow["contact"]["nlgs_tolerance"]) == (1e-6, 1e-8)
    for name in ("model", "box", "packing", "species", "mesh", "material",
                 "walls", "damping", "observables"):
        assert slow[name] == paper[name], name
    for conf in (paper, slow):  # both write an output every 0.9 ms
        interval = conf["output"]["every_steps"] * conf["time"]["time_step"]
        assert interval == pytest.approx(9e-4, rel=0.05)


def test_small_example_is_ci_sized():
    small = load_config(EXAMPLES / "small.toml")
    assert sum(s["count"] for s in small["species"]) <= 16
    assert small["mesh"]["element_size"] >= 2.5e-3
    phi0 = initial_packing_fraction(small)
    speed = math.hypot(*small["walls"]["right"]["velocity"])
    travel = small["box"]["length"] * (
        1 - phi0 / small["stop"]["packing_fraction"])
    steps = travel / speed / small["time"]["time_step"]
    assert 100 < steps < 1000
    assert small["stop"]["max_time"] * speed > travel


@pytest.mark.parametrize("text, expected", [
    ("[time]\nstepp = 1\n",
     "unknown key [time] stepp (allowed: time_step, max_step_factor,"),
    ("[timing]\ntime_step = 1e-5\n", "unknown section [timing] (allowed"
     " sections: model, box, packing, species, mesh, material, materials,"
     " walls,"),
    ("friction = 0.3\n[walls.right]\nvelocity = [-0.1, 0.0]\n",
     "key friction outside a section"),
    ("[material.parameters]\nmu = 1e5\n", "unknown key [material.parameters]"
     " mu (allowed: shear_modulus, lame_lambda)"),
    ("[[species]]\ndiameter = 0.02\nsize = 3\n",
     "unknown key [species.0] size (allowed: name, shape, diameter, count,"),
    ("[walls.right]\nspeed = 1\n", "unknown key [walls.right] speed"),
])
def test_unknown_names(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


@pytest.mark.parametrize("text, expected", [
    ('[time]\ntime_step = "fast"\n',
     '[time] time_step = "fast": must be a number in (0, 0.01] s'),
    ("[contact]\nnlgs_max_sweeps = 10.5\n",
     "[contact] nlgs_max_sweeps = 10.5: must be an integer >= 1"),
    ("[output]\nfields = 1\n", "[output] fields = 1: must be true or false"),
    ("[contact]\nfriction = true\n",
     "[contact] friction = true: must be a number >= 0"),
    ('[time]\nmass = "diagonal"\n',
     '[time] mass = "diagonal": must be one of "consistent", "lumped"'),
    ("[[species]]\ncount = 7.0\n",
     "[species.0] count = 7.0: must be an integer >= 0"),
    ("[box]\nlength = nan\n", "must be a number > 0 m"),
    ("[walls.right]\nvelocity = 0.1\n",
     "[walls.right] velocity = 0.1: must be a pair of numbers [x, y] m/s"),
    ('[material]\nlaw = "rubber"\n', '[material] law = "rubber": must be'
     ' one of "gent", "mooney_rivlin", "neo_hookean",'
     ' "neo_hookean_nodal", "saint_venant_kirchhoff"'),
    ('[[species]]\nshape = "square"\n',
     '[species.0] shape = "square": must be one of "disk"'),
])
def test_wrong_types(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


@pytest.mark.parametrize("text, expected", [
    ("[contact]\nfriction = -1\n", "[contact] friction = -1: must be >= 0"),
    ("[time]\ntheta = 0.4\n", "[time] theta = 0.4: must be in [0.5, 1]"),
    ("[stop]\npacking_fraction = 1.0\n",
     "[stop] packing_fraction = 1.0: must be in [0, 1)"),
    ("[material.parameters]\nshear_modulus = 0\n",
     "[material.parameters] shear_modulus = 0: must be > 0 Pa"),
    ("[[species]]\ndiameter = -0.03\n",
     "[species.0] diameter = -0.03: must be > 0 m"),
    ("[contact]\nnlgs_relaxation = 2.0\n",
     "[contact] nlgs_relaxation = 2.0: must be in (0, 2)"),
])
def test_out_of_range(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


@pytest.mark.parametrize("text, expected", [
    ("[mesh]\nelement_size = 0.01\n", "[mesh] element_size = 0.01: must be"
     " <= 0.007854 m (at least 8 elements around the smallest particle,"
     " species small"),
    ("[stop]\npacking_fraction = 0.7\n", "the particles fill 0.748 of"
     " the box: must be < [stop] packing_fraction = 0.7"),
    ("[box]\nwidth = 0.03\n", "[species.1] (species 'large') diameter ="
     " 0.03: must be < 0.0298 m"),
    # a distribution's bound is named by the key the user wrote
    ("[box]\nwidth = 0.08\n[[species]]\ndistribution = \"lognormal\"\n"
     "diameter = 0.03\nsigma = 0.1\ndiameter_max = 0.1\ncount = 2\n",
     "[species.0] (species 'species0') diameter_max = 0.1: must be <"
     " 0.0798 m"),
    ("[[species]]\ndistribution = \"uniform\"\ndiameter_min = 0.001\n"
     "diameter_max = 0.03\ncount = 2\n[mesh]\nelement_size = 0.001\n",
     "D = 0.001 m from [species.0] diameter_min = 0.001)"),
    ("[box]\nwidth = 0.08\n[[species]]\ndistribution = \"lognormal\"\n"
     "diameter = 0.03\nsigma = 0.4\ncount = 2\n",
     "[species.0] (species 'species0') diameter = 0.03, sigma = 0.4"
     " (lognormal without diameter_max: its 1 - 1e-4 quantile, 0.1328 m):"
     " must be < 0.0798 m"),
    ("[time]\ntime_step = 0.005\n", "[time] time_step = 0.005: must be <="
     " 0.002 s ([contact] alert_distance / the speed of [walls.right]"),
    ("[time]\ntime_step = 0.0015\nmax_step_factor = 2.0\n", "[time]"
     " time_step x max_step_factor = 0.003: must be <= 0.002 s"),
    ("[time]\nmax_step_factor = 0.5\n", "[time] max_step_factor = 0.5"),
    ("[time]\nmax_step_factor = 40.0\n", "[time] time_step x max_step_factor"
     " = 0.00288: must be <= 0.002 s ([contact] alert_distance / the speed of"
     " [walls.right]"),
    ("[time]\nmax_step_factor = 25.0\n[contact]\nmax_penetration = 1.5e-4\n",
     "[contact] max_penetration = 0.00015: must be >= 0.00018 m (the travel"
     " of [walls.right] in one step of [time] time_step x max_step_factor)"),
    ("[contact]\nnlgs_tolerance = 1e-4\n", "[contact] nlgs_tolerance ="
     " 0.0001: must be <= 1e-05 (a tenth of [time] newton_tolerance"),
    ("[walls.right]\nvelocity = [-0.1, 0.0]\npoint = [0.2, 0.0]\n",
     "[walls.right] point: the box's walls take their point and normal"
     " from [box]; set only velocity"),
    ("[walls.right]\nvelocity = [-0.1, 0.0]\n[walls.lid]\nnormal = [0, -1]\n",
     "[walls.lid] point missing: a wall not of the box needs point and"
     " normal"),
    ("[box]\nenabled = false\n[[species]]\ncount = 1\n[stop]\nmax_time = 1.0\n"
     "[walls.top]\npoint = [0, 0.1]\nnormal = [0, -1]\n",
     "[stop] packing_fraction = 0.88: must be 0 with [box] enabled = false"),
    ("[[species]]\ncount = 0\n", "there must be at least one particle"),
])
def test_inconsistent_values(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


def test_no_moving_wall_needs_a_max_time(tmp_path):
    message = error_of(tmp_path, "[contact]\nfriction = 0.3\n", piston=False)
    assert "[stop] max_time missing" in message


def test_free_walls_without_a_box(tmp_path):
    """The single-disk scene: two plates, one disk, no box."""
    c = load_config(write(tmp_path, """
[box]
enabled = false
[[species]]
diameter = 0.02
count = 1
[walls.bottom]
point = [0.0, -0.01]
normal = [0.0, 2.0]
velocity = [0.0, 0.01]
[walls.top]
point = [0.0, 0.01]
normal = [0.0, -1.0]
velocity = [0.0, -0.01]
[stop]
packing_fraction = 0.0
max_time = 0.1
"""))
    assert list(c["walls"]) == ["bottom", "top"]
    assert c["walls"]["bottom"]["normal"] == [0.0, 1.0]  # normalised
    assert c["species"][0]["name"] == "species0"
    assert initial_packing_fraction(c) == 0.0


def test_box_walls_come_first_then_the_files_order():
    c = validate({"walls": {"lid": {"point": [0, 0.1], "normal": [0, -1]},
                            "right": {"velocity": [-0.1, 0]}}}, "a.toml")
    assert list(c["walls"]) == ["left", "right", "bottom", "top", "lid"]
    top = c["walls"]["top"]
    assert {k: top[k] for k in ("point", "normal", "velocity")} == {
        "point": [0.0, 0.202], "normal": [0.0, -1.0], "velocity": [0.0, 0.0]}
    assert top["control"] == "velocity"


def test_unreadable_and_invalid_files(tmp_path):
    with pytest.raises(ConfigError, match="nope.toml: cannot read"):
        load_config(tmp_path / "nope.toml")
    assert "invalid TOML" in error_of(tmp_path, "[time\n")


def test_overrides_are_validated_and_blamed_on_the_command_line():
    c = validate(PISTON, "paper.toml", {
        "contact.friction": 0.7, "packing.seed": 2,
        "material.parameters.shear_modulus": 2e5, "species.1.count": 20,
        "walls.right.velocity": [-0.2, 0.0]})
    assert c["contact"]["friction"] == 0.7 and c["packing"]["seed"] == 2
    assert c["material"]["parameters"]["lame_lambda"] == 4e5
    assert [s["count"] for s in c["species"]] == [70, 20]
    assert c["stop"]["max_time"] == pytest.approx(0.286 / 0.4)
    with pytest.raises(ConfigError, match=r"paper.toml: \[contact\] friction"
                       r" = -0.1 \(from the command line\): must be >= 0"):
        validate(PISTON, "paper.toml", {"contact.friction": -0.1})
    with pytest.raises(ConfigError, match=r"\[species.1\] count = -1 \(from"
                       r" the command line\)"):
        validate(PISTON, "paper.toml", {"species.1.count": -1})
    with pytest.raises(ConfigError, match="not one of the 2"):
        validate(PISTON, "paper.toml", {"species.5.count": 1})


def test_validate_leaves_its_input_alone():
    data = {"walls": {"right": {"velocity": [-0.1, 0.0]}}}
    validate(data, "a.toml", {"walls.right.velocity": [-0.3, 0.0]})
    assert data == {"walls": {"right": {"velocity": [-0.1, 0.0]}}}


@pytest.mark.parametrize("name", ["paper", "small", "paper_9us", "adhesive_small"])
def test_toml_round_trip(tmp_path, name):
    c = load_config(EXAMPLES / f"{name}.toml")
    again = load_config(write(tmp_path, to_toml(c), "resolved.toml"))
    assert dict(again) == dict(c)
    tomllib.loads(to_toml(c))


def test_other_values_round_trip(tmp_path):
    c = validate({**PISTON, "material": {"parameters": {"lame_lambda": 1e5}},
                  "contact": {"friction": 0.1}, "time": {"mass": "lumped"},
                  "walls": {"right": {"velocity": [-0.1, 0.0]},
                            "lid": {"point": [0, 0.2], "normal": [0, -1]}}},
                 "a.toml")
    again = load_config(write(tmp_path, to_toml(c), "resolved.toml"))
    assert dict(again) == dict(c)


def test_ranges_are_read_from_the_schema():
    assert parse_range("(0, inf)") == (0.0, None, True, True)
    assert parse_range("[0.5, 1]") == (0.5, 1.0, False, False)
    theta = load_schema()["time"].parameters["theta"]
    assert theta.allowed() == "in [0.5, 1]" and theta.in_range(0.5)
    assert not theta.in_range(0.49)


def test_expression_defaults_are_arithmetic_only():
    assert materials.evaluate("2 * a + (b - 1) / 4", {"a": 3, "b": 5}) == 7
    assert materials.evaluate("-a", {"a": 2}) == -2
    for bad in ("__import__('os')", "a ** 2", "a.real", "[a]", "a if a else 1"):
        with pytest.raises(materials.RegistryError):
            materials.evaluate(bad, {"a": 2})
    with pytest.raises(materials.RegistryError, match="unknown name 'c'"):
        materials.evaluate("2 * c", {"a": 2})


def test_a_law_is_taken_from_the_registry(tmp_path_factory, monkeypatch):
    """A law with its own keys validates from TOML with no code change."""
    law = {"c1": {"unit": "Pa", "range": "(0, inf)", "default": 1e5,
                  "doc": "c1"},
           "c2": {"unit": "Pa", "range": "[0, inf)", "default": "c1 / 4",
                  "doc": "c2"},
           "bulk": {"unit": "Pa", "range": "[0, inf)",
                    "default": "10 * (c1 + c2)", "doc": "bulk"}}
    use_registry(tmp_path_factory, monkeypatch, {
        "schema_version": 2, "materials": {"mooney": {"doc": "",
                                                      "parameters": law}}})
    c = validate({**PISTON, "material": {"law": "mooney",
                                         "parameters": {"c1": 2e5}}}, "a")
    assert c["material"]["parameters"] == {"c1": 2e5, "c2": 5e4,
                                           "bulk": 2.5e6}
    with pytest.raises(ConfigError, match=r"\[material\] law ="
                       r' "neo_hookean": must be one of "mooney"'):
        validate({**PISTON, "material": {"law": "neo_hookean"}}, "a")


def test_a_missing_registry_says_how_to_build_it(tmp_path, monkeypatch):
    monkeypatch.setattr(paths, "MATERIALS", tmp_path / "none.json")
    with pytest.raises(ConfigError, match="./softpack build"):
        validate(PISTON, "a.toml")


def test_docs_parameters_md_is_current():
    """docs/parameters.md is generated from the schema (and committed)."""
    committed = (paths.ROOT / "docs" / "parameters.md").read_text()
    assert committed == markdown(), (
        "docs/parameters.md is stale: regenerate it with /usr/bin/python3 -m"
        " softpack.contract.schema --markdown > docs/parameters.md")
    out = subprocess.run([sys.executable, "-m", "softpack.contract.schema",
                          "--markdown"], capture_output=True, text=True,
                         check=True).stdout
    assert out == committed
