"""Checks of one body dropped under [gravity] and settled on a wall, shared
by the 2D disk (test_gravity.py) and the 3D sphere (test_gravity_3d.py)."""

import dataclasses

import numpy as np
import pytest

from softpack.analysis import connectivity as net_
from softpack.analysis.setup import read_rules, read_setup
from softpack.contract.tables import read_table


def assert_work_is_weight_times_drop(out, axis: str, min_drop: float):
    """The work of gravity is the weight times the drop of the centre along
    ``axis`` ("y" in 2D, "z" in 3D), 2e-3 relative: the centroid is the
    area's (volume's), the work follows the lumped masses' centre, the same
    for a rigid motion and within the deformation's share here; the energy
    balance closes to 1e-4 of that work."""
    steps = read_table(out / "raw" / "steps.csv")
    particles = read_table(out / "raw" / "particles.csv")
    centre = np.asarray(particles[f"centroid_{axis}"])
    drop = centre[0] - centre[-1]
    weight = read_setup(out).body_weight[0]["xyz".index(axis)]
    assert drop > min_drop
    assert steps["external_work"][-1] == pytest.approx(-weight * drop,
                                                       rel=2e-3)
    residual = np.abs(steps["energy_residual"])
    assert residual.max() < 1e-4 * steps["external_work"][-1]


def assert_balanced_by_its_weight(out):
    """The analysis counts the resting body as balanced: its weight enters
    its resultant, balanced within 1 % of the contact forces (the stage
    ended at 5e-3), where the contacts alone leave the whole weight
    unbalanced."""
    setup = read_setup(out)
    steps = read_table(out / "raw" / "steps.csv")
    contacts = net_.read_contacts(out / "raw" / "contacts" /
                                  f"step_{int(steps['step'][-1]):08d}.csv")
    rules = dataclasses.replace(read_rules(out), unbalanced_threshold=1e-2)
    with_weight = net_.contact_network(contacts, 1, 0.0, rules,
                                       setup.body_weight)
    alone = net_.contact_network(contacts, 1, 0.0, rules)
    assert not with_weight.unbalanced[0] and alone.unbalanced[0]
    assert with_weight.resultant[0] < 1e-2 * alone.resultant[0]
