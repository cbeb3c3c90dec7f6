"""Random initial packings: reproducibility, admissibility, file round trip."""

import numpy as np
import pytest

from softpack.scene.packing import (DEFAULT_GAP, Packing, PackingError,
                              random_packing)

SMALL = dict(counts=(8, 4), diameters=(20e-3, 30e-3), length=0.12,
             width=0.10)


@pytest.fixture(scope="module")
def paper_packing():
    return random_packing(1)


def test_paper_defaults(paper_packing):
    p = paper_packing
    assert p.n_particles == 100
    assert np.array_equal(p.ids, np.arange(100))
    assert np.all(p.radii[:70] == 10e-3) and np.all(p.radii[70:] == 15e-3)
    assert (p.length, p.width) == (0.286, 0.202)
    expected = np.pi * (70 * 0.01**2 + 30 * 0.015**2) / (0.286 * 0.202)
    assert p.packing_fraction == pytest.approx(expected, rel=1e-12)
    assert 0.74 < p.packing_fraction < 0.76
    assert np.allclose(p.areas, np.pi * p.radii**2)


def test_paper_packing_is_admissible(paper_packing):
    assert paper_packing.min_particle_gap() >= DEFAULT_GAP
    assert paper_packing.min_wall_gap() >= DEFAULT_GAP


def test_paper_packing_reproducible(paper_packing):
    again = random_packing(1)
    assert np.array_equal(again.centres, paper_packing.centres)
    assert again.seed == 1


def test_seeds_differ():
    a, b = random_packing(5, **SMALL), random_packing(6, **SMALL)
    assert not np.allclose(a.centres, b.centres)
    assert np.array_equal(a.radii, b.radii)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_small_packing_admissible(seed):
    gap = 0.5e-3
    p = random_packing(seed, gap=gap, **SMALL)
    assert p.n_particles == 12
    assert p.min_particle_gap() >= gap
    assert p.min_wall_gap() >= gap
    x, y = p.centres.T
    assert np.all((x > 0) & (x < 0.12) & (y > 0) & (y < 0.10))


def test_plain_rsa_cannot_reach_paper_density():
    with pytest.raises(PackingError, match="random sequential addition"):
        random_packing(1, relax=False)


def test_plain_rsa_at_low_density():
    p = random_packing(3, counts=(5, 2), length=0.2, width=0.2, relax=False)
    assert p.n_particles == 7
    assert p.min_particle_gap() >= DEFAULT_GAP


def test_overfull_box_raises():
    # phi = 0.85 for 12 equal disks in a square: no room with the walls
    side = np.sqrt(12 * np.pi * 0.01**2 / 0.85)
    with pytest.raises(PackingError, match="too full"):
        random_packing(0, counts=(12, 0), length=side, width=side)


def test_denser_than_hexagonal_rejected():
    with pytest.raises(ValueError, match="hexagonal"):
        random_packing(0, counts=(12, 0), length=0.06, width=0.06)


@pytest.mark.parametrize("kwargs", [
    dict(seed=-1), dict(seed=1.5), dict(counts=(70,)),
    dict(counts=(-1, 3)), dict(diameters=(0.02, 0.0)),
    dict(length=0.02), dict(gap=-1e-4), dict(width=float("nan")),
])
def test_invalid_arguments(kwargs):
    args = dict(seed=0, counts=(3, 2), length=0.2, width=0.2)
    args.update(kwargs)
    with pytest.raises(ValueError):
        random_packing(args.pop("seed"), **args)


def test_csv_round_trip(tmp_path):
    p = random_packing(4, **SMALL)
    path = p.to_csv(tmp_path / "p.packing.csv")
    q = Packing.from_csv(path)
    assert np.array_equal(q.centres, p.centres)
    assert np.array_equal(q.radii, p.radii)
    assert np.array_equal(q.ids, p.ids)
    assert (q.length, q.width, q.seed) == (p.length, p.width, 4)
    assert q.packing_fraction == p.packing_fraction
    assert [f.name for f in tmp_path.iterdir()] == ["p.packing.csv"]
    text = path.read_text().splitlines()
    assert "particle,x,y,radius,area" in text


def test_from_csv_needs_box(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("particle,x,y,radius,area\n0,0.1,0.1,0.01,0.0003\n")
    with pytest.raises(ValueError, match="length"):
        Packing.from_csv(path)
