"""Checks of the axisymmetric sphere reference
(softpack.references.sphere_axisym): the continuum answer of issue 40's
Hertz check (docs/contact_3d.md, "Hertz: the reference").

CI-sized: 0.2 mm triangles near the pole (the docs' table converges at
0.05-0.025 mm), up to eps = 0.005; seconds with a warm FFCx cache.
"""

import math

import pytest

pytest.importorskip("dolfinx")
from softpack.references import sphere_axisym  # noqa: E402


@pytest.fixture(scope="module")
def coarse():
    return sphere_axisym.compress_sphere(element_size=2e-4, max_strain=0.005)


def test_small_strain_force_is_hertz_plus_the_bulk_term(coarse):
    """At eps = 0.005 (a/R = 0.07) the converged sphere is 3.1 % stiffer
    than Hertz's half-space (docs' table: the body between the two contacts
    adds to Hertz's compliance a term linear in a/R); this mesh 3.4 %."""
    i = coarse["eps"].index(0.005)
    assert coarse["error_vs_hertz"][i] == pytest.approx(0.031, abs=0.006)
    assert 0.06 < coarse["a_m"][i] / 0.01 < 0.08


def test_the_force_is_in_equilibrium(coarse):
    """The plate's penalty force is the reaction on the equator, and the
    plate's penetration is tiny against the closure."""
    for f, f_sym, pen, closure in zip(coarse["force_N"], coarse["force_sym_N"],
                                      coarse["penetration_m"],
                                      coarse["closure_m"]):
        assert f_sym == pytest.approx(f, rel=1e-7)
        assert pen < 1e-3 * closure


def test_hertz_force_is_johnsons():
    """F = (4/3) E* sqrt(R) (closure/2)^(3/2), nu = 1/3 at lambda = 2 mu."""
    mu = 0.15e6
    e_star = 2 * mu * (1 + 1 / 3) / (1 - 1 / 9)
    expected = 4 / 3 * e_star * math.sqrt(0.01) * 2e-4 ** 1.5
    assert sphere_axisym.hertz_force(4e-4, 0.02, mu, 2 * mu) == \
        pytest.approx(expected, rel=1e-12)
