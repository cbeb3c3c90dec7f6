"""Size distributions and orientations of species: seeded, within bounds,
with the moments they claim; refusals name the keys."""

import math

import numpy as np
import pytest

from softpack.scene import distributions, species
from softpack.scene.distributions import DistributionError


def table(**keys):
    """A species with the schema's defaults for the size keys."""
    return {"name": "s", "shape": "disk", "diameter": 0.02, "count": 4000,
            "distribution": "fixed", "diameter_min": 0.0,
            "diameter_max": 0.0, "sigma": 0.0, "diameters": [], **keys}


def test_fixed():
    assert np.all(distributions.draw(table(count=5), 0, 0) == 0.02)


def test_uniform_moments_and_bounds():
    s = table(distribution="uniform", diameter_min=0.01, diameter_max=0.03)
    d = distributions.draw(s, 3, 0)
    assert d.min() >= 0.01 and d.max() <= 0.03
    # mean 0.02, standard deviation 0.02 / sqrt(12): 5 standard errors
    assert abs(d.mean() - 0.02) < 5 * 0.02 / math.sqrt(12 * len(d))
    assert distributions.mean_square(s) == pytest.approx(
        np.mean(d**2), rel=0.02)
    assert distributions.bounds(s) == (0.01, 0.03)


def test_lognormal_median_and_sigma():
    s = table(distribution="lognormal", sigma=0.2)
    d = distributions.draw(s, 1, 0)
    z = np.log(d)
    assert abs(np.median(z) - math.log(0.02)) < 5 * 0.2 / math.sqrt(len(d))
    assert np.std(z) == pytest.approx(0.2, rel=0.05)
    assert distributions.mean_square(s) == pytest.approx(np.mean(d**2),
                                                         rel=0.03)
    low, high = distributions.bounds(s)
    assert np.mean((d < low) | (d > high)) < 1e-3


def test_truncated_lognormal():
    s = table(distribution="lognormal", sigma=0.5, diameter_min=0.015,
              diameter_max=0.025)
    d = distributions.draw(s, 2, 0)
    assert d.min() >= 0.015 and d.max() <= 0.025
    # the quadrature of the truncated density against the draws
    assert distributions.mean_square(s) == pytest.approx(np.mean(d**2),
                                                         rel=0.01)


def test_list():
    s = table(distribution="list", diameters=[0.01, 0.02, 0.025], count=3)
    assert distributions.draw(s, 0, 0).tolist() == [0.01, 0.02, 0.025]
    assert distributions.mean_square(s) == pytest.approx(
        (0.01**2 + 0.02**2 + 0.025**2) / 3)


def test_seeded_and_species_independent():
    a = table(distribution="uniform", diameter_min=0.01, diameter_max=0.03,
              count=10)
    one, _ = species.particle_table([a], seed=7)
    again, _ = species.particle_table([a], seed=7)
    other, _ = species.particle_table([a], seed=8)
    assert np.array_equal(one, again) and not np.array_equal(one, other)
    # a species added after it changes none of its draws
    both, index = species.particle_table(
        [a, table(distribution="uniform", diameter_min=0.01,
                  diameter_max=0.03, count=3)], seed=7)
    assert np.array_equal(both[index == 0], one)


@pytest.mark.parametrize("keys, message", [
    (dict(distribution="uniform"), "needs 0 < diameter_min"),
    (dict(distribution="uniform", diameter_min=0.03, diameter_max=0.02),
     "diameter_min"),
    (dict(distribution="lognormal"), "sigma > 0"),
    (dict(distribution="lognormal", sigma=0.1, diameter_min=0.021,
          diameter_max=0.03), "between the cuts"),
    (dict(distribution="list", diameters=[0.02], count=2), "count = 2"),
])
def test_refusals_name_the_keys(keys, message):
    with pytest.raises(DistributionError, match=r"\[species.0\]"):
        species.check([table(**keys)])
    with pytest.raises(DistributionError, match=message):
        species.check([table(**keys)])


def test_orientations():
    tables = [{"shape": "disk", "orientation": "random"},
              {"shape": "polygon", "orientation": "random"},
              {"shape": "ellipse", "orientation": "fixed", "angle": 0.3}]
    index = np.repeat([0, 1, 2], 500)
    angles = species.orientations(tables, index, seed=4)
    assert np.all(angles[index == 0] == 0)  # disks are not rotated
    random = angles[index == 1]
    assert random.min() >= 0 and random.max() < 2 * math.pi
    assert abs(random.mean() - math.pi) < 5 * 2 * math.pi / math.sqrt(
        12 * 500)
    assert np.all(angles[index == 2] == 0.3)
    assert np.array_equal(angles, species.orientations(tables, index, 4))


def test_total_area_is_the_expected_area():
    s = table(distribution="uniform", diameter_min=0.01, diameter_max=0.03,
              count=10)
    expected = 10 * math.pi / 4 * (0.01**2 + 0.01 * 0.03 + 0.03**2) / 3
    assert species.total_area([s]) == pytest.approx(expected, rel=1e-12)
