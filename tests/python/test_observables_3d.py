"""The observables of 3D runs (issue 40, item 3) on cases known by hand:
p and q of known 3x3 stresses and the 2D q unchanged; the 3D fabric of
known normals; Z of three bodies whose node-to-face contacts are counted by
hand; Love-Weber and the wall totals of a cube squeezed by the six planes
of a box (all give the planes' pressures); the box's strains. The end to
end checks on the driver's output are in test_run_3d_observables.py."""

import numpy as np
import pytest

from softpack.analysis import stress, tensors
from softpack.analysis.connectivity import contact_network
from softpack.analysis.network import fabric
from softpack.analysis.setup import Rules


def test_p_and_q_of_known_stresses():
    # uniaxial: p = s / 3, q = |s|; hydrostatic: q = 0
    p, q = stress.scalars({"xx": np.array([6.0]), "yy": np.zeros(1),
                           "zz": np.zeros(1), "xy": np.zeros(1),
                           "xz": np.zeros(1), "yz": np.zeros(1)}, 3)
    assert p[0] == pytest.approx(2.0) and q[0] == pytest.approx(6.0)
    iso = {c: np.zeros(1) for c in tensors.components(3)}
    iso.update(xx=np.ones(1) * 5, yy=np.ones(1) * 5, zz=np.ones(1) * 5)
    p, q = stress.scalars(iso, 3)
    assert p[0] == pytest.approx(5.0) and q[0] == pytest.approx(0.0)
    # pure shear tau (symmetric part of xy, yx): q = sqrt(3) tau
    shear = {c: np.zeros(1) for c in tensors.components(3)}
    shear.update(xy=np.array([1.0]), yx=np.array([3.0]))
    assert stress.scalars(shear, 3)[1][0] == pytest.approx(2 * 3 ** 0.5)


def test_the_2d_q_is_the_maximum_shear_stress_as_before():
    rng = np.random.default_rng(0)
    xx, yy, xy, yx = rng.normal(size=(4, 50))
    p, q = stress.pressure_deviator(xx, yy, xy, yx)
    # the formula of the 2D stress.csv before 3D existed, bit for bit
    assert np.array_equal(p, 0.5 * (xx + yy))
    assert np.array_equal(q, np.hypot(0.5 * (xx - yy), 0.5 * (xy + yx)))


def fabric_of(branches):
    b = np.asarray(branches, float)
    table = {"step": np.zeros(len(b)), "b": np.ones(len(b)),
             "branch_x": b[:, 0], "branch_y": b[:, 1], "branch_z": b[:, 2]}
    return {k: v[0] for k, v in fabric(table, np.zeros(1)).items()}


def test_the_3d_fabric_of_known_normals():
    iso = fabric_of(np.vstack([np.eye(3), -2 * np.eye(3)]))
    assert iso["fabric_xx"] == pytest.approx(1 / 3)
    assert iso["fabric_xy"] == pytest.approx(0.0)
    assert iso["fabric_anisotropy"] == pytest.approx(0.0, abs=1e-14)
    parallel = fabric_of([[2.0, 0, 0], [-1.0, 0, 0]])
    assert parallel["fabric_xx"] == pytest.approx(1.0)
    assert parallel["fabric_anisotropy"] == pytest.approx(7.5)
    # in the plane z = 0, isotropic in it (standing cylinders): 15/2 x 1/2
    plane = fabric_of([[1, 0, 0], [0, 1, 0], [1, 1, 0], [1, -1, 0]])
    assert plane["fabric_zz"] == 0.0
    assert plane["fabric_anisotropy"] == pytest.approx(3.75)
    assert "fabric_angle" not in plane


def test_z_of_three_bodies_counted_by_hand():
    """Body 0 presses three of its nodes on a face of body 1 (a contact),
    body 1 one node on body 2 (not a contact: one node), body 2 two nodes
    on the base (wall 4: a contact). Z = (1 + 1 + 1) / 3 retained bodies,
    without walls 2 / 3; none is a rattler."""
    rows = [  # candidate, node, antagonist, wall, fn, fx, fy, fz
        (0, 3, 1, -1, 1.0, 1.0, 0, 0), (0, 4, 1, -1, 1.0, 1.0, 0, 0),
        (0, 9, 1, -1, 1.0, 1.0, 0, 0), (1, 2, 2, -1, 1.0, 0, 1.0, 0),
        (2, 0, -1, 4, 1.0, 0, 0, 1.0), (2, 5, -1, 4, 1.0, 0, 0, 1.0)]
    a = np.array(rows, float)
    contacts = {k: a[:, i] for i, k in enumerate(
        ("candidate", "node", "antagonist", "wall", "fn", "fx", "fy", "fz"))}
    for k in ("candidate", "node", "antagonist", "wall"):
        contacts[k] = contacts[k].astype(np.int64)
    rules = Rules(force_threshold=1e-4, unbalanced_threshold=1e9,
                  rule="loaded_nodes")
    net = contact_network(contacts, 3, 0.0, rules, np.zeros((3, 3)))
    assert net.pairs.tolist() == [[0, 1]]
    assert net.walls.tolist() == [[2, 4]]
    assert net.z == pytest.approx(1.0)
    assert net.z_without_walls == pytest.approx(2 / 3)
    assert not net.rattler.any()
    # the resultants have three components: body 0 receives 3 along x
    assert net.resultant[0] == pytest.approx(3.0)
    assert net.resultant[2] == pytest.approx(np.sqrt(1 + 4))
    # the base (wall 4) uncounted, as series.csv's z_without_base: body 2
    # touches nothing else and is a rattler; Z = (1 + 1) / 2
    planar = contact_network(contacts, 3, 0.0, rules, np.zeros((3, 3)),
                             uncounted_walls=[4, 5])
    assert planar.walls.tolist() == [] and planar.rattler.tolist() == [
        False, False, True]
    assert planar.z == pytest.approx(1.0) and planar.retained.sum() == 2
    assert planar.resultant[2] == net.resultant[2]


def squeezed_cube(F, G, K, half=0.5):
    """One body at the origin touching the six planes of [-half, half]^3
    at six nodes; the planes push it with F (x), G (y) and K (z)."""
    nodes = np.vstack([half * np.eye(3), -half * np.eye(3)])
    geometry = stress.Geometry(centres=np.zeros((1, 3)), current=nodes,
                               nodes=[np.arange(6)])
    # planes 0 left, 1 right, 2 bottom, 3 top, 4 base, 5 lid
    rows = [(0, 0, -1, 1, -F, 0, 0), (0, 1, -1, 3, 0, -G, 0),
            (0, 2, -1, 5, 0, 0, -K), (0, 3, -1, 0, F, 0, 0),
            (0, 4, -1, 2, 0, G, 0), (0, 5, -1, 4, 0, 0, K)]
    a = np.array(rows, float)
    table = {k: a[:, i] for i, k in enumerate(
        ("candidate", "node", "antagonist", "wall", "fx", "fy", "fz"))}
    for k in ("candidate", "node", "antagonist", "wall"):
        table[k] = table[k].astype(np.int64)
    steps = {}
    for name, axis, sign in (("left", 0, -1), ("right", 0, 1),
                             ("bottom", 1, -1), ("top", 1, 1),
                             ("base", 2, -1), ("lid", 2, 1)):
        force = (F, G, K)[axis]
        for i, c in enumerate("xyz"):
            steps[f"{name}_{c}"] = np.array([sign * half if i == axis
                                             else 0.0])
            steps[f"{name}_f{c}"] = np.array([sign * force if i == axis
                                              else 0.0])
    return geometry, table, steps


def test_a_cube_squeezed_by_the_six_planes_gives_their_pressures():
    F, G, K, half = 30.0, 12.0, 6.0, 0.5
    geometry, table, steps = squeezed_cube(F, G, K, half)
    volume = (2 * half) ** 3
    area = (2 * half) ** 2
    expected = np.diag([F, G, K]) / area
    np.testing.assert_allclose(stress.love_weber(table, geometry, volume),
                               expected, rtol=1e-14)
    np.testing.assert_allclose(
        stress.boundary_stress(table, geometry, volume), expected,
        rtol=1e-14)
    totals = stress.wall_totals_stress(steps, 3)
    assert totals["area"][0] == pytest.approx(volume)
    for i, c in enumerate(tensors.components(3)):
        assert totals[c][0] == pytest.approx(expected.flat[i])
    own = stress.wall_normal_stresses(steps, 3)
    assert list(own) == [f"{w}_stress" for w in stress.BOX_3D]
    assert own["left_stress"][0] == own["right_stress"][0] == F / area
    assert own["base_stress"][0] == own["lid_stress"][0] == K / area


def test_tetrahedra_centroids_and_the_3d_strains():
    # one tetrahedron per body: its volume centroid is its vertices' mean
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1],
                       [2, 0, 0], [4, 0, 0], [2, 2, 0], [2, 0, 2]], float)
    cells = np.array([[0, 1, 2, 3], [4, 5, 6, 7]])
    c = stress.centroids(points, cells, np.array([0, 1]), 2)
    np.testing.assert_allclose(c, [[0.25, 0.25, 0.25], [2.5, 0.5, 0.5]])
    eps = stress.strain_columns({"xx": np.array([0.3]),
                                 "yy": np.array([0.0]),
                                 "zz": np.array([0.0])})
    assert eps["eps_v"][0] == pytest.approx(0.3)
    # eps_q = sqrt(2/3 e:e) = 2/3 eps_xx for a uniaxial strain
    assert eps["eps_q"][0] == pytest.approx(0.2)
