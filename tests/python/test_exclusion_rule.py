"""The readings of the paper's unbalanced-particle exclusion (Sec. VI) on a
hand-built contact set, the insensitivity criterion and why Z is undefined.

Three particles and three walls. Particles 0 and 1 are pressed between
walls 0 and 1 (force 2 per contact, two nodes each) and are balanced.
Particle 2 touches wall 2 and particle 0 with small forces: its resultant
is 0.005 (from the wall only). The piston force is 2; the normal forces of
all contacts sum to 6.01.
"""

import math

import numpy as np
import pytest

from softpack.analysis import connectivity as net_
from softpack.analysis.setup import Rules, read_rules

PISTON = 2.0
ROWS = [  # candidate, node, antagonist, wall, fn, ft, fx, fy
    (0, 1, -1, 0, 1.0, 0, 1.0, 0), (0, 2, -1, 0, 1.0, 0, 1.0, 0),
    (0, 3, 1, -1, 1.0, 0, -1.0, 0), (0, 4, 1, -1, 1.0, 0, -1.0, 0),
    (1, 1, -1, 1, 1.0, 0, -1.0, 0), (1, 2, -1, 1, 1.0, 0, -1.0, 0),
    (2, 1, -1, 2, 0.0025, 0, 0, 0.0025), (2, 2, -1, 2, 0.0025, 0, 0, 0.0025),
    (2, 3, 0, -1, 0.0025, 0, 0, 0), (2, 4, 0, -1, 0.0025, 0, 0, 0)]


def contacts(rows=ROWS):
    table = np.array(rows, dtype=float)
    out = dict(zip(net_.CONTACT_COLUMNS, table.T))
    for name in ("candidate", "node", "antagonist", "wall"):
        out[name] = out[name].astype(np.int64)
    return out


def rules(reference, excluded, threshold=1e-3):
    return Rules(force_threshold=1e-4, unbalanced_threshold=threshold,
                 rule="loaded_nodes", unbalanced_reference=reference,
                 excluded_contacts=excluded)


def test_reference_forces():
    c = contacts()
    assert net_.reference_force(c, PISTON, "piston_force") == PISTON
    assert net_.reference_force(c, PISTON, "total_normal_force") == \
        pytest.approx(6.01)
    with pytest.raises(ValueError, match="unbalanced_reference"):
        net_.reference_force(c, PISTON, "pressure")


@pytest.mark.parametrize("reference, excluded, unbalanced, z", [
    # f = piston: f_p* = 0.002 < 0.005, particle 2 is excluded ...
    ("piston_force", "dropped", [0, 0, 1], 2.0),     # ... and 0 loses it
    ("piston_force", "kept", [0, 0, 1], 2.5),        # ... 0 keeps 3 of 3
    # f = sum of normal forces: f_p* = 0.00601 > 0.005, nobody is excluded
    ("total_normal_force", "dropped", [0, 0, 0], 7 / 3),
    ("total_normal_force", "kept", [0, 0, 0], 7 / 3)])
def test_readings(reference, excluded, unbalanced, z):
    net = net_.contact_network(contacts(), 3, PISTON,
                               rules(reference, excluded))
    assert net.unbalanced.tolist() == [bool(u) for u in unbalanced]
    assert net.resultant[2] == pytest.approx(0.005)
    assert net.z == pytest.approx(z)
    assert net_.z_undefined_code(net) == 0


def test_kept_contacts_do_not_make_an_unbalanced_particle_count():
    net = net_.contact_network(contacts(), 3, PISTON,
                               rules("piston_force", "kept"))
    assert net.z_contacts.tolist() == [3, 2, 0]
    assert net.retained.tolist() == [True, True, False]


def test_unknown_reading_is_refused():
    with pytest.raises(ValueError, match="excluded_contacts"):
        net_.contact_network(contacts(), 3, PISTON,
                             rules("piston_force", "ignored"))


def test_insensitivity_criterion():
    # the criterion: the largest |dZ| between two thresholds over the Phi
    # range where both are defined
    phi = np.array([0.78, 0.80, 0.84, 0.88])
    z_a = np.array([np.nan, 3.0, 3.6, 4.3])
    z_b = np.array([2.0, 3.2, 3.5, 4.3])
    assert net_.z_change(phi, z_a, z_b) == pytest.approx(0.2)
    assert net_.z_change(phi, z_a, z_b, (0.83, 0.9)) == pytest.approx(0.1)
    assert math.isnan(net_.z_change(phi, z_a, z_b, (0.7, 0.79)))
    # on the hand-built set, between f_p* = 0.05 % and 0.1 % of f: particle
    # 2 (resultant 0.005) is excluded at both under the piston reading
    # (f_p* = 0.001, 0.002), so Z does not change; under the total-force
    # reading (f_p* = 0.003, 0.006) it is excluded at 0.05 % only
    z = {(reference, threshold): net_.contact_network(
            contacts(), 3, PISTON, rules(reference, "dropped", threshold)).z
         for reference in net_.REFERENCES for threshold in (5e-4, 1e-3)}
    for reference, change in (("piston_force", 0.0),
                              ("total_normal_force", 1 / 3)):
        assert net_.z_change([0.8], [z[reference, 5e-4]],
                             [z[reference, 1e-3]]) == pytest.approx(change)


def test_why_z_is_undefined():
    assert net_.z_undefined_code(None) == 1
    floating = contacts([(0, 1, 1, -1, 0.0, 0, 0, 0)])
    net = net_.contact_network(floating, 2, PISTON,
                               rules("piston_force", "dropped"))
    assert math.isnan(net.z) and net_.z_undefined_code(net) == 2
    pushed = contacts([(0, 1, -1, 0, 1.0, 0, 1.0, 0),
                       (0, 2, -1, 0, 1.0, 0, 1.0, 0)])
    net = net_.contact_network(pushed, 1, PISTON,
                               rules("piston_force", "dropped"))
    assert net_.z_undefined_code(net) == 3
    net = net_.contact_network(pushed, 2, PISTON,
                               rules("piston_force", "dropped"))
    assert net_.z_undefined_code(net) == 4  # particle 1 floats
    assert set(net_.Z_UNDEFINED) == {1, 2, 3, 4}


def test_rules_of_a_run_before_the_readings_take_the_defaults(tmp_path):
    (tmp_path / "config.toml").write_text(
        "[observables]\nunbalanced_threshold = 0.001\n"
        "contact_force_threshold = 0.0001\ntwo_node_rule = \"loaded_nodes\"\n")
    from softpack.contract.schema import load_schema
    spec = load_schema()["observables"].parameters
    r = read_rules(tmp_path)
    assert r.unbalanced_reference == spec["unbalanced_reference"].default
    assert r.excluded_contacts == spec["excluded_contacts"].default
    (tmp_path / "config.toml").write_text(
        "[observables]\nunbalanced_threshold = 0.001\n"
        "contact_force_threshold = 0.0001\ntwo_node_rule = \"loaded_nodes\"\n"
        "unbalanced_reference = \"total_normal_force\"\n"
        "excluded_contacts = \"kept\"\n")
    r = read_rules(tmp_path)
    assert (r.unbalanced_reference, r.excluded_contacts) == (
        "total_normal_force", "kept")
