"""[gravity] in 3D (issue 40): the standing cylinders' weight on the base.

One soft sphere dropped in a box settles on the base: the stage ends by its
equilibrium criterion (the weight enters the particle's balance); at rest
the base carries the sphere's weight rho V g (V its reference volume) and
the side walls and lid nothing; the work of gravity is the weight times the
drop of the centre of mass; the energy balance closes. A 2D scene's gravity
acts in the plane: three components are refused naming the key, by the
scene's check and by the driver before anything is written.
"""

import json
import os
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

from softpack.analysis.setup import read_setup
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.scene.build import build_scene
from softpack.simulation.driver_input import write_driver_json
from softpack.simulation.run import run
from driver_required import require_driver
from dropped_body import (assert_balanced_by_its_weight,
                          assert_work_is_weight_times_drop)

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
G = -9.81
RHO = 1180.0  # [material] density (the default)


def one_sphere():
    data = {
        "model": {"dimension": 3},
        # narrow across (the sphere's 20 mm in 24 mm): it falls along z
        "box": {"length": 0.024, "width": 0.024, "height": 0.05},
        "species": [{"name": "sphere", "shape": "sphere", "diameter": 0.02,
                     "count": 1}],
        "mesh": {"element_size": 5.0e-3},
        "material": {"parameters": {"shear_modulus": 0.15e6,
                                    "lame_lambda": 3.0e5}},
        "gravity": {"acceleration": [0.0, 0.0, G]},
        "damping": {"alpha": 20.0},
        "contact": {"friction": 0.3, "alert_distance": 1.0e-3,
                    "max_penetration": 1.5e-3, "nlgs_tolerance": 1.0e-8},
        "time": {"time_step": 1.0e-4},
        "output": {"every_steps": 10},
        "stages": [{"name": "settle",
                    "stop": {"equilibrium": 5e-3, "max_time": 1.0}}],
        "stop": {"packing_fraction": 0.0},
    }
    return cfg.validate(data, "one-sphere")


@pytest.fixture(scope="module")
def dropped(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("gravity3d") / "one-sphere"
    assert run(one_sphere(), out) == 0
    return out


def test_the_sphere_settles_and_the_base_carries_its_weight(dropped):
    done = json.loads((dropped / "raw" / "done.json").read_text())
    assert done["complete"] and done["ended_by"] == ["equilibrium"]
    setup = read_setup(dropped)
    weight = setup.body_weight[0]
    volume = setup.reference_area[0]  # (3D: the reference volume)
    # the 5 mm mesh's polyhedron is inscribed in the sphere (measured
    # 2026-12-04: 0.931 of its volume)
    assert 0.85 < volume / (np.pi / 6 * 0.02**3) < 1
    assert weight == pytest.approx([0.0, 0.0, RHO * volume * G], rel=1e-12)
    steps = read_table(dropped / "raw" / "steps.csv")
    # the base pushes up (the force it receives points down); at rest
    # within the stage's criterion 5e-3 (measured 2026-12-04: +0.24 %)
    assert -steps["base_fz"][-1] == pytest.approx(-weight[2], rel=1e-2)
    for wall in ("left_fx", "right_fx", "bottom_fy", "top_fy", "lid_fz"):
        assert abs(steps[wall][-1]) < 1e-3 * abs(weight[2]), wall


def test_the_work_of_gravity_is_the_weight_times_the_drop(dropped):
    assert_work_is_weight_times_drop(dropped, "z", min_drop=1e-3)


def test_the_analysis_counts_the_resting_sphere_as_balanced(dropped):
    assert_balanced_by_its_weight(dropped)


def test_three_components_in_a_2d_scene_are_refused_naming_the_key():
    with open(ROOT / "examples" / "deposition_small.toml", "rb") as f:
        data = tomllib.load(f)
    data["gravity"]["acceleration"] = [0.0, -9.81, 0.0]
    with pytest.raises(cfg.ConfigError, match=r"\[gravity\] acceleration"):
        cfg.validate(data, "deposition.toml")
    with pytest.raises(cfg.ConfigError, match=r"\[gravity\] acceleration"):
        cfg.validate({"gravity": {"acceleration": [0.0, 0.0, 0.0, -9.81]}},
                     "a.toml")


def test_the_driver_refuses_three_components_in_a_2d_run(tmp_path):
    """The driver's own check (driver.json is its input too)."""
    with open(ROOT / "examples" / "deposition_small.toml", "rb") as f:
        config = cfg.validate(tomllib.load(f), "deposition.toml")
    scene = build_scene(config, tmp_path / "mesh" / "packing")
    write_driver_json(config, scene.record(), tmp_path)
    document = json.loads((tmp_path / "driver.json").read_text())
    document["gravity"]["acceleration"] = [0.0, -9.81, 0.0]
    (tmp_path / "driver.json").write_text(json.dumps(document))
    refused = subprocess.run([str(require_driver()), "driver.json",
                              "--quiet"], cwd=tmp_path, capture_output=True,
                             text=True, timeout=120)
    assert refused.returncode == 1
    assert "gravity.acceleration" in refused.stderr, refused.stderr
    assert "2D" in refused.stderr
    assert not (tmp_path / "raw").exists()
