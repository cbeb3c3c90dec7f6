"""The observables of a 3D run end to end (issue 40, item 3): the standing
cylinders of examples/cylinders3d_small.toml pushed by the piston at 2 m/s
for 36 steps, fields at every output, through ``softpack.simulation.run``
as ``./softpack run`` runs it (which writes series.csv, particles.csv,
network.csv and stress.csv after the driver).

Checked against what the driver wrote and against independent
recomputations: Phi and phi_base are the raw columns; E/(W H L mu) is the
strain energy over the box's W L, the cylinders' height H and mu; Z is
recounted here with plain loops over the last contacts file (the two-node
rule over node-to-face contacts); the candidate nodes of the wall contacts
read from fields.h5 lie on their planes (the node numbering of the contact
files is the fields' in 3D too); the analysis's volume centroids from the
tetrahedra are the driver's from the boundary faces; the finite elements'
stress is the Cauchy integrals over the box's volume; the standing
cylinders' branch vectors are horizontal (fabric_zz ~ 0).
"""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from softpack.analysis import stress
from softpack.analysis.observables import series_columns
from softpack.contract.run_directory import EXIT_DONE
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.simulation.run import run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
STEPS = 36


@pytest.fixture(scope="module")
def cylinders(tmp_path_factory):
    require_driver()
    config = cfg.load_config(EXAMPLES / "cylinders3d_small.toml",
                             {"stop.steps": STEPS, "output.every_steps": 12,
                              "output.fields_every": 1,
                              "walls.right.velocity": [-2.0, 0.0]})
    out = tmp_path_factory.mktemp("cyl3d")
    assert run(config, out, verbose=False) == EXIT_DONE
    return out


def test_series_has_the_3d_columns_and_the_raw_fractions(cylinders):
    with open(cylinders / "series.csv") as f:
        header = next(csv.reader(f))
    assert tuple(header) == series_columns(3)
    s = read_table(cylinders / "series.csv")
    raw = read_table(cylinders / "raw" / "steps.csv")
    assert len(s["step"]) == STEPS // 12 + 1
    assert np.array_equal(s["phi"], raw["phi"])
    assert np.array_equal(s["phi_base"], raw["phi_base"])
    setup = json.loads((cylinders / "raw" / "setup.json").read_text())
    mu = setup["material"]["parameters"]["shear_modulus"]
    # E / (W H L mu): 3D energies in J, H the cylinders' height
    np.testing.assert_allclose(
        s["E_over_WHLmu"], raw["strain_energy"] / (0.078 * 0.015 * 0.110
                                                   * mu), rtol=1e-10)
    assert s["strain_energy"][-1] == raw["strain_energy"][-1] > 0
    assert s["piston_force"][-1] == pytest.approx(raw["right_fx"][-1])
    from softpack.api import read_run  # the Python API reads them too

    for table in ("series", "particles", "network", "stress"):
        assert len(read_run(cylinders, table)["step"]) > 0
    assert "centroid_z" in read_run(cylinders, "particles")


def z_by_loops(contacts, count, threshold, unbalanced_threshold):
    """Z recounted with the default rules (loaded_nodes, total normal
    force, excluded contacts kept), one contact row at a time."""
    fn = np.abs(contacts["fn"])
    largest = fn.max()
    nodes = {}
    resultant = np.zeros((count, 3))
    for k in range(len(fn)):
        c, a, w = (int(contacts[n][k]) for n in ("candidate", "antagonist",
                                                   "wall"))
        f = np.array([contacts[n][k] for n in ("fx", "fy", "fz")])
        resultant[c] += f
        if a >= 0:
            resultant[a] -= f
        if fn[k] > 0 and fn[k] > threshold * largest:
            key = (min(c, a), max(c, a)) if a >= 0 else (c, -1 - w)
            nodes.setdefault(key, set()).add((c, int(contacts["node"][k])))
    counted = [key for key, n in nodes.items() if len(n) >= 2]
    per_body = np.zeros(count, int)
    for i, j in counted:
        per_body[i] += 1
        if j >= 0:
            per_body[j] += 1
    unbalanced = (np.linalg.norm(resultant, axis=1)
                  > unbalanced_threshold * fn.sum())
    retained = ~unbalanced & (per_body > 0)
    return (per_body[retained].sum() / retained.sum() if retained.any()
            else np.nan), int(retained.sum())


def test_z_is_recounted_by_hand(cylinders):
    s = read_table(cylinders / "series.csv")
    last = int(s["step"][-1])
    contacts = read_table(cylinders / "raw" / "contacts"
                        / f"step_{last:08d}.csv")
    for threshold in (1e-3, 1e9):  # the run's rule, and none unbalanced
        z, retained = z_by_loops(contacts, 14, 1e-4, threshold)
        if threshold == 1e-3:
            assert retained == s["retained"][-1]
            assert z == pytest.approx(s["z"][-1], nan_ok=True)
    # with no particle unbalanced: every touching cylinder counts
    assert retained > 0 and z > 0
    # every standing cylinder touches the base: Z without the base and
    # the lid is below Z where both count the same particles
    same = s["retained_without_base"] == s["retained"]
    assert np.all(s["z_without_base"][same & (s["retained"] > 0)]
                  < s["z"][same & (s["retained"] > 0)])


def test_contact_nodes_and_centroids_agree_with_the_fields(cylinders):
    times, geometries = stress.stored_geometries(cylinders, 14)
    s = read_table(cylinders / "raw" / "steps.csv")
    p = read_table(cylinders / "raw" / "particles.csv")
    k = len(s["step"]) - 1
    geometry = geometries[int(np.argmin(np.abs(times - s["time"][k])))]
    mine = p["step"] == s["step"][k]
    driver = np.column_stack([p[f"centroid_{a}"][mine] for a in "xyz"])
    np.testing.assert_allclose(geometry.centres, driver, atol=1e-12)
    contacts = read_table(cylinders / "raw" / "contacts"
                        / f"step_{int(s['step'][k]):08d}.csv")
    table = {n: contacts[n].astype(int) for n in ("candidate", "node")}
    points = stress.contact_points(table, geometry)
    names = ("left", "right", "bottom", "top", "base", "lid")
    for wall in np.unique(contacts["wall"][contacts["wall"] >= 0]):
        name = names[int(wall)]
        axis = "xxyyzz"[int(wall)]
        on = contacts["wall"] == wall
        coordinate = points[on, "xyz".index(axis)]
        # within the alert distance (1.3e-3 m) of the plane
        assert np.abs(coordinate - s[f"{name}_{axis}"][k]).max() < 1.3e-3


def test_stress_csv_has_the_three_3d_estimates(cylinders):
    t = read_table(cylinders / "stress.csv")
    raw = read_table(cylinders / "raw" / "steps.csv")
    assert list(t)[:3] == ["step", "time", "volume"]
    volume = ((raw["right_x"] - raw["left_x"]) * (raw["top_y"]
              - raw["bottom_y"]) * (raw["lid_z"] - raw["base_z"]))
    np.testing.assert_allclose(t["volume"], volume, rtol=1e-10)
    for c in ("xx", "yy", "zz", "xz", "zy"):
        np.testing.assert_allclose(t[f"fe_{c}"], -raw[f"cauchy_{c}"] / volume,
                                   rtol=1e-10)
    # the piston's normal stress: its force over its current area
    area = (raw["top_y"] - raw["bottom_y"]) * (raw["lid_z"] - raw["base_z"])
    np.testing.assert_allclose(t["right_stress"], raw["right_fx"] / area,
                               rtol=1e-10)
    assert np.all(np.isfinite(t["contact_xx"][1:]))
    fe_p = -(raw["cauchy_xx"] + raw["cauchy_yy"] + raw["cauchy_zz"]) / (
        3 * volume)
    np.testing.assert_allclose(t["fe_P"], fe_p, rtol=1e-10)


def test_network_and_fabric_are_3d(cylinders):
    n = read_table(cylinders / "network.csv")
    assert {"fz", "branch_z"} <= set(n)
    s = read_table(cylinders / "series.csv")
    pairs = n["b"] >= 0
    assert pairs.sum() > 0
    # standing cylinders: their centroids at one height, branches flat
    assert np.nanmax(np.abs(s["fabric_zz"])) < 1e-2
    assert np.nanmax(s["fabric_anisotropy"]) > 3.0  # 3.75: flat, isotropic


def test_the_plane_strain_comparison_reads_the_3d_columns(cylinders):
    """``./softpack plot-plane-strain`` takes a 3D run's phi_base, its
    piston force over the cylinders' height and z_without_base."""
    from softpack.plots.plane_strain import read_curve

    s = read_table(cylinders / "series.csv")
    setup = json.loads((cylinders / "raw" / "setup.json").read_text())
    height = setup["scene"]["model"]["thickness"]
    curve = read_curve("3D", cylinders)
    assert curve.dimension == 3
    np.testing.assert_array_equal(curve.phi, s["phi_base"])
    np.testing.assert_allclose(curve.force, s["piston_force"] / height,
                               rtol=1e-15)
    np.testing.assert_allclose(curve.energy, s["strain_energy"] / height,
                               rtol=1e-15)
    np.testing.assert_array_equal(curve.z, s["z_without_base"])


def test_the_cylinders_axial_strain_is_their_height_over_their_rest(cylinders):
    """analysis/standing.py: each body's ln(h / H), h its top face's mean
    height over its bottom face's, and its bottom face's lift, recounted
    here body by body from the snapshot's tetrahedra; the squeezed
    cylinders rise (free tops), where plane strain holds them."""
    from softpack.analysis import fields
    from softpack.analysis.standing import standing

    path = cylinders / "fields.h5"
    st = standing(path)
    assert len(st.times) == STEPS // 12 + 1
    np.testing.assert_array_equal(st.axial[0], 0.0)
    np.testing.assert_array_equal(st.lift[0], 0.0)
    last = fields.read_snapshot(path, st.times[-1])
    x = last.points + last.displacement
    for b in (0, last.body.max()):
        nodes = np.unique(last.cells[last.body == b])
        z0 = last.points[nodes, 2]
        # (gmsh's faces are flat to round-off, not to the bit)
        bottom = nodes[np.abs(z0 - z0.min()) <= 1e-9 * 0.015]
        top = nodes[np.abs(z0 - z0.max()) <= 1e-9 * 0.015]
        assert z0.max() - z0.min() == pytest.approx(0.015, rel=1e-12)
        h = x[top, 2].mean() - x[bottom, 2].mean()
        assert st.axial[-1, b] == pytest.approx(np.log(h / 0.015),
                                                rel=1e-12, abs=1e-15)
        assert st.lift[-1, b] == pytest.approx(
            x[bottom, 2].mean() - z0[np.isin(nodes, bottom)].mean(),
            abs=1e-15)
    assert st.axial[-1].mean() > 0
