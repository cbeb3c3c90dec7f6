"""Tatara's (1989) force-approach law of a sphere between two plates
(softpack.references.tatara) and the axisymmetric reference against it up
to eps = 0.3 (docs/contact_3d.md, "Large strain: against Tatara").

No tabulated values of the law were found to check it against, so the
formula is checked by its limits (Hertz plus Boussinesq's point load at the
far pole) and the comparison on a stored reference run
(tests/python/reference/sphere_large.csv: ``./softpack reference-sphere
--element-size 1e-4 --fine-radius 0.7 --max-strain 0.3``, D 20 mm,
mu 0.15 MPa, lambda 2 mu; its eps, force_N and a_m columns; and
sphere_large_nu049.csv, the same at lambda = 49 mu).
"""

import math
from pathlib import Path

import pytest

from softpack.contract.tables import read_table
from softpack.references import tatara

MU, LAM, D = 0.15e6, 0.3e6, 0.02
STRAINS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3)
TABLE = Path(__file__).parent / "reference" / "sphere_large.csv"


def test_the_far_pole_term_is_boussinesqs_point_load():
    """At a vanishing force the approach is Hertz's minus the half-space
    displacement on the axis at depth 2R: F (1 + nu)(3 - 2 nu)/(4 pi E R)."""
    E, nu = tatara.young_poisson(MU, LAM)
    R, F = 0.01, 1e-12
    e_star = E / (1 - nu * nu)
    hertz = (3 * F / (4 * e_star * math.sqrt(R))) ** (2 / 3)
    far = hertz - tatara.approach(F, R, E, nu)
    assert far == pytest.approx(
        F * (1 + nu) * (3 - 2 * nu) / (4 * math.pi * E * R), rel=1e-6)


def test_force_inverts_the_approach_and_exceeds_hertz():
    E, nu = tatara.young_poisson(MU, LAM)
    for eps in (0.001,) + STRAINS:
        f = tatara.force(eps * D, D, MU, LAM)
        assert 2 * tatara.approach(f, D / 2, E, nu) == \
            pytest.approx(eps * D, rel=1e-10)
        hertz = 4 / 3 * E / (1 - nu * nu) * math.sqrt(D / 2) * \
            (eps * D / 2) ** 1.5
        assert f > hertz


def test_the_reference_follows_tatara_to_eps_03():
    """nu = 1/3 (the 3D test's lambda = 2 mu): F_reference / F_Tatara - 1 at
    eps = 0.05 ... 0.3 is -2.3, -2.4, -1.9, -0.6, +1.5, +4.5 %, where Hertz
    is 12-49 % below the reference. The reference's own error is below
    0.05 % (its 0.1 and 0.2 mm meshes agree to 0.02 % from eps = 0.05 on;
    penalty 1e5 -> 1e6 moves it 0.003 %), so the differences are the law's:
    each is pinned to its measured value +- 0.15 points (three times the
    reference's error), not widened into a tolerance."""
    cmp = tatara.compare(read_table(TABLE), D, MU, LAM, STRAINS)
    measured = (-2.26, -2.44, -1.88, -0.61, +1.47, +4.49)
    for got, want in zip(cmp["ratio"], measured):
        assert 100 * (got - 1) == pytest.approx(want, abs=0.15)
    assert max(abs(r - 1) for r in cmp["ratio"]) < 0.05


def test_nearly_incompressible_the_law_is_stiffer_than_the_reference():
    """nu = 0.49 (lambda = 49 mu, the same run with --lame-lambda 7.35e6;
    0.1 and 0.2 mm meshes agree to 0.03 % from eps = 0.05 on): Tatara's law
    is 6.8, 8.8, 9.4, 9.0, 7.5, 4.7 % above the reference, 2.2 % already at
    eps = 0.005 -- its half-space far-pole term over-stiffens the nearly
    incompressible sphere. Pinned as above."""
    table = read_table(TABLE.with_name("sphere_large_nu049.csv"))
    cmp = tatara.compare(table, D, MU, 49 * MU, (0.005,) + STRAINS)
    measured = (-2.20, -6.83, -8.79, -9.42, -8.98, -7.47, -4.71)
    for got, want in zip(cmp["ratio"], measured):
        assert 100 * (got - 1) == pytest.approx(want, abs=0.15)


def test_compare_rejects_a_strain_not_in_the_table():
    with pytest.raises(ValueError):
        tatara.compare({"eps": [0.1], "force_N": [1.0]}, D, MU, LAM, (0.12,))
