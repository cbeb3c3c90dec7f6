"""Figures from fake runs: averaging, the Z fit, PNG output, Fig. 7 fields."""

import numpy as np
import pytest

from softpack.plots import paper as plots
from softpack.scene.config import to_toml, validate
from softpack.analysis.observables import SERIES_COLUMNS, write_table

PNG = b"\x89PNG\r\n\x1a\n"


def fake_run(directory, friction, seed, phi_t=0.79, fields=False):
    """A run directory with a synthetic series.csv (+ fields.h5).

    Rigid-like compaction Phi = Phi0 e^eps; Z on the paper's law above
    phi_t and 2 below it; E and c_v smooth functions of Phi.
    """
    directory.mkdir(parents=True)
    config = validate({"geometry": {"seed": seed},
                       "contact": {"friction": friction}}, "paper.toml")
    (directory / "config.toml").write_text(to_toml(config))
    eps = np.linspace(0.0, 0.17, 60)
    phi = (0.745 + 0.002 * seed) * np.exp(eps)
    series = {name: np.full(len(eps), np.nan) for name in SERIES_COLUMNS}
    z = np.where(phi > phi_t, plots.connectivity_law(phi, phi_t), 2.0)
    series.update(step=np.arange(len(eps)) * 100, time=eps, eps=eps, phi=phi,
                  piston_displacement=0.286 * (1 - np.exp(-eps)),
                  E_over_WHLmu=friction * (phi - 0.74)**2 + 0.001 * seed,
                  z=z + 0.02 * seed, z_without_walls=z - 0.5,
                  cv_psi=0.1 / (phi - 0.7))
    write_table(directory / "series.csv", series, SERIES_COLUMNS)
    if fields:
        write_fields(directory / "fields.h5", times=eps[::10])
    return directory


def write_fields(path, times):
    """Two triangles in the dolfinx XDMF/HDF5 layout, Psi = 1000 t."""
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as f:
        f["Mesh/mesh/geometry"] = np.array([[0, 0], [1, 0], [1, 1], [0, 1.]])
        f["Mesh/mesh/topology"] = np.array([[0, 1, 2], [0, 2, 3]])
        for t in times:
            key = repr(float(t)).replace(".", "_")
            u = np.zeros((4, 3))
            u[:, 0] = t
            f[f"Function/displacement/{key}"] = u
            f[f"Function/Psi/{key}"] = np.full((2, 1), 1000.0 * t)
            f[f"Function/particle/{key}"] = np.zeros((2, 1))


def test_mean_over_seeds_uses_the_common_range():
    x1, x2 = np.linspace(0, 1, 11), np.linspace(0.2, 1.5, 7)[::-1]
    grid, mean, std = plots.mean_over_seeds([(x1, x1), (x2, x2 + 2)], 5)
    assert np.allclose(grid, np.linspace(0.2, 1.0, 5))
    assert np.allclose(mean, grid + 1) and np.allclose(std, 1.0)
    empty = plots.mean_over_seeds([(x1, x1), (x1 + 5, x1)])
    assert all(len(a) == 0 for a in empty)


def test_connectivity_law_anchors():
    assert plots.connectivity_law(0.785, 0.785) == 3.0
    assert plots.connectivity_law(0.9, 0.785) == pytest.approx(4.72)
    assert plots.connectivity_law(0.70, 0.785) == 3.0


def test_fit_recovers_phi_t():
    rng = np.random.default_rng(0)
    phi = np.linspace(0.75, 0.88, 200)
    z = np.where(phi > 0.79, plots.connectivity_law(phi, 0.79), 2.0)
    phi_t, error = plots.fit_rigidity_transition(phi, z)
    assert phi_t == pytest.approx(0.79, abs=2e-4)
    noisy, error = plots.fit_rigidity_transition(
        phi, z + 0.05 * rng.standard_normal(len(z)))
    assert noisy == pytest.approx(0.79, abs=3e-3)
    assert 0 < error < 5e-3
    assert np.isnan(plots.fit_rigidity_transition([0.8, 0.81], [3, 3.2])[0])


def test_read_snapshot_picks_nearest_time(tmp_path):
    write_fields(tmp_path / "fields.h5", times=[0.0, 0.05, 0.1])
    x, cells, psi, t = plots.read_snapshot(tmp_path / "fields.h5", 0.06)
    assert t == 0.05
    assert np.allclose(x[:, 0], [0.05, 1.05, 1.05, 0.05])
    assert cells.shape == (2, 3) and np.allclose(psi, 50.0)


def test_plot_friction_sweep(tmp_path, capsys):
    runs = [fake_run(tmp_path / f"mu{mu}-seed{s}", mu, s,
                     fields=(mu == 0.3 and s == 0))
            for mu in (0.1, 0.3) for s in (0, 1)]
    out = tmp_path / "figures"
    assert plots.main([str(r) for r in runs] + ["--out", str(out)]) == 0
    for name in ("fig4_phi_eps", "fig6_energy", "fig7_snapshots",
                 "fig8_connectivity", "fig9_cv_psi"):
        data = (out / f"{name}.png").read_bytes()
        assert data.startswith(PNG) and len(data) > 5000, name
    printed = capsys.readouterr().out
    assert "paper: Phi_T = 0.785 +- 0.005" in printed
    fit = (out / "fig8_fit.txt").read_text()
    line = next(l for l in fit.splitlines() if l.startswith("mu_f = 0.3:"))
    phi_t = float(line.split("Phi_T = ")[1].split()[0])
    assert phi_t == pytest.approx(0.79, abs=3e-3)
    assert "std over 2 seeds" in line
    assert "fig7: " in printed and "Phi = 0.78" in printed


def test_missing_fields_skip_fig7(tmp_path, capsys):
    run = fake_run(tmp_path / "run", 0.3, 0)
    assert plots.main([str(run)]) == 0
    out = run / "figures"
    assert (out / "fig4_phi_eps.png").read_bytes().startswith(PNG)
    assert not (out / "fig7_snapshots.png").exists()
    assert "fields.h5 missing" in capsys.readouterr().out


def test_incomplete_runs_are_skipped(tmp_path, capsys):
    (tmp_path / "crashed").mkdir()
    assert plots.main([str(tmp_path / "crashed")]) == 1
    err = capsys.readouterr().err
    assert "no series.csv" in err and "no complete run" in err
