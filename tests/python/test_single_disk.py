"""The 2D single-disk check (softpack.references.single_disk, paper Figs. 2 and 3).

Helpers are tested on hand-made data; the physics with softpack-simulate
(skipped when it is not built) on three CI-sized runs, each driver call a
few seconds on one core:

* ``coarse``: h = 2 mm (206 triangles), up to eps = 0.2 through the
  command line (``main``), the files it writes;
* ``paper_mesh``: h = 1.065 mm (the paper's, 669 triangles), up to
  eps = 0.15;
* ``fine_small_strain``: h = 0.5325 mm (2604 triangles), up to eps = 0.012,
  for Johnson's small-strain limit.

The tolerances are at most ~10x the measured values; each test says what
was measured, on this code on 2026-12-03 (as the 2D numbers of
docs/single_disk/README.md, regenerated that day).
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from softpack.references import between_plates
from softpack.references import single_disk as sd
from softpack.references.cylinder3d import johnson_line_contact
from softpack.scene.config import ConfigError

DOCS = Path(__file__).resolve().parents[2] / "docs" / "single_disk"
FORCE_3D = DOCS / "force_3d_nu0495.csv"
PROFILE_3D = DOCS / "profile_3d_nu0495.csv"


def _read(path):
    return np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))


# ------------------------------------------------------------ helpers

def test_config_loads_symmetrically_and_stops_past_the_target(registry,
                                                              tmp_path):
    """The protocol's overrides on top of the production defaults, through
    the one driver.json writer."""
    from softpack.contract.schema import load_schema
    from softpack.simulation.driver_input import driver_document

    p = sd.Params()
    config = sd.single_disk_config(p, -0.01, 0.01)
    doc = driver_document(config, {"bodies": {}}, tmp_path)
    bottom, top = doc["walls"]
    assert (bottom["name"], top["name"]) == ("bottom", "top")
    assert bottom["normal"] == [0.0, 1.0] and top["normal"] == [0.0, -1.0]
    assert bottom["point"] == [0.0, -0.01] and top["point"] == [0.0, 0.01]
    assert bottom["velocity"] == [0.0, p.speed]
    assert top["velocity"] == [0.0, -p.speed]
    assert config["box"]["enabled"] is False
    assert doc["stop"]["packing_fraction"] == 0.0
    # both plates together approach by at least delta_max before the stop
    approach = 2 * p.speed * doc["stop"]["max_time"]
    assert approach >= p.diameter * (1 - math.exp(-p.max_strain))
    assert doc["material"]["parameters"]["lame_lambda"] == pytest.approx(
        2 * doc["material"]["parameters"]["shear_modulus"])
    # the protocol's own values ...
    assert doc["contact"]["friction"] == p.friction == 0.01
    assert (doc["time"]["time_step"], doc["time"]["theta"],
            doc["damping"]["alpha"]) == (1e-4, 0.5, 200.0)
    # ... and the production defaults for every other numerical setting
    schema = load_schema()
    for section, keys in (("contact", ("alert_distance", "max_penetration",
                                       "nlgs_tolerance", "nlgs_max_sweeps",
                                       "nlgs_relaxation")),
                          ("time", ("newton_tolerance", "tangent_reuse_steps",
                                    "full_newton", "newton_max_iterations",
                                    "refactor_above_iterations", "mass")),
                          ("damping", ("beta",))):
        for key in keys:
            assert doc[section][key] == schema[section].parameters[key].default
    assert doc["contact"]["delassus_drop_tolerance"] == pytest.approx(
        doc["contact"]["nlgs_tolerance"] / 1000)


def test_the_schema_refuses_a_plate_faster_than_the_alert_distance(
        registry):
    with pytest.raises(ConfigError, match="alert_distance"):
        sd.single_disk_config(sd.Params(speed=10.0))


@pytest.mark.parametrize("argv, message", [
    (["--max-strain", "1.5"], "--max-strain must be in (0, 1)"),
    (["--speed", "10"], "alert_distance"),
    (["--shape", "square", "--speed", "10"], "alert_distance"),
    (["--shape", "pentagon", "--max-strain", "2"],
     "--max-strain must be in (0, 1)"),
])
def test_disk_and_polygons_refuse_bad_input_before_meshing(
        registry, tmp_path, capsys, argv, message):
    """Both commands (disk, and polygon through plates.main) check
    --max-strain, the schema and the output directory alike, exit 2 and
    write nothing."""
    out = tmp_path / "out"
    assert sd.main(argv + ["--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("softpack single-disk: ") and message in err, err
    assert not out.exists()


def test_an_unusable_out_directory_is_refused(registry, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory\n")
    for shape in ("disk", "square"):
        assert sd.main(["--shape", shape, "--out", str(blocker)]) == 2
        assert "softpack single-disk: " in capsys.readouterr().err


def test_line_interpolation_is_exact_for_a_linear_field():
    x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    cells = np.array([[0, 1, 2], [1, 3, 2]])
    u = np.column_stack([2 * x[:, 0] - x[:, 1] + 0.5, 3 * x[:, 1]])
    points = np.array([[0.25, 0.25], [0.9, 0.8], [1.0, 0.5], [0.5, 0.0]])
    values = sd.interpolate(u, cells, sd.line_interpolator(x, cells, points))
    expected = np.column_stack([2 * points[:, 0] - points[:, 1] + 0.5,
                                3 * points[:, 1]])
    np.testing.assert_allclose(values, expected, atol=1e-14)


def test_rigid_rotation_sees_rolling_and_ignores_symmetric_stretch():
    rng = np.random.default_rng(1)
    angles = np.sort(rng.uniform(0, 2 * np.pi, 40))
    x = np.vstack([[0.0, 0.0], np.column_stack([np.cos(angles),
                                                np.sin(angles)])])
    cells = np.array([[0, i, i % 40 + 1] for i in range(1, 41)])
    theta = 0.3
    rot = np.array([[np.cos(theta), -np.sin(theta)],
                    [np.sin(theta), np.cos(theta)]])
    assert sd.rigid_rotation(x, cells, x @ rot.T - x) == pytest.approx(theta)
    # a stretch along the axes: exactly no rotation on any mesh
    stretch = x * [0.1, -0.2]
    assert abs(sd.rigid_rotation(x, cells, stretch)) < 1e-14
    # a non-affine field symmetric about both axes: its P1 interpolant on
    # this irregular mesh is not exactly symmetric (measured 2.03e-6 rad)
    u = np.column_stack([0.1 * x[:, 0] * (1 + x[:, 1] ** 2),
                         -0.2 * x[:, 1] * (1 + x[:, 0] ** 2)])
    assert abs(sd.rigid_rotation(x, cells, u)) < 2e-5


def test_put_node_up_turns_the_mesh_about_its_centre(tmp_path):
    pytest.importorskip("dolfinx")
    from softpack.scene.mesh import mesh_disks

    radius = 0.01
    info = mesh_disks([(0.0, 0.0)], [radius], 1.065e-3, tmp_path / "disk")
    before = between_plates.reference_nodes(info.h5)
    angle = sd.put_node_up(info.h5, radius)
    after = between_plates.reference_nodes(info.h5)
    boundary = sd.on_circle(after, radius)
    assert boundary.sum() == 59  # the paper's h: 59 nodes around D = 20 mm
    top = after[boundary][np.argmax(after[boundary, 1])]
    assert abs(top[0]) < 1e-12 and top[1] == pytest.approx(radius)
    assert abs(angle) <= np.pi / 59 + 1e-12
    # a rigid rotation: distances to the centre unchanged
    np.testing.assert_allclose(np.hypot(*after.T), np.hypot(*before.T),
                               atol=1e-15)
    # 59 is odd: the polygon is mirror-symmetric about the loading axis
    mirrored = after[boundary] * [-1.0, 1.0]
    gaps = np.min(np.hypot(*(mirrored[:, None] - after[boundary]).T), axis=0)
    assert gaps.max() < 1e-12


# ------------------------------------------------------------ with the driver

@pytest.fixture(scope="module")
def coarse(tmp_path_factory):
    """h = 2 mm up to eps = 0.2 through the command line."""
    require_driver()
    out = tmp_path_factory.mktemp("coarse")
    status = sd.main(["--element-size", "2e-3", "--max-strain", "0.2",
                      "--out", str(out)])
    assert status == 0
    return out


@pytest.fixture(scope="module")
def paper_mesh(tmp_path_factory):
    """The paper's element size, up to eps = 0.15."""
    require_driver()
    out = tmp_path_factory.mktemp("paper_mesh")
    params = sd.Params(element_size=1.065e-3, max_strain=0.15)
    return sd.run(params, out), out


@pytest.fixture(scope="module")
def fine_small_strain(tmp_path_factory):
    """h = 0.5325 mm up to eps = 0.012."""
    require_driver()
    out = tmp_path_factory.mktemp("fine")
    params = sd.Params(element_size=0.5325e-3, max_strain=0.012)
    return sd.run(params, out)


def test_command_line_writes_the_two_csv_files(coarse):
    force = _read(coarse / "force_2d.csv")
    assert force.dtype.names == ("eps", "f_norm")
    assert force["eps"][0] == 0 and force["f_norm"][0] == 0
    assert 0.2 <= force["eps"][-1] < 0.2 + 0.002
    profile = _read(coarse / "profile_2d.csv")
    assert profile.dtype.names == ("eps", "w", "ux_over_D")
    assert sorted(set(profile["eps"].round(6))) == [0.05, 0.1, 0.15, 0.2]
    grid_3d = _read(PROFILE_3D)["w"] if PROFILE_3D.exists() else sd.PROFILE_W
    np.testing.assert_allclose(
        profile["w"][profile["eps"] == 0.05], np.unique(grid_3d), atol=1e-9)
    meta = json.loads((coarse / "run_2d.json").read_text())
    assert meta["mesh"]["triangles"] == 206
    assert meta["max_penetration_m"] < 1e-9  # measured 2.2e-10 m


def test_force_grows_monotonically_and_both_plates_agree(paper_mesh):
    """f (the mean of the two plates) increases at every output. The two
    plates' forces differ by a small vibration of the disk between them
    (the mean cancels it): measured at most 2.9 % of f over
    0.01 <= eps < 0.05 and 0.26 % beyond (2026-12-03, README)."""
    result, _ = paper_mesh
    curve = result["curve"]
    assert np.all(np.diff(curve["f_norm"]) > 0)
    mismatch = np.abs(curve["f_norm_top"] - curve["f_norm_bottom"])
    early = (curve["eps"] >= 0.01) & (curve["eps"] < 0.05)
    assert np.all(mismatch[early] < 0.05 * curve["f_norm"][early])
    late = curve["eps"] >= 0.05
    assert np.all(mismatch[late] < 0.01 * curve["f_norm"][late])


def test_friction_pins_the_rolling_mode(paper_mesh):
    """With friction 0.01 the disk turns by < 1e-3 rad (measured 2.5e-4
    rad, centre drift 1.9e-4 D, 2026-12-03); frictionless it rolls by
    0.16 rad (README)."""
    result, out = paper_mesh
    meta = json.loads((out / "run_2d.json").read_text())
    assert meta["max_rigid_rotation_rad"] < 1e-3
    assert meta["centre_drift_over_D"] < 1e-3


def test_small_strain_limit_is_johnson_line_contact(fine_small_strain):
    """Johnson (plane strain, nu = 1/3, E* = 3 mu) at eps = 0.01: within
    3 %. Measured f_2D/f_J = 1.014 at h = 0.53 mm, 0.999 at 0.27 mm, 1.054
    at the paper's h = 1.065 mm (1.5 elements across the contact)
    (2026-12-03, README)."""
    f = sd.value_at(fine_small_strain["curve"], 0.01)
    ratio = f / johnson_line_contact(0.01, 1.0 / 3.0)[0]
    assert abs(ratio - 1) < 0.03


def test_halving_the_element_size_changes_the_force_little(coarse,
                                                           paper_mesh):
    """h = 2 mm -> 1.065 mm changes f_norm(0.15) by < 2 % (measured
    1.1 %, 2026-12-03 and README); 1.065 -> 0.53 -> 0.27 mm: -0.65 %,
    -0.13 % (README)."""
    force = _read(coarse / "force_2d.csv")
    f_coarse = np.interp(0.15, force["eps"], force["f_norm"])
    f_paper = sd.value_at(paper_mesh[0]["curve"], 0.15)
    assert abs(f_coarse / f_paper - 1) < 0.02


@pytest.mark.skipif(not FORCE_3D.exists(), reason="no 3D reference CSV")
def test_2d_and_3d_forces_agree_within_the_measured_gap(paper_mesh):
    """2D (paper's mesh) vs 3D nu = 0.495 (0.5 mm P2, docs/single_disk):
    2D/3D - 1 in [-6 %, -2 %] over 0.02 <= eps <= 0.15 (measured -5.2 %,
    at eps = 0.025 where the 2D curve has a wiggle as boundary nodes touch
    the plates, to -2.9 %; within -5 % elsewhere; 2026-12-03). The
    mesh-converged 2D
    is lower still (h = 0.27 mm: -7.6 % at eps = 0.02, -3.6 % at 0.15):
    the 3D cylinder (l/D = 0.75) is stiffer than the plane-stress law the
    2D model stands for (README)."""
    ref = _read(FORCE_3D)
    eps = np.arange(0.02, 0.1501, 0.0025)
    f2 = sd.value_at(paper_mesh[0]["curve"], eps)
    f3 = np.interp(eps, ref["eps"], ref["f_norm"])
    gap = f2 / f3 - 1
    assert np.all(gap > -0.06) and np.all(gap < -0.02)


def test_profile_is_antisymmetric_and_grows_with_strain(paper_mesh):
    """u_x/D along Y = 0: odd in w, increasing in w (for |w| <= 0.8),
    growing with eps; at
    w = 1, 5-15 % above the 3D mid-plane profile (measured +9 % to +10 %,
    2026-12-03 +10.5 %:
    plane strain with nu = 1/3 bulges more than the 3D cylinder's
    mid-plane, and 20 % less than its end face)."""
    profiles = paper_mesh[0]["profiles"]
    w = sd.PROFILE_W
    previous = np.zeros_like(w)
    for eps in (0.05, 0.10, 0.15):
        u = profiles[eps]
        # measured at most 1.8e-3 u.max (2026-12-03)
        np.testing.assert_allclose(u, -u[::-1], atol=2e-3 * u.max())
        # increasing, except for a flat top next to the free surface
        # (measured: dips of up to 2.2e-3 u_x(1) between |w| = 0.95 and 1)
        inner = np.abs(w) <= 0.8
        assert np.all(np.diff(u[inner]) > 0)
        assert np.all(np.diff(u) > -5e-3 * u.max())
        assert np.all(u[w > 0] > previous[w > 0])
        previous = u
    if PROFILE_3D.exists():
        ref = _read(PROFILE_3D)
        for eps in (0.05, 0.10, 0.15):
            at = (np.abs(ref["eps"] - eps) < 1e-6) & (ref["w"] == 1.0)
            ratio = profiles[eps][-1] / ref["ux_over_D"][at][0]
            assert 1.05 < ratio < 1.15


def test_plot_single_disk_uses_the_2d_files(coarse, tmp_path):
    pytest.importorskip("matplotlib")
    from softpack.plots import single_disk as plots_single_disk

    for name in ("force_2d.csv", "profile_2d.csv"):
        (tmp_path / name).write_text((coarse / name).read_text())
    assert plots_single_disk.main([str(tmp_path)]) == 0
    for name in ("fig2_force.png", "fig3_profile.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
