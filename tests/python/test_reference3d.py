"""Physical checks of the 3D single-cylinder reference (softpack.references.cylinder3d).

CI-sized: a coarse mesh (2 mm tetrahedra near the contact, 263 cells, P2) up
to eps = 0.15 in 15 steps, once per model; about 30 s on one core with a warm
FFCx cache (the first run also compiles the forms, ~20 s more).
"""

import json

import numpy as np
import pytest

pytest.importorskip("dolfinx")
from softpack.contract.tables import read_table  # noqa: E402
from softpack.references import cylinder3d as r3d  # noqa: E402  (python/ on sys.path: conftest.py)

CI_MESH = dict(element_size=0.002, max_strain=0.15, n_steps=15)


@pytest.fixture(scope="module")
def nearly_incompressible():
    return r3d.compress_cylinder_3d(nu=0.495, **CI_MESH)


@pytest.fixture(scope="module")
def incompressible():
    return r3d.compress_cylinder_3d(nu=None, **CI_MESH)


def _at(res, eps):
    i = int(np.argmin(np.abs(np.asarray(res.eps) - eps)))
    assert abs(res.eps[i] - eps) < 1e-9
    return res.f_norm[i]


@pytest.mark.parametrize("model", ["nearly_incompressible", "incompressible"])
def test_plate_work_equals_stored_energy(model, request):
    """Quasi-static and frictionless: int f d(delta) = strain + penalty energy.

    The work is a trapezoidal integral over 15 steps: its error, measured
    2026-12-03 (both models), is 8.1e-4 of the stored energy at the end,
    at most 4.8e-3 of the energy stored so far past eps = 0.04 (6 % at the
    first step) and at most 8.1e-4 of the final energy at any step.
    """
    res = request.getfixturevalue(model)
    work = np.asarray(res.work)
    stored = np.asarray(res.energy) + np.asarray(res.penalty_energy)
    assert abs(r3d.energy_balance(res)) < 8e-3
    # every step, against the final energy (the first steps store ~nothing)
    assert np.all(np.abs(work - stored) < 8e-3 * stored[-1])
    for k in range(5, len(work)):          # every step past eps = 0.04
        assert abs(work[k] - stored[k]) < 0.01 * stored[k]
    # the penalty plate is nearly rigid: its energy and penetration are tiny
    # (measured 5.7e-4 and 6.2e-4 of the energy, 2.9e-4 of delta)
    assert res.penalty_energy[-1] < 1e-3 * res.energy[-1]
    assert res.max_overlap < 1e-3 * res.delta[-1]


@pytest.mark.parametrize("model", ["nearly_incompressible", "incompressible"])
def test_force_monotonic_and_in_equilibrium(model, request):
    res = request.getfixturevalue(model)
    f = np.asarray(res.force)
    assert np.all(np.diff(f) > 0)
    # stiffening: the secant f/eps grows with eps (geometric + contact growth)
    secant = f[1:] / np.asarray(res.eps[1:])
    assert np.all(np.diff(secant) > 0)
    # plate force and the reaction on the symmetry plane y = 0 balance
    # (measured 9.2e-13 and 2.6e-13 apart, 2026-12-03)
    np.testing.assert_allclose(res.force_sym[1:], f[1:], rtol=1e-11)


def test_small_strain_force_between_line_contact_estimates(nearly_incompressible):
    """A short cylinder with free ends lies between plane stress and plane strain.

    Johnson's line-contact formula with E* = E/(1 - nu^2) (plane strain) is an
    upper estimate for the 3D cylinder (l/D = 0.75, free end faces), E* = E
    (plane stress) a lower one. At eps = 0.05 this coarse mesh gives 1.0743 x
    the plane-stress and 0.811 x the plane-strain value (measured
    2026-12-03; the 0.5 mm mesh 1.06 x, docs/single_disk/README.md). The
    run is deterministic: the ratio is held to 1 % of what was measured, so
    that a change of the model, the mesh or the solve that moves the 3D
    force by a percent is seen (the bounds alone allowed -20 %/+23 %).
    """
    f = _at(nearly_incompressible, 0.05)
    upper = r3d.johnson_line_contact(0.05, 0.495, plane_strain=True)[0]
    lower = r3d.johnson_line_contact(0.05, 0.495, plane_strain=False)[0]
    assert lower < f < upper
    assert f / lower == pytest.approx(1.0743, rel=1e-2)


def test_nearly_incompressible_matches_incompressible(nearly_incompressible, incompressible):
    """nu = 0.495 (lmbda = 99 mu) vs J = 1: within 2 % for eps <= 0.05
    (measured 2026-12-03: at most 1.56 %, at eps = 0.02), and 2 % beyond
    (measured 0.22 %; formerly 3 %)."""
    a, b = nearly_incompressible, incompressible
    np.testing.assert_allclose(a.eps, b.eps)
    fa, fb = a.f_norm[1:], b.f_norm[1:]
    small = np.asarray(a.eps[1:]) <= 0.05 + 1e-12
    assert np.all(np.abs(fa[small] / fb[small] - 1) < 0.02)
    assert np.all(np.abs(fa[~small] / fb[~small] - 1) < 0.02)


def test_transverse_profile(nearly_incompressible):
    """u_x along the transverse diameter: odd in w, outward, growing with eps.

    (Not monotonic in w: on fine meshes u_x dips slightly next to w = 1.)
    """
    prof = nearly_incompressible.profiles_mid
    assert sorted(prof) == [0.05, 0.10, 0.15]
    edge = []
    for eps in sorted(prof):
        w, ux = prof[eps]
        assert w[0] == pytest.approx(-1.0) and w[-1] == pytest.approx(1.0)
        np.testing.assert_allclose(ux, -ux[::-1], atol=1e-14)
        off_axis = w > 1e-9                          # w = 0 is computed as ~1e-18
        assert np.all(ux[off_axis] > 0)              # material moves away from the axis
        edge.append(ux[-1])
    assert np.all(np.diff(edge) > 0)
    # the lateral bulge is a fraction of the imposed approach delta/D = 1 - e^-eps
    assert 0.1 * (1 - np.exp(-0.15)) < edge[-1] < 0.5 * (1 - np.exp(-0.15))


def test_csv_files_and_plots(nearly_incompressible, tmp_path):
    r3d.write_csvs(nearly_incompressible, tmp_path)
    force = read_table(tmp_path / "force_3d_nu0495.csv")
    assert list(force) == ["eps", "f_norm"]
    np.testing.assert_allclose(force["f_norm"], nearly_incompressible.f_norm, rtol=1e-11, atol=1e-15)
    prof = read_table(tmp_path / "profile_3d_nu0495.csv")
    assert list(prof) == ["eps", "w", "ux_over_D"]
    assert set(np.round(prof["eps"], 6)) == {0.05, 0.10, 0.15}

    from softpack.plots import single_disk as plots_single_disk
    assert plots_single_disk.main([str(tmp_path)]) == 0    # 3D files only
    assert (tmp_path / "fig2_force.png").stat().st_size > 0
    assert (tmp_path / "fig3_profile.png").stat().st_size > 0


def test_johnson_estimate_is_the_inverse_of_the_formula():
    p = r3d.johnson_line_contact([0.02, 0.1], 0.5)
    k = 4.0     # E*/mu for nu = 1/2, plane strain
    approach = 2 * p / (np.pi * k) * (2 * np.log(4 / np.sqrt(8 * p / (np.pi * k))) - 1)
    np.testing.assert_allclose(approach, 1 - np.exp(-np.array([0.02, 0.1])), rtol=1e-10)


def test_cli_writes_the_csv_files(tmp_path):
    """The module's CLI end to end on a tiny run (eps = 0.05 in 2 steps, 3 mm mesh)."""
    argv = ["--out", str(tmp_path), "--element-size", "0.003", "--incompressible",
            "--max-strain", "0.05", "--steps", "2"]
    assert r3d.main(argv) == 0
    force = read_table(tmp_path / "force_3d_incompressible.csv")
    np.testing.assert_allclose(force["eps"], [0.0, 0.025, 0.05])
    # measured 0.04895 (2026-12-03): deterministic, held to 1 %
    assert force["f_norm"][-1] == pytest.approx(0.04895, rel=1e-2)
    for name in ("profile_3d_incompressible.csv", "profile_3d_incompressible_endface.csv",
                 "energy_3d_incompressible.csv", "run_3d_incompressible.json"):
        assert (tmp_path / name).stat().st_size > 0


def test_a_standing_cylinder_between_plates_through_the_3d_driver(tmp_path):
    """./softpack single-disk --shape cylinder, 3 mm tetrahedra to eps =
    0.03: the free-ended cylinder and the plane-strain slab (its faces on
    frictionless planes) load the two plates alike, the slab stiffer by
    less than plane strain over plane stress at nu = 1/3 (E* 3 mu against
    8/3 mu: 1.125), the free cylinder lying between the two."""
    from softpack.references import cylinder_plates

    curves = {}
    for slab in (False, True):
        out = tmp_path / ("slab" if slab else "free")
        argv = ["--out", str(out), "--max-strain", "0.03",
                "--element-size", "3e-3"] + (["--slab"] if slab else [])
        assert cylinder_plates.main(argv) == 0
        curve = read_table(out / "force_3d_driver.csv")
        record = json.loads((out / "run_3d_driver.json").read_text())
        assert record["max_plate_mismatch_over_f"] < 0.02
        assert curve["eps"][-1] >= 0.03
        assert np.all(np.diff(curve["f_norm"][curve["eps"] > 0.002]) > 0)
        curves[slab] = curve
    ratio = (np.interp(0.025, curves[True]["eps"], curves[True]["f_norm"])
             / np.interp(0.025, curves[False]["eps"],
                         curves[False]["f_norm"]))
    assert 1.0 < ratio < 1.125


def test_the_3d_driver_with_the_nodal_pressure_does_not_lock(tmp_path,
                                                            incompressible):
    """The standing cylinder through the 3D driver at nu = 0.499 (3 mm
    tetrahedra, to eps = 0.1) against the Taylor-Hood cylinder (J = 1, the
    module's fixture; 0.5 mm differs from it by 0.2 % at eps = 0.1, and
    nu = 0.499 from J = 1 by ~0.1 %). With neo_hookean's volumetric energy
    per tetrahedron the P1 cylinder locks: +45 % measured. With the averaged
    nodal pressure (neo_hookean_nodal) it carries the mesh's own error:
    +6.3 % measured, where the same mesh at nu = 1/3 (no locking) is +8.3 %
    above its own P2 reference (docs/incompressible.md, "On tetrahedra")."""
    from softpack.references import cylinder_plates

    taylor_hood = _at(incompressible, 0.1)
    f = {}
    for law in ("neo_hookean", "neo_hookean_nodal"):
        out = tmp_path / law
        assert cylinder_plates.main(
            ["--out", str(out), "--max-strain", "0.1", "--element-size",
             "3e-3", "--law", law, "--lame-lambda", "74.85e6"]) == 0
        curve = read_table(out / "force_3d_driver.csv")
        assert curve["eps"][-1] >= 0.1
        f[law] = np.interp(0.1, curve["eps"], curve["f_norm"]) / taylor_hood
    assert f["neo_hookean"] > 1.3
    assert abs(f["neo_hookean_nodal"] - 1) < 0.1
