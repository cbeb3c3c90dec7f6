"""network.csv's pairs and the fabric tensor on hand-made contacts, where
each value is known (issue 37 item 2; the runs' tables are checked against
the driver's in test_assembly_runs.py)."""

import math

import numpy as np
import pytest

from softpack.analysis.network import fabric, pairs


def _contacts(rows):
    """(candidate, antagonist, wall, fn, fx, fy) rows as a contacts table."""
    data = np.array(rows, dtype=float).reshape(-1, 6)
    table = {name: data[:, j] for j, name in enumerate(
        ("candidate", "antagonist", "wall", "fn", "fx", "fy"))}
    for name in ("candidate", "antagonist", "wall"):
        table[name] = table[name].astype(np.int64)
    return table


def test_pairs_sum_nodal_forces_on_the_lower_particle():
    """Particles 0 at (0, 0) and 1 at (0.02, 0) press each other with two
    nodes of 1's against 0 and one of 0's against 1; 1 touches the right
    wall (x = 0.035, normal -x); an open contact (fn = 0) is left out."""
    c = _contacts([
        (1, 0, -1, 2.0, -2.0, 0.1),   # on 1 from 0
        (1, 0, -1, 3.0, -3.0, -0.1),
        (0, 1, -1, 4.0, 4.0, 0.3),    # on 0 from 1
        (1, -1, 0, 5.0, -5.0, 0.0),   # on 1 from wall 0
        (0, -1, 0, 0.0, 0.0, 0.0),
    ])
    centroids = np.array([[0.0, 0.0], [0.02, 0.0]])
    walls = [(np.array([0.035, 0.0]), np.array([-1.0, 0.0]))]
    rows = pairs(c, centroids, walls, thickness=0.5)
    assert rows["a"].tolist() == [0, 1] and rows["b"].tolist() == [1, -1]
    assert rows["nodes"].tolist() == [3, 1]
    # on 0 from 1: its own 4 and the opposite of 1's 2 + 3, times H
    np.testing.assert_allclose([rows["fx"][0], rows["fy"][0]],
                               [0.5 * 9.0, 0.5 * 0.3])
    np.testing.assert_allclose([rows["branch_x"][0], rows["branch_y"][0]],
                               [0.02, 0.0])
    # a tensile x force along an x branch: fn < 0, ft its y part
    assert rows["fn"][0] == pytest.approx(-4.5)
    assert rows["ft"][0] == pytest.approx(0.15)
    # the wall: branch to the projection of 1's centroid; compression
    np.testing.assert_allclose([rows["branch_x"][1], rows["branch_y"][1]],
                               [0.015, 0.0])
    assert rows["fn"][1] == pytest.approx(2.5)


def test_fabric_of_known_normals():
    def table(angles, step=0):
        n = len(angles)
        return {"step": np.full(n, step), "b": np.ones(n),
                "branch_x": 0.01 * np.cos(angles),
                "branch_y": 0.01 * np.sin(angles)}
    iso = fabric(table(np.array([0, math.pi / 2, math.pi, -math.pi / 2])),
                 [0])
    assert iso["fabric_xx"][0] == pytest.approx(0.5)
    assert iso["fabric_anisotropy"][0] == pytest.approx(0.0, abs=1e-15)
    one = fabric(table(np.full(3, math.pi / 6)), [0])
    assert one["fabric_anisotropy"][0] == pytest.approx(2.0)
    assert one["fabric_angle"][0] == pytest.approx(math.pi / 6)
    assert one["fabric_xx"][0] + one["fabric_yy"][0] == pytest.approx(1.0)
    # walls (b < 0) are left out; a step with no pair is NaN
    walls = dict(table(np.zeros(2)), b=-np.ones(2))
    assert np.isnan(fabric(walls, [0])["fabric_xx"][0])
