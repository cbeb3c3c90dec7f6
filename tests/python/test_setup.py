"""raw/setup.json and the [observables] rules, as the analysis reads them."""

import json
import math

import numpy as np
import pytest

from fake_runs import setup_document, write_rules, write_setup
from softpack.analysis.setup import Rules, SetupError, read_rules, read_setup


def test_box_identity_and_bodies(tmp_path):
    write_setup(tmp_path, length=0.286, width=0.202, thickness=0.015,
                diameters=(0.02, 0.03), species=[0, 1, 0], friction=0.3,
                seed=7, shear_modulus=0.15e6)
    s = read_setup(tmp_path)
    assert (s.length, s.width, s.thickness) == (0.286, 0.202, 0.015)
    assert s.has_box and list(s.walls) == ["left", "right", "bottom", "top"]
    assert np.array_equal(s.walls["right"].normal, [-1, 0])
    assert np.array_equal(s.walls["right"].velocity, [-0.1, 0])
    assert (s.friction, s.seed, s.shear_modulus) == (0.3, 7, 0.15e6)
    assert s.count == 3 and s.body_species.tolist() == [0, 1, 0]
    assert np.allclose(s.radii, [0.01, 0.015, 0.01])
    assert np.allclose(s.reference_area, np.pi * np.array([1, 2.25, 1]) * 1e-4)
    assert s.notes == ()


def test_no_shear_modulus_and_no_box_are_said(tmp_path):
    write_setup(tmp_path, shear_modulus=None, law="c2", box=False)
    s = read_setup(tmp_path)
    assert math.isnan(s.shear_modulus) and math.isnan(s.length)
    assert not s.has_box
    assert any("no box" in n for n in s.notes)
    assert any("'c2' has no shear_modulus" in n for n in s.notes)


def test_refuses_other_versions_and_missing_keys(tmp_path):
    with pytest.raises(SetupError, match="setup.json missing"):
        read_setup(tmp_path)
    doc = write_setup(tmp_path)
    doc["schema_version"] = 1
    (tmp_path / "raw" / "setup.json").write_text(json.dumps(doc))
    with pytest.raises(SetupError, match="schema_version 1"):
        read_setup(tmp_path)
    doc = setup_document()
    del doc["scene"]["model"]
    (tmp_path / "raw" / "setup.json").write_text(json.dumps(doc))
    with pytest.raises(SetupError, match="missing key 'model'"):
        read_setup(tmp_path)
    doc = setup_document()
    doc["bodies"]["count"] = 5
    (tmp_path / "raw" / "setup.json").write_text(json.dumps(doc))
    with pytest.raises(SetupError, match="bodies.count 5"):
        read_setup(tmp_path)


def test_rules_come_from_the_observables_section_only(tmp_path):
    write_rules(tmp_path, unbalanced=5e-4, force=1e-5,
                rule="candidate_nodes")
    assert read_rules(tmp_path) == Rules(force_threshold=1e-5,
                                         unbalanced_threshold=5e-4,
                                         rule="candidate_nodes")


@pytest.mark.parametrize("text, message", [
    ("[observables]\nunbalanced_threshold = 1e-3\n", "missing keys"),
    ("[observables]\nunbalanced_threshold = 1.5\ncontact_force_threshold"
     " = 1e-4\ntwo_node_rule = \"loaded_nodes\"\n", "unbalanced_threshold"),
    ("[observables]\nunbalanced_threshold = 1e-3\ncontact_force_threshold"
     " = 1e-4\ntwo_node_rule = \"three_nodes\"\n", "two_node_rule"),
    ("[model]\nthickness = 1.0\n", "no \\[observables\\] section"),
])
def test_bad_rules_are_refused(tmp_path, text, message):
    (tmp_path / "config.toml").write_text(text)
    with pytest.raises(SetupError, match=message):
        read_rules(tmp_path)
