"""Curves averaged over seeds, grouped by friction: Figs. 4, 6, 8 and 9.

The drawing that ``./softpack plot`` (:mod:`.paper`) and the figures of
docs/paper (:mod:`.paper_seeds`) share: each run's curve is interpolated
linearly on a common grid spanning the range all runs of a group cover;
markers are the mean, error bars one standard deviation over seeds (none
for a single run). All groups share one plot.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis import fits
from softpack.plots import style, write_figure

#: Points of the common grid of a group's curves.
GRID_POINTS = 25


@dataclass(frozen=True)
class Run:
    """One run directory's series and what identifies it.

    Attributes
    ----------
    path : Path
    friction : float
    seed : int
    shear_modulus : float
        NaN when the material law has none (Fig. 7 then draws Psi in Pa).
    length, width : float
        The initial box (m).
    series : dict of ndarray
        Columns of ``series.csv``.
    """

    path: Path
    friction: float
    seed: int
    shear_modulus: float
    length: float
    width: float
    series: dict


def mean_over_seeds(curves, points=GRID_POINTS):
    """Mean and standard deviation of curves on a common grid.

    Parameters
    ----------
    curves : list of (x, y) array pairs
        One curve per seed; NaN points are dropped, x need not be sorted.
    points : int
        Grid size; the grid spans the x range that every curve covers.

    Returns
    -------
    (grid, mean, std) : ndarrays
        Empty arrays when the curves have no common range.
    """
    cleaned = []
    for x, y in curves:
        x, y = np.asarray(x, float), np.asarray(y, float)
        ok = np.isfinite(x) & np.isfinite(y)
        order = np.argsort(x[ok], kind="stable")
        if ok.sum() >= 2:
            cleaned.append((x[ok][order], y[ok][order]))
    if not cleaned:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    lo = max(x[0] for x, _ in cleaned)
    hi = min(x[-1] for x, _ in cleaned)
    if not hi > lo:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    grid = np.linspace(lo, hi, points)
    values = np.array([np.interp(grid, x, y) for x, y in cleaned])
    return grid, values.mean(axis=0), values.std(axis=0)


def _style(index):
    """Marker and colour of the index-th friction group."""
    markers, colours = "osD^v", ("tab:blue", "tab:red", "tab:green",
                                 "tab:purple", "tab:orange")
    return dict(marker=markers[index % 5], color=colours[index % 5])


def _label(mu, runs):
    """Legend text of a friction group (or of a group named by a text)."""
    seeds = f"{len(runs)} seeds" if len(runs) > 1 else f"seed {runs[0].seed}"
    name = mu if isinstance(mu, str) else rf"$\mu_f$ = {mu:g}"
    return f"{name} ({seeds})"


def _figure():
    """A one-column figure in softpack's style."""
    import matplotlib.pyplot as plt

    with style.context():
        return plt.subplots(figsize=(style.SINGLE_COLUMN,
                                     0.78 * style.SINGLE_COLUMN))


def plot_curves(groups, x_name, y_name, xlabel, ylabel, path, extra=None):
    """Mean +- std over seeds of ``y(x)`` for each friction group."""
    fig, ax = _figure()
    for i, (mu, runs) in enumerate(groups.items()):
        grid, mean, std = mean_over_seeds(
            [(r.series[x_name], r.series[y_name]) for r in runs])
        if len(grid):
            ax.errorbar(grid, mean, yerr=std if len(runs) > 1 else None,
                        ms=3, mfc="none", lw=1, capsize=1.5,
                        label=_label(mu, runs), **_style(i))
    if extra is not None:
        extra(ax)
    return _save(fig, ax, xlabel, ylabel, path)


#: Legend entries longer than this go one per row (two columns would be
#: wider than a one-column figure and squeeze the axes).
LEGEND_TWO_COLUMNS = 38
#: Legend rows below the axes that the figure's height holds as it is;
#: each row beyond adds LEGEND_ROW inches, so the axes keep their size.
LEGEND_ROWS, LEGEND_ROW = 4, 0.135


def _save(fig, ax, xlabel, ylabel, path):
    """Label, grid and legend one plot, write it (PNG and PDF), close it."""
    with style.context():
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        labels = ax.get_legend_handles_labels()[1]
        ncols = 2 if max(map(len, labels), default=0) <= LEGEND_TWO_COLUMNS \
            else 1
        rows = -(-len(labels) // ncols)
        if rows > LEGEND_ROWS:
            width, height = fig.get_size_inches()
            fig.set_size_inches(width, height
                                + (rows - LEGEND_ROWS) * LEGEND_ROW)
        ax.legend(fontsize=6, frameon=False, loc="upper center",
                  bbox_to_anchor=(0.5, -0.2), ncols=ncols)
        write_figure(fig, path)
    return path


def plot_connectivity(groups, path) -> list[str]:
    """Fig. 8 with each group's fit and, where the runs reach its range,
    the paper's law; returns the fit report lines."""
    lines = [f"paper: Phi_T = {fits.PAPER_PHI_T} +- {fits.PAPER_PHI_T_ERROR}"
             f" (Z_T = {fits.Z_T:g}, Z_1 = {fits.Z_1:g},"
             f" Phi_1 = {fits.PHI_1:g})"]
    fig, ax = _figure()
    phi_max = -np.inf
    for i, (mu, runs) in enumerate(groups.items()):
        marks = _style(i)
        for column, filled in (("z", True), ("z_without_walls", False)):
            grid, mean, std = mean_over_seeds(
                [(r.series["phi"], r.series[column]) for r in runs])
            if not len(grid):
                continue
            phi_max = max(phi_max, grid.max())
            ax.errorbar(grid, mean, yerr=std if len(runs) > 1 else None,
                        ms=3, lw=0, elinewidth=1, capsize=1.5,
                        mfc=marks["color"] if filled else "none",
                        label=_label(mu, runs) + ("" if filled else
                                                  ", no wall contacts"),
                        **marks)
        fit = fits.fit_runs([(r.series["phi"], r.series["z"])
                             for r in runs])
        name = mu if isinstance(mu, str) else f"mu_f = {mu:g}"
        lines.append(f"{name}: {fit.summary()}; {len(runs)} run(s)")
        if fit.ok:
            x = np.linspace(fit.phi_t, np.nanmax(
                np.concatenate([r.series["phi"] for r in runs])), 100)
            ax.plot(x, fits.connectivity_law(x, fit.phi_t),
                    color=marks["color"], lw=1,
                    label=rf"fit, $\Phi_T$ = {fit.phi_t:.3f}")
    # The paper's curve where the runs reach its range (axes from the data)
    if phi_max > fits.PAPER_PHI_T:
        x = np.linspace(fits.PAPER_PHI_T, min(0.89, phi_max), 100)
        ax.plot(x, fits.connectivity_law(x, fits.PAPER_PHI_T), "k--", lw=1,
                label=rf"paper, $\Phi_T$ = {fits.PAPER_PHI_T}")
    _save(fig, ax, r"$\Phi$", "$Z$", path)
    return lines


