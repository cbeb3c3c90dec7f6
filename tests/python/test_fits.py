"""The Eq. 14 fit: recovers a known Phi_T within its reported uncertainty,
and refuses data that do not constrain it."""

import numpy as np
import pytest

from softpack.analysis import fits

TRUE_PHI_T = 0.79


def synthetic(rng, n=150, noise=0.08, top=0.88, phi_t=TRUE_PHI_T):
    """Z on the law above phi_t, 2 below it, Gaussian noise; Phi sorted."""
    phi = np.sort(rng.uniform(0.75, top, n))
    z = np.where(phi > phi_t, fits.connectivity_law(phi, phi_t), 2.0)
    return phi, z + noise * rng.standard_normal(n)


def test_connectivity_law_anchors():
    assert fits.connectivity_law(0.785, 0.785) == 3.0
    assert fits.connectivity_law(0.9, 0.785) == pytest.approx(4.72)
    assert fits.connectivity_law(0.70, 0.785) == 3.0


def test_exact_data_give_phi_t_to_the_grid():
    phi = np.linspace(0.75, 0.88, 200)
    z = np.where(phi > TRUE_PHI_T, fits.connectivity_law(phi, TRUE_PHI_T),
                 2.0)
    fit = fits.fit_rigidity_transition(phi, z)
    assert fit.ok and fit.phi_t == pytest.approx(TRUE_PHI_T, abs=2e-4)
    assert fit.error <= 2e-4


def test_noisy_data_are_recovered_within_the_reported_error():
    """Over 20 noisy draws the 2-sigma interval holds Phi_T >= 80 % of the
    time (95 % expected for a Gaussian error), and the error is small."""
    rng = np.random.default_rng(3)
    results = [fits.fit_rigidity_transition(*synthetic(rng))
               for _ in range(20)]
    assert all(r.ok for r in results)
    inside = [abs(r.phi_t - TRUE_PHI_T) <= 2 * r.error for r in results]
    assert np.mean(inside) >= 0.8
    assert all(0 < r.error < 5e-3 for r in results)


def test_more_noise_gives_a_larger_error():
    rng = np.random.default_rng(4)
    quiet = fits.fit_rigidity_transition(*synthetic(rng, noise=0.02))
    loud = fits.fit_rigidity_transition(*synthetic(rng, noise=0.2))
    assert quiet.ok and loud.ok and loud.error > 2 * quiet.error


def test_several_seeds_give_the_spread_over_seeds():
    rng = np.random.default_rng(5)
    curves = [synthetic(rng, phi_t=t) for t in (0.785, 0.79, 0.795)]
    fit = fits.fit_runs(curves)
    assert fit.ok and len(fit.runs) == 3
    assert fit.phi_t == pytest.approx(0.79, abs=2e-3)
    assert fit.error == pytest.approx(0.005, rel=0.4)
    assert fit.method == "std over 3 seeds"


@pytest.mark.parametrize("top, why", [
    (0.795, "last 10 points"),        # barely reaches past Phi_T
    (0.80, "span 0.0080 < 0.01"),     # 14 points within 0.008 of the top
])
def test_data_that_stop_near_the_transition_are_refused(top, why):
    rng = np.random.default_rng(6)
    fit = fits.fit_rigidity_transition(*synthetic(rng, n=60, top=top))
    assert not fit.ok and why in fit.reason
    assert np.isnan(fit.phi_t) and np.isnan(fit.error)
    assert fit.summary().startswith("no Phi_T: ")


def test_flat_noise_and_too_few_points_are_refused():
    rng = np.random.default_rng(7)
    phi = np.linspace(0.75, 0.88, 100)
    flat = fits.fit_rigidity_transition(phi, 3.5 + 0.5
                                        * rng.standard_normal(100))
    assert not flat.ok
    few = fits.fit_rigidity_transition([0.8, 0.81, 0.82], [3, 3.2, 3.4])
    assert not few.ok and "3 usable points" in few.reason
    nan = fits.fit_rigidity_transition(phi, np.full(100, np.nan))
    assert not nan.ok and nan.points == 0


def test_data_entirely_above_the_transition_are_refused():
    """The scan cannot go below the data: Phi_T at its lowest edge."""
    rng = np.random.default_rng(8)
    phi = np.sort(rng.uniform(0.80, 0.88, 100))
    z = fits.connectivity_law(phi, 0.77) + 0.02 * rng.standard_normal(100)
    fit = fits.fit_rigidity_transition(phi, z)
    assert not fit.ok
    assert "lowest Phi" in fit.reason or "at an edge" in fit.reason


def test_one_good_run_among_refused_ones_says_so():
    rng = np.random.default_rng(9)
    good = synthetic(rng)
    bad = synthetic(rng, n=60, top=0.795)
    fit = fits.fit_runs([good, bad])
    assert fit.ok and fit.method.endswith("1 of 2 runs refused")
    assert not fits.fit_runs([bad, bad]).ok


def test_the_onset_is_where_binned_z_first_exceeds_z_t():
    phi = np.linspace(0.75, 0.88, 261)
    z = np.where(phi < 0.8, 2.5, 3.6)
    onset = fits.rigidity_onset(phi, z)
    # the first bin (0.005 wide, on a 0.0025 grid) whose mean passes 3
    assert 0.8 - fits.ONSET_BIN / 2 <= onset <= 0.8 + fits.ONSET_BIN / 2
    assert np.isnan(fits.rigidity_onset(phi, np.full_like(phi, 2.9)))
    assert np.isnan(fits.rigidity_onset(phi[:0], z[:0]))
    # the law's data leave 3 at Phi_T, within a bin
    law = fits.connectivity_law(phi, 0.79)
    assert abs(fits.rigidity_onset(phi, law) - 0.79) <= fits.ONSET_BIN
