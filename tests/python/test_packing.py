"""Random initial packings: reproducibility, admissibility, file round trip."""

import numpy as np
import pytest

from softpack.scene.placement import place
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


# -- the initial packing fraction and the growth protocol ---------------------

def _admissible(centres, radii, length, width, gap):
    p = Packing(centres=centres, radii=radii, length=length, width=width)
    return p.min_particle_gap() >= gap and p.min_wall_gap() >= gap


def test_growth_reaches_full_size_without_overlaps():
    from softpack.scene.placement import _padded, _sequential
    from softpack.scene.preparation import grow
    radii = np.repeat([0.01, 0.015], (14, 6))
    area = np.pi * np.sum(radii**2)
    width = 0.1
    length = area / (0.70 * width)
    rng = np.random.default_rng(0)
    start = 0.55
    placed, overlapping = _sequential(radii * start, (length, width), 1e-4,
                                      rng, 200, relax=False)
    assert not overlapping
    x = grow(placed, radii, length, width, _padded(1e-4), start, rng)
    assert _admissible(x, radii, length, width, 1e-4)
    # the growth moved the circles, and it is reproducible
    assert not np.allclose(x, placed)
    rng = np.random.default_rng(0)
    again, _ = _sequential(radii * start, (length, width), 1e-4, rng, 200,
                           relax=False)
    assert np.array_equal(grow(again, radii, length, width, _padded(1e-4),
                               start, rng), x)


def test_growth_jams_in_an_overfull_box():
    from softpack.scene.placement import _padded
    from softpack.scene.preparation import grow
    import softpack.scene.preparation as preparation
    radii = np.full(4, 0.01)
    # four disks of 20 mm need 40 x 40 mm; the box is 39 mm square
    centres = np.array([[0.01, 0.01], [0.029, 0.01], [0.01, 0.029],
                        [0.029, 0.029]])
    old = preparation.STALL_SWEEPS
    preparation.STALL_SWEEPS = 50
    try:
        with pytest.raises(preparation.Jammed, match="growth jammed at 0.9"):
            grow(centres, radii, 0.039, 0.039, _padded(1e-4), 0.9,
                 np.random.default_rng(0))
    finally:
        preparation.STALL_SWEEPS = old


def test_place_falls_back_to_growth_when_inflation_jams(monkeypatch):
    import softpack.scene.placement as placement

    def jammed(*args, **kwargs):
        raise PackingError("stalled (test)")

    monkeypatch.setattr(placement, "_relax_overlaps", jammed)
    monkeypatch.setattr(placement, "ATTEMPTS", 1)
    radii = np.repeat([0.01, 0.015], (14, 6))
    width = 0.1
    length = np.pi * np.sum(radii**2) / (0.72 * width)
    x = placement.place(radii, (length, width), 1e-4,
                        np.random.default_rng(3))
    assert _admissible(x, radii, length, width, 1e-4)


def _config(**packing):
    from softpack.scene.config import load_config
    return load_config("examples/paper_phi078.toml",
                       overrides={f"packing.{k}": v
                                  for k, v in packing.items()})


def test_paper_phi078_starts_at_078():
    from softpack.scene.packing import _check_requested_fraction, scene_packing
    config = _config(seed=2)
    assert config["packing"]["initial_packing_fraction"] == 0.78
    radii = np.repeat([0.01, 0.015], (70, 30))
    area = np.pi * np.sum(radii**2)
    assert area / (config["box"]["length"] * 0.202) == pytest.approx(
        0.78, abs=1e-12)
    # the key only checks the box (placement does not read it)
    _check_requested_fraction(config, radii, None)
    p = scene_packing(config, radii)
    assert p.packing_fraction == pytest.approx(0.78, abs=1e-12)
    assert p.min_particle_gap() >= 1e-4 and p.min_wall_gap() >= 1e-4


def test_requested_fraction_the_box_does_not_give_is_refused():
    from softpack.scene.packing import scene_packing
    config = _config(initial_packing_fraction=0.8)
    radii = np.repeat([0.01, 0.015], (70, 30))
    with pytest.raises(PackingError, match=r"\[packing\]"
                       r" initial_packing_fraction = 0.8: .* fill 0.7800 .*"
                       r"set \[box\] length = 0.2673075432"):
        scene_packing(config, radii)


def _clearances_3d(x, radii, cell=None):
    """Smallest clearance between two spheres (to the nearest images in a
    periodic cube of edge ``cell``)."""
    diff = x[:, None, :] - x[None, :, :]
    if cell is not None:
        diff -= cell * np.round(diff / cell)
    gap = (np.linalg.norm(diff, axis=-1) - radii[:, None] - radii[None, :])
    np.fill_diagonal(gap, np.inf)
    return gap.min()


@pytest.mark.parametrize("periodic,phi", [(False, 0.45), (True, 0.55)])
def test_spheres_placed_in_a_box_and_a_periodic_cell(periodic, phi):
    """The same placement in 3D (issue 40): 100 spheres of the paper's two
    diameters, clear of each other (and of the walls) by the gap."""
    from softpack.scene.ball_fraction import ball_fraction
    from softpack.scene.placement import place

    radii = np.repeat([0.01, 0.015], (70, 30))
    edge = (4 / 3 * np.pi * np.sum(radii**3) / phi) ** (1 / 3)
    extent = (edge, edge, edge)
    assert ball_fraction(radii, extent) == pytest.approx(phi, rel=1e-12)
    x = place(radii, extent, 2e-4, np.random.default_rng(0),
              periodic=periodic)
    assert x.shape == (100, 3)
    assert _clearances_3d(x, radii, edge if periodic else None) >= 2e-4
    if periodic:
        assert np.all((x >= 0) & (x < edge))
    else:
        assert np.all(x - radii[:, None] >= 2e-4)
        assert np.all(x + radii[:, None] <= edge - 2e-4)


def test_spheres_too_dense_for_the_box_are_refused_naming_the_limit(
        monkeypatch):
    import softpack.scene.placement as placement

    monkeypatch.setattr(placement, "ATTEMPTS", 1)
    radii = np.full(20, 0.01)
    edge = (4 / 3 * np.pi * np.sum(radii**3) / 0.62) ** (1 / 3)
    with pytest.raises(PackingError, match="growth protocol .* 2D box only"):
        placement.place(radii, (edge, edge, edge), 2e-4,
                        np.random.default_rng(0))


@pytest.mark.parametrize("extent", [(0.04, 0.020002), (0.04, 0.020002, 0.03)])
def test_a_circle_alone_is_clear_of_the_walls(extent):
    """One body in a box just wider than it (the plate checks): shrunk for
    the placement, then grown with no pair to relax, it was left where it
    fell, through a wall (0.26 mm for a 20 mm cylinder)."""
    for seed in range(5):
        x = place(np.array([0.01]), extent, 0.0, np.random.default_rng(seed))
        assert np.all(x >= 0.01) and np.all(x <= np.array(extent) - 0.01)


def test_a_dilute_box_is_clear_of_the_walls():
    radii = np.full(6, 0.005)
    gap = 1e-4
    for seed in range(20):
        x = place(radii, (0.1, 0.1), gap, np.random.default_rng(seed))
        assert np.all(x - radii[:, None] >= gap)
        assert np.all(0.1 - x - radii[:, None] >= gap)
