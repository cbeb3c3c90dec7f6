"""Figures from fake runs: averaging, the Z fit's report, PNG output, Fig. 7."""

import numpy as np
import pytest

from fake_runs import write_fields, write_setup
from softpack.analysis import fits
from softpack.analysis.observables import SERIES_COLUMNS
from softpack.contract.tables import write_table
from softpack.plots import curves, paper as plots

PNG = b"\x89PNG\r\n\x1a\n"


def fake_run(directory, friction, seed, phi_t=0.79, fields=False, top=0.17):
    """A run directory with raw/setup.json, a synthetic series.csv
    (+ fields.h5).

    Rigid-like compaction Phi = Phi0 e^eps; Z on the paper's law above
    phi_t and 2 below it; E and c_v smooth functions of Phi.
    """
    directory.mkdir(parents=True)
    write_setup(directory, length=0.286, width=0.202, friction=friction,
                seed=seed, diameters=(0.02, 0.03))
    eps = np.linspace(0.0, top, 60)
    phi = (0.745 + 0.002 * seed) * np.exp(eps)
    series = {name: np.full(len(eps), np.nan) for name in SERIES_COLUMNS}
    z = np.where(phi > phi_t, fits.connectivity_law(phi, phi_t), 2.0)
    series.update(step=np.arange(len(eps)) * 100, time=eps, eps=eps, phi=phi,
                  piston_displacement=0.286 * (1 - np.exp(-eps)),
                  E_over_WHLmu=friction * (phi - 0.74)**2 + 0.001 * seed,
                  z=z + 0.02 * seed, z_without_walls=z - 0.5,
                  cv_psi=0.1 / (phi - 0.7))
    write_table(directory / "series.csv", series, SERIES_COLUMNS)
    if fields:
        pytest.importorskip("h5py")
        write_fields(directory / "fields.h5", times=eps)
    return directory


def test_mean_over_seeds_uses_the_common_range():
    x1, x2 = np.linspace(0, 1, 11), np.linspace(0.2, 1.5, 7)[::-1]
    grid, mean, std = curves.mean_over_seeds([(x1, x1), (x2, x2 + 2)], 5)
    assert np.allclose(grid, np.linspace(0.2, 1.0, 5))
    assert np.allclose(mean, grid + 1) and np.allclose(std, 1.0)
    empty = curves.mean_over_seeds([(x1, x1), (x1 + 5, x1)])
    assert all(len(a) == 0 for a in empty)


def test_runs_are_identified_from_setup_json(tmp_path):
    run = fake_run(tmp_path / "run", 0.7, 4)
    (run / "config.toml").write_text("this is not read")
    (loaded,) = plots.load_runs([run])
    assert (loaded.friction, loaded.seed) == (0.7, 4)
    assert (loaded.length, loaded.width, loaded.shear_modulus) == \
        (0.286, 0.202, 0.15e6)
    assert len(loaded.series["phi"]) == 60


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


def test_an_unconstrained_fit_is_reported_not_drawn(tmp_path, capsys):
    """A run that stops just past Phi_T gives no Phi_T, and says why."""
    run = fake_run(tmp_path / "run", 0.3, 0, top=0.07)
    assert plots.main([str(run)]) == 0
    line = (run / "figures" / "fig8_fit.txt").read_text().splitlines()[1]
    assert line.startswith("mu_f = 0.3: no Phi_T: ")
    assert "1 run(s)" in line


def test_missing_fields_skip_fig7(tmp_path, capsys):
    run = fake_run(tmp_path / "run", 0.3, 0)
    assert plots.main([str(run)]) == 0
    out = run / "figures"
    assert (out / "fig4_phi_eps.png").read_bytes().startswith(PNG)
    assert not (out / "fig7_snapshots.png").exists()
    assert "fields.h5 missing" in capsys.readouterr().out


def test_fig7_refuses_a_frame_far_from_the_phi_asked(tmp_path, capsys):
    """A fields.h5 that only holds the start (e.g. a resumed run without
    its fields.part.h5) must not be drawn under the labels of later Phi."""
    run = fake_run(tmp_path / "run", 0.3, 0)
    write_fields(run / "fields.h5", times=[0.0])
    assert plots.main([str(run)]) == 0
    assert not (run / "figures" / "fig7_snapshots.png").exists()
    assert "no frame within 0.01; no frame near Phi = 0.780" in \
        capsys.readouterr().out


def test_incomplete_runs_are_skipped(tmp_path, capsys):
    (tmp_path / "crashed").mkdir()
    (tmp_path / "old").mkdir()
    (tmp_path / "old" / "series.csv").write_text("step\n0\n")
    assert plots.main([str(tmp_path / "crashed"), str(tmp_path / "old")]) \
        == 1
    err = capsys.readouterr().err
    assert "no series.csv" in err and "no complete run" in err
    assert "setup.json missing" in err


def test_a_state_that_is_not_one_is_refused(tmp_path, capsys):
    run = fake_run(tmp_path / "run", 0.3, 0)
    for bad in ("foo", "phi=x", "speed=3"):
        with pytest.raises(SystemExit) as caught:
            plots.main([str(run), "--at", bad])
        assert caught.value.code == 2
        assert "--at" in capsys.readouterr().err


def _capture_figures(monkeypatch, module):
    """Keep the figures ``module`` writes (they are still written)."""
    from softpack.plots import write_figure

    kept = []

    def keep(fig, path, tight=True):
        fig.canvas.draw()
        kept.append(fig)
        return write_figure(fig, path, tight)

    monkeypatch.setattr(module, "write_figure", keep)
    return kept


def _below(legend, axes):
    """Whether the legend lies wholly under every one of the axes."""
    renderer = legend.figure.canvas.get_renderer()
    top = legend.get_window_extent(renderer).y1
    return all(top <= ax.get_window_extent(renderer).y0 + 1e-6 for ax in axes)


def test_plates_figure_is_two_columns_with_the_legend_under_the_panels(
        tmp_path, monkeypatch):
    import json

    from softpack.plots import shapes, style

    dirs = []
    for shape in ("square", "pentagon"):
        for h in (2e-3, 1e-3):
            d = tmp_path / f"{shape}-{h:g}"
            d.mkdir()
            (d / "plates.json").write_text(json.dumps({
                "params": {"shape": shape, "element_size": h},
                "mesh": {"triangles": int(4e-4 / h ** 2)},
                "height_H0_m": 0.02}))
            eps = np.linspace(0.0, 0.2, 41)
            write_table(d / "force_dolfinx.csv", {"eps": eps, "f_norm": 3 * eps})
            write_table(d / "force_softpack.csv",
                        {"eps": eps, "f_norm": 3 * eps * (1 + h)})
            dirs.append(d)
    kept = _capture_figures(monkeypatch, shapes)
    with style.context():
        shapes.plates_figures(dirs, tmp_path)
    assert (tmp_path / "plates_force.png").read_bytes().startswith(PNG)
    assert (tmp_path / "plates_force.pdf").is_file()
    fig, = kept
    assert fig.get_figwidth() == pytest.approx(style.DOUBLE_COLUMN)
    legend, = fig.legends
    assert len(legend.get_texts()) == 4  # softpack and dolfinx per mesh
    assert _below(legend, fig.axes)


def test_single_disk_figures_in_one_column_with_the_legend_under_the_axes(
        tmp_path, monkeypatch):
    from softpack.plots import single_disk, style

    eps = np.linspace(0.0, 0.25, 26)
    write_table(tmp_path / "force_2d.csv", {"eps": eps, "f_norm": eps})
    write_table(tmp_path / "force_3d_nu0495.csv", {"eps": eps, "f_norm": 1.05 * eps})
    w = np.tile(np.linspace(-1, 1, 21), 4)
    strains = np.repeat(single_disk.PROFILE_STRAINS, 21)
    write_table(tmp_path / "profile_2d.csv",
                {"eps": strains, "w": w, "ux_over_D": 0.15 * strains * w})
    kept = _capture_figures(monkeypatch, single_disk)
    assert single_disk.main([str(tmp_path)]) == 0
    for name in ("fig2_force", "fig3_profile"):
        assert (tmp_path / f"{name}.png").read_bytes().startswith(PNG)
        assert (tmp_path / f"{name}.pdf").is_file()
    assert len(kept) == 2
    for fig in kept:
        assert fig.get_figwidth() == pytest.approx(style.SINGLE_COLUMN)
        ax, = fig.axes
        assert "$" in ax.get_xlabel() and "$" in ax.get_ylabel()
        assert _below(ax.get_legend(), [ax])


def test_snapshot_panels_fill_the_figure_height(tmp_path):
    """Equal-aspect boxes in a figure of a fixed height leave empty bands
    above and below them (and a colour bar taller than they are): the
    figure's height is fitted to the panels."""
    from softpack.plots import snapshots

    run = fake_run(tmp_path / "run", 0.3, 0, fields=True)
    fig = snapshots.snapshot_figure(run, [("phi", 0.78), ("phi", 0.85)])
    fig.canvas.draw()
    ax = fig.axes[0]
    spare = (ax.get_position(original=True).height
             - ax.get_position().height) * fig.get_figheight()
    assert spare < 0.05  # inches (0.5 in a figure 0.42 x its width tall)


def test_snapshot_fields_are_images_in_a_pdf(tmp_path):
    """The field of every panel is rasterized (one image each in a PDF,
    outlines and text vector): as vector triangles the paper case's
    snapshots made 4-6 MB PDFs (0.34-0.38 MB rasterized, 2026-12-03)."""
    from matplotlib.collections import PolyCollection
    from softpack.plots import snapshots

    run = fake_run(tmp_path / "run", 0.3, 0, fields=True)
    fig = snapshots.snapshot_figure(run, [("phi", 0.78), ("phi", 0.85)])
    fields = [c for ax in fig.axes for c in ax.collections
              if isinstance(c, PolyCollection)]
    assert len(fields) >= 2
    assert all(c.get_rasterized() for c in fields)
    pdf = tmp_path / "snapshots.pdf"
    fig.savefig(pdf)
    assert pdf.read_bytes().count(b"/Subtype /Image") >= 2


def test_shape_distributions_leave_out_runs_without_fields(tmp_path,
                                                           monkeypatch):
    """A run without fields.h5 gets no (empty) column, and the legends sit
    above the bars."""
    from softpack.plots import shapes
    from softpack.plots.paper import load_runs

    with_fields = fake_run(tmp_path / "a", 0.3, 0, fields=True)
    without = fake_run(tmp_path / "b", 0.3, 1)
    runs = [(load_runs([with_fields])[0], "a"), (load_runs([without])[0], "b")]
    kept = _capture_figures(monkeypatch, shapes)
    messages = shapes.shape_distributions(runs, tmp_path / "shapes.png")
    assert any("fields.h5 missing" in m for m in messages)
    fig, = kept
    assert len(fig.axes) == 3  # one column: run a's
    for ax in fig.axes:
        counts = max(p.get_path().vertices[:, 1].max() for p in ax.patches)
        assert counts <= ax.get_ylim()[1] / 1.4
    assert (tmp_path / "shapes.pdf").is_file()
