"""Configuration: defaults, examples, and the promised error messages."""

import json
from pathlib import Path

import pytest

from softpack.scene.config import (SCHEMA, ConfigError, defaults,
                             initial_packing_fraction, load_config,
                             to_driver_json, to_toml, validate)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def write(tmp_path, text, name="x.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def error_of(tmp_path, text):
    path = write(tmp_path, text)
    with pytest.raises(ConfigError) as info:
        load_config(path)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    return message


def test_defaults_are_the_papers_values():
    """Every physical parameter is the paper's; the numerical settings are
    softpack's (examples/paper_9us.toml restores the paper's)."""
    c = defaults()
    g = c["geometry"]
    assert (g["length"], g["width"], g["thickness"]) == (0.286, 0.202, 0.015)
    assert g["counts"] == [70, 30] and g["diameters"] == [0.020, 0.030]
    assert c["mesh"]["element_size"] == 1.065e-3
    assert c["material"]["shear_modulus"] == 0.15e6
    assert c["material"]["lmbda"] == 0.3e6  # derived: 2 mu
    assert c["material"]["density"] == 1180.0
    assert c["loading"]["piston_speed"] == 0.1
    assert c["loading"]["target_packing_fraction"] == 0.88
    assert c["loading"]["max_time"] == pytest.approx(0.286 / 0.2)
    assert c["contact"]["friction"] == 0.3
    assert (c["damping"]["alpha"], c["damping"]["beta"]) == (30.0, 1e-5)
    assert c["time"]["time_step"] == 7.2e-5 and c["time"]["theta"] == 0.55
    paper = load_config(EXAMPLES / "paper_9us.toml")
    assert paper["time"]["time_step"] == 9e-6 and paper["time"]["theta"] == 0.5
    assert (paper["time"]["newton_tolerance"],
            paper["contact"]["nlgs_tolerance"]) == (1e-6, 1e-8)
    # both write an output every 0.9 ms (within a step)
    for conf in (c, paper):
        interval = conf["output"]["every_steps"] * conf["time"]["time_step"]
        assert interval == pytest.approx(9e-4, rel=0.05)
    assert c["observables"]["unbalanced_threshold"] == 1e-3
    assert initial_packing_fraction(c) == pytest.approx(0.7477, abs=1e-4)


def test_paper_example_sets_every_default():
    paper = load_config(EXAMPLES / "paper.toml")
    assert dict(paper) == dict(defaults())
    text = (EXAMPLES / "paper.toml").read_text()
    for section, keys in SCHEMA.items():
        assert f"[{section}]" in text
        for key in keys:
            assert f"\n{key} =" in text or f"\n# {key} =" in text, key


def test_small_example_is_ci_sized():
    small = load_config(EXAMPLES / "small.toml")
    assert sum(small["geometry"]["counts"]) <= 16
    assert small["mesh"]["element_size"] >= 2.5e-3
    # steps until a rigid compression reaches the target packing fraction
    phi0 = initial_packing_fraction(small)
    g, loading = small["geometry"], small["loading"]
    travel = g["length"] * (1 - phi0 / loading["target_packing_fraction"])
    steps = travel / loading["piston_speed"] / small["time"]["time_step"]
    assert 100 < steps < 1000
    assert loading["max_time"] * loading["piston_speed"] > travel


@pytest.mark.parametrize("text, expected", [
    ("[time]\nstepp = 1\n",
     "unknown key [time] stepp (allowed: time_step, theta, mass,"),
    ("[timing]\ntime_step = 1e-5\n", "unknown section [timing] (allowed"
     " sections: geometry, mesh, material, loading, contact, time,"),
    ("friction = 0.3\n", "key friction outside a section"),
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
    ("[geometry]\ncounts = [70.0, 30]\n", "[geometry] counts = [70.0, 30]:"
     " must be a non-empty list of integers >= 0"),
    ("[geometry]\ncounts = 100\n", "must be a non-empty list of integers"),
    ("[geometry]\nlength = nan\n", "must be a number > 0 m"),
])
def test_wrong_types(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


@pytest.mark.parametrize("text, expected", [
    ("[contact]\nfriction = -1\n", "[contact] friction = -1: must be >= 0"),
    ("[time]\ntheta = 0.4\n", "[time] theta = 0.4: must be in [0.5, 1]"),
    ("[loading]\ntarget_packing_fraction = 1.0\n",
     "[loading] target_packing_fraction = 1.0: must be in (0, 1)"),
    ("[material]\nshear_modulus = 0\n",
     "[material] shear_modulus = 0: must be > 0 Pa"),
    ("[geometry]\ndiameters = [0.02, -0.03]\n",
     "[geometry] diameters = [0.02, -0.03]: must be a list of numbers > 0 m"),
    ("[contact]\nnlgs_relaxation = 2.0\n",
     "[contact] nlgs_relaxation = 2.0: must be in (0, 2)"),
])
def test_out_of_range(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


@pytest.mark.parametrize("text, expected", [
    ("[geometry]\ncounts = [70, 30, 5]\n", "[geometry] counts and diameters"
     " must have the same length (got 3 and 2)"),
    ("[mesh]\nelement_size = 0.01\n", "[mesh] element_size = 0.01: must be"
     " <= 0.007854 m (at least 8 elements around the smallest disk"),
    ("[loading]\ntarget_packing_fraction = 0.7\n", "the disks fill 0.748 of"
     " the box: must be < [loading] target_packing_fraction = 0.7"),
    ("[geometry]\nwidth = 0.03\n", "[geometry] diameters = [0.02, 0.03]:"
     " must be < 0.0298 m"),
    ("[time]\ntime_step = 0.005\n", "[time] time_step = 0.005: must be <="
     " 0.002 s ([contact] alert_distance / [loading] piston_speed"),
])
def test_inconsistent_values(tmp_path, text, expected):
    assert expected in error_of(tmp_path, text)


def test_unreadable_and_invalid_files(tmp_path):
    with pytest.raises(ConfigError, match="nope.toml: cannot read"):
        load_config(tmp_path / "nope.toml")
    assert "invalid TOML" in error_of(tmp_path, "[time\n")


def test_override_is_validated_and_named():
    c = validate({}, "paper.toml", {"contact.friction": 0.7,
                                    "geometry.seed": 2})
    assert c["contact"]["friction"] == 0.7 and c["geometry"]["seed"] == 2
    with pytest.raises(ConfigError, match=r"paper.toml: \[contact\] friction"
                       r" = -0.1 \(from the command line\): must be >= 0"):
        validate({}, "paper.toml", {"contact.friction": -0.1})


def test_toml_round_trip(tmp_path):
    c = validate({"material": {"lmbda": 1e5}, "contact": {"friction": 0.1},
                  "time": {"mass": "lumped"}}, "a.toml")
    again = load_config(write(tmp_path, to_toml(c), "resolved.toml"))
    assert dict(again) == dict(c)


def test_driver_json(tmp_path):
    c = load_config(EXAMPLES / "paper.toml")
    doc = to_driver_json(c, tmp_path / "mesh" / "packing.xdmf",
                         tmp_path / "out")
    written = json.loads((tmp_path / "out" / "driver.json").read_text())
    assert written == doc
    assert doc["mesh"] == str((tmp_path / "mesh" / "packing.xdmf").resolve())
    assert doc["material"] == {"name": "neo_hookean", "density": 1180.0,
                               "parameters": {"mu": 0.15e6, "lmbda": 0.3e6}}
    walls = {w["name"]: w for w in doc["walls"]}
    assert list(walls) == ["left", "piston", "bottom", "top"]
    assert walls["piston"] == {"name": "piston", "point": [0.286, 0.0],
                               "normal": [-1.0, 0.0],
                               "velocity": [-0.1, 0.0]}
    assert walls["top"]["point"] == [0.0, 0.202]
    assert walls["left"]["velocity"] == [0.0, 0.0]
    assert doc["box"] == {"left": "left", "right": "piston",
                          "bottom": "bottom", "top": "top"}
    ts = doc["time_stepping"]
    assert (ts["time_step"], ts["rayleigh_alpha"], ts["rayleigh_beta"],
            ts["velocity_scale"], ts["mass"]) == (7.2e-5, 30.0, 1e-5, 0.1,
                                                  "consistent")
    assert doc["contact"]["friction"] == 0.3
    assert doc["contact"]["nlgs_tolerance"] == 1e-6
    assert doc["contact"]["nlgs_relaxation"] == 1.8
    # the dropped Delassus couplings are far below what the NLGS resolves
    assert doc["contact"]["delassus_drop_tolerance"] == pytest.approx(1e-9)
    assert doc["stop"]["packing_fraction"] == 0.88
    assert doc["output"] == {"directory": str((tmp_path / "out").resolve()),
                             "every_steps": 12, "fields": 10,
                             "state": True}
    assert (ts["tangent_reuse_steps"], ts["refactor_above_iterations"]) \
        == (50, 5)
