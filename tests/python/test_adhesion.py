"""The adhesion check of issue 39 (docs/adhesion/README.md).

The line-contact theory (softpack.references.adhesion_theory) against
Baney & Hui's published equations and the JKR closed forms; then one
coarse run of ``./softpack adhesion`` (a few seconds): a disk pressed on a
cohesive flat and pulled off, its pull-off force against the
Maugis–Dugdale line contact within the error this mesh has in the
convergence study, and its energy balance.
"""

import math

import pytest
from scipy import optimize

from driver_required import require_driver
from softpack.references import adhesion, adhesion_measure
from softpack.references.adhesion_theory import LineContact

#: The default protocol's theory (R of the meshed arc, E* = 3 mu).
THEORY = LineContact(0.010007, 4.5e5, 2.8e4, 1.57e-5)


def _baney_hui_load(theory, a):
    """P(a) from Baney & Hui (1997), eq. 23 for m = c/a and
    P = a^2 - lambda a sqrt(m^2 - 1), in their units a* = 2 (w R^2 /
    (pi E*))^(1/3), P* = (pi E* w^2 R)^(1/3)."""
    e, r, w = theory.modulus, theory.radius, theory.work
    lam = theory.maugis_lambda
    a_unit = 2 * (w * r * r / (math.pi * e)) ** (1 / 3)
    p_unit = (math.pi * e * w * w * r) ** (1 / 3)
    ab = a / a_unit

    def eq23(m):
        mu = math.sqrt(m * m - 1)
        return (lam * ab * ab / 2 * (m * mu - math.log(m + mu))
                + lam * lam * ab / 2 * (mu * math.log(m + mu)
                                        - m * math.log(m)) - 1)

    m = optimize.brentq(eq23, 1 + 1e-14, 1e6, xtol=1e-15)
    return (ab * ab - lam * ab * math.sqrt(m * m - 1)) * p_unit


@pytest.mark.parametrize("a", [1e-4, 3e-4, 9e-4, 1.5e-3])
def test_maugis_dugdale_is_baney_and_hui(a):
    assert THEORY.md_load(a) == pytest.approx(_baney_hui_load(THEORY, a),
                                              rel=1e-9, abs=1e-9)


def test_jkr_closed_forms():
    a_c, p_c = THEORY.jkr_pull_off()
    step = 1e-6 * a_c  # dP/da = 0 at the pull-off
    assert THEORY.jkr_load(a_c + step) - THEORY.jkr_load(a_c - step) \
        == pytest.approx(0.0, abs=1e-9 * abs(p_c))
    assert THEORY.jkr_load(a_c) == pytest.approx(p_c, rel=1e-12)
    assert THEORY.jkr_load(THEORY.jkr_zero_load_width()) == pytest.approx(
        0.0, abs=1e-12 * abs(p_c))
    # Chaudhury et al. (1996): the width at separation is 39 % of a_0
    assert a_c / THEORY.jkr_zero_load_width() == pytest.approx(
        16 ** (-1 / 3), rel=1e-12)


def test_maugis_dugdale_tends_to_jkr_for_a_short_zone():
    w = THEORY.work
    short = LineContact(THEORY.radius, THEORY.modulus, 100 * THEORY.cohesion,
                        w / (100 * THEORY.cohesion))  # lambda = 251
    assert short.md_pull_off()[1] == pytest.approx(short.jkr_pull_off()[1],
                                                   rel=1e-4)
    assert short.md_zero_load_width() == pytest.approx(
        short.jkr_zero_load_width(), rel=1e-3)


def test_coarse_pull_off_within_its_mesh_error(tmp_path):
    """h_fine = 100 um (1 to 2 boundary segments over the pull-off's
    cohesive zone): the convergence study (docs/adhesion/README.md)
    measures this mesh's pull-off force 2.6 % above the Maugis-Dugdale
    value (17.01 N/m against 16.58), +1.9 to +2.05 % on the finer meshes.
    Here at twice the speed and step: measured 17.18 N/m (+3.6 %).
    Asserted: within the issue's 5 % above MD (and not below it), and the
    energy balance within 5e-4 of the largest wall work (measured
    5.8e-5)."""
    require_driver()
    params = adhesion.Params(h_fine=1e-4, time_step=1e-4, speed=2e-3,
                             every=10)
    adhesion.simulate(params, tmp_path)
    result = adhesion_measure.measure(tmp_path / "sim", params)
    theory = result["theory"]
    ratio = result["pull_off"] / theory["md_pull_off"]
    assert 1.0 < ratio < 1.05
    assert theory["lambda"] == pytest.approx(2.52, abs=0.01)
    b = result["balance"]
    assert b["max_abs_residual"] < 5e-4 * b["max_abs_wall_work"]
