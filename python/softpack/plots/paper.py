"""``./softpack plot DIR... [--out FIGDIR]``: the paper's Figs. 4, 6, 7, 8, 9.

Reads ``series.csv`` and ``config.toml`` of each run directory written by
``./softpack run`` (and ``fields.h5`` for Fig. 7), groups the runs by
friction coefficient mu_f and, within a group, averages over the seeds: each
run's curve is interpolated linearly on a common grid spanning the range
all runs of the group cover; markers are the mean, error bars one standard
deviation over seeds (none for a single run). All groups share one plot.

fig4_phi_eps.png
    Phi against eps (paper Fig. 4).
fig6_energy.png
    E/(W H L mu) against Phi (Fig. 6).
fig7_snapshots.png
    Deformed particles coloured by Psi / mu at Phi = 0.78, 0.83, 0.88 (Fig. 7),
    for one run (mu_f = 0.3 if present, lowest seed), from ``fields.h5``
    (dolfinx XDMF layout: ``/Mesh/<mesh>/geometry``, ``/Mesh/<mesh>/topology``,
    ``/Function/<name>/<time with '.' as '_'>``; the displacement function is
    the one named ``displacement`` or ``u``, the energy density the one whose
    name contains ``psi``). Skipped, with a message, when fields are missing.
fig8_connectivity.png, fig8_fit.txt
    Z against Phi (Fig. 8), with and without wall contacts, and the fit
    ``Z = Z_T + (Z_1 - Z_T) sqrt((Phi - Phi_T) / (Phi_1 - Phi_T))``,
    Z_T = 3, Z_1 = 4.72, Phi_1 = 0.9 (Eqs. 14-15), of each group; the paper's
    Phi_T = 0.785 +- 0.005 is drawn dashed. See :func:`fit_rigidity_transition`.
fig9_cv_psi.png
    c_v(Psi_p) against Phi over all particles (Fig. 9).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: The paper's connectivity law (Sec. VI, Eq. 14-15, Fig. 8).
Z_T, Z_1, PHI_1 = 3.0, 4.72, 0.9
PAPER_PHI_T, PAPER_PHI_T_ERROR = 0.785, 0.005
#: Packing fractions of the paper's snapshots (Fig. 7).
SNAPSHOT_PHIS = (0.78, 0.83, 0.88)
#: A snapshot is drawn only if an output step is this close in Phi.
SNAPSHOT_TOLERANCE = 0.01
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


def load_runs(directories) -> list[Run]:
    """Runs of the directories that have ``series.csv`` and ``config.toml``.

    Directories without them are reported on stderr and skipped.
    """
    from softpack.scene.config import ConfigError, load_config
    from softpack.analysis.observables import read_table

    runs = []
    for d in map(Path, directories):
        if not (d / "series.csv").is_file():
            print(f"softpack plot: {d}: no series.csv (not a complete run);"
                  " skipped", file=sys.stderr)
            continue
        try:
            config = load_config(d / "config.toml")
        except ConfigError as err:
            print(f"softpack plot: {err}; skipped", file=sys.stderr)
            continue
        runs.append(Run(d, config["contact"]["friction"],
                        config["geometry"]["seed"],
                        config["material"]["shear_modulus"],
                        config["geometry"]["length"],
                        config["geometry"]["width"],
                        read_table(d / "series.csv")))
    return runs


def group_by_friction(runs) -> dict:
    """``{friction: [runs sorted by seed]}``, frictions ascending."""
    groups = {}
    for r in runs:
        groups.setdefault(r.friction, []).append(r)
    return {mu: sorted(groups[mu], key=lambda r: r.seed)
            for mu in sorted(groups)}


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


def connectivity_law(phi, phi_t):
    """``Z_T + (Z_1 - Z_T) sqrt((Phi - Phi_T) / (Phi_1 - Phi_T))`` (Eq. 14)."""
    phi = np.asarray(phi, float)
    return Z_T + (Z_1 - Z_T) * np.sqrt(np.maximum(phi - phi_t, 0.0)
                                       / (PHI_1 - phi_t))


def fit_rigidity_transition(phi, z, step=1e-4, min_points=3):
    """Least-squares Phi_T of the paper's connectivity law.

    Phi_T minimises the mean squared residual ``(Z - law(Phi; Phi_T))^2``
    over the points with ``Phi > Phi_T`` (the law holds above the rigidity
    transition only), scanned in steps of ``step`` from the smallest Phi to
    the value leaving ``min_points`` points.

    Parameters
    ----------
    phi, z : array_like
        Data points (NaNs dropped).

    Returns
    -------
    (phi_t, error) : (float, float)
        ``error`` is the linearised standard error
        ``sqrt(s^2 / sum(dZ/dPhi_T)^2)``, ``s^2`` the residual variance;
        NaN, NaN when there are too few points.
    """
    phi, z = np.asarray(phi, float), np.asarray(z, float)
    ok = np.isfinite(phi) & np.isfinite(z) & (phi < PHI_1)
    phi, z = phi[ok], z[ok]
    if len(phi) < min_points + 1:
        return float("nan"), float("nan")
    top = np.sort(phi)[-min_points]
    candidates = np.arange(phi.min() - step, top, step)
    costs = [np.mean((z[phi > t] - connectivity_law(phi[phi > t], t))**2)
             for t in candidates]
    best = float(candidates[int(np.argmin(costs))])
    above = phi > best
    a, b = phi[above] - best, PHI_1 - best
    slope = (Z_1 - Z_T) * (phi[above] - PHI_1) / (2 * b**2 * np.sqrt(a / b))
    n = int(above.sum())
    s2 = np.sum((z[above] - connectivity_law(phi[above], best))**2) / \
        max(n - 1, 1)
    return best, float(np.sqrt(s2 / np.sum(slope**2)))


def _style(index):
    """Marker and colour of the index-th friction group."""
    markers, colours = "osD^v", ("tab:blue", "tab:red", "tab:green",
                                 "tab:purple", "tab:orange")
    return dict(marker=markers[index % 5], color=colours[index % 5])


def _label(mu, runs):
    """Legend text of a friction group."""
    seeds = f"{len(runs)} seeds" if len(runs) > 1 else f"seed {runs[0].seed}"
    return f"mu_f = {mu:g} ({seeds})"


def plot_curves(groups, x_name, y_name, xlabel, ylabel, path, extra=None):
    """Mean +- std over seeds of ``y(x)`` for each friction group."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for i, (mu, runs) in enumerate(groups.items()):
        grid, mean, std = mean_over_seeds(
            [(r.series[x_name], r.series[y_name]) for r in runs])
        if len(grid):
            ax.errorbar(grid, mean, yerr=std if len(runs) > 1 else None,
                        ms=4, mfc="none", lw=1, capsize=2,
                        label=_label(mu, runs), **_style(i))
    if extra is not None:
        extra(ax)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def plot_connectivity(groups, path) -> list[str]:
    """Fig. 8 with each group's fit; returns the fit report lines."""
    import matplotlib.pyplot as plt

    lines = [f"paper: Phi_T = {PAPER_PHI_T} +- {PAPER_PHI_T_ERROR}"
             f" (Z_T = {Z_T:g}, Z_1 = {Z_1:g}, Phi_1 = {PHI_1:g})"]
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for i, (mu, runs) in enumerate(groups.items()):
        style = _style(i)
        for column, filled in (("z", True), ("z_without_walls", False)):
            grid, mean, std = mean_over_seeds(
                [(r.series["phi"], r.series[column]) for r in runs])
            if not len(grid):
                continue
            ax.errorbar(grid, mean, yerr=std if len(runs) > 1 else None,
                        ms=4, lw=0, elinewidth=1, capsize=2,
                        mfc=style["color"] if filled else "none",
                        label=_label(mu, runs) + ("" if filled else
                                                  ", no wall contacts"),
                        **style)
        phi = np.concatenate([r.series["phi"] for r in runs])
        z = np.concatenate([r.series["z"] for r in runs])
        phi_t, error = fit_rigidity_transition(phi, z)
        seeds = [fit_rigidity_transition(r.series["phi"], r.series["z"])[0]
                 for r in runs]
        if len(runs) > 1 and np.all(np.isfinite(seeds)):
            error, how = float(np.std(seeds)), f"std over {len(runs)} seeds"
        else:
            how = "least-squares standard error"
        lines.append(f"mu_f = {mu:g}: Phi_T = {phi_t:.4f} +- {error:.4f}"
                     f" ({how}; {len(runs)} run(s))")
        if np.isfinite(phi_t):
            x = np.linspace(phi_t, np.nanmax(phi), 100)
            ax.plot(x, connectivity_law(x, phi_t), color=style["color"],
                    lw=1, label=f"fit, Phi_T = {phi_t:.3f}")
    x = np.linspace(PAPER_PHI_T, 0.89, 100)
    ax.plot(x, connectivity_law(x, PAPER_PHI_T), "k--", lw=1,
            label=f"paper, Phi_T = {PAPER_PHI_T}")
    ax.set_xlabel("Phi")
    ax.set_ylabel("Z")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return lines


def read_snapshot(h5_path, time):
    """Deformed mesh and Psi at the stored time nearest to ``time``.

    Returns
    -------
    (points, triangles, psi, stored_time)
        Current node positions ``(n, 2)``, triangles ``(m, 3)``, Psi per
        triangle ``(m,)`` (J/m^3), and the time actually read.

    Raises
    ------
    KeyError
        When the file lacks the mesh, the displacement or Psi.
    """
    import h5py

    with h5py.File(h5_path, "r") as f:
        mesh = f["Mesh"][next(iter(f["Mesh"]))]
        x, cells = mesh["geometry"][:, :2], mesh["topology"][:]
        functions = {name.lower(): name for name in f["Function"]}
        u_name = functions.get("displacement") or functions.get("u")
        psi_name = next((v for k, v in functions.items() if "psi" in k),
                        None)
        if u_name is None or psi_name is None:
            raise KeyError(f"{h5_path}: needs functions 'displacement' and"
                           f" 'Psi', has {sorted(f['Function'])}")
        u_group, psi_group = f["Function"][u_name], f["Function"][psi_name]
        times = {float(key.replace("_", ".")): key for key in u_group}
        stored = min(times, key=lambda t: abs(t - time))
        u = u_group[times[stored]][:, :2]
        psi = psi_group[times[stored]][:].reshape(-1)
    return x + u, cells, psi, stored


def plot_snapshots(run: Run, path) -> str:
    """Fig. 7 for one run; returns a message saying what was drawn."""
    h5 = run.path / "fields.h5"
    if not h5.is_file():
        return f"fig7: {h5} missing (run with [output] fields = true); skipped"
    phi, time = run.series["phi"], run.series["time"]
    delta = run.series["piston_displacement"]
    picks = []
    for target in SNAPSHOT_PHIS:
        k = int(np.nanargmin(np.abs(phi - target)))
        if abs(phi[k] - target) <= SNAPSHOT_TOLERANCE:
            picks.append((phi[k], time[k], run.length - delta[k]))
    if not picks:
        return (f"fig7: {run.path} never came within {SNAPSHOT_TOLERANCE}"
                f" of Phi = {SNAPSHOT_PHIS}; skipped")
    try:
        snaps = [read_snapshot(h5, t) for _, t, _ in picks]
    except (KeyError, OSError) as err:
        return f"fig7: cannot read {h5}: {err}; skipped"
    _draw_snapshots(run, picks, snaps, path)
    return (f"fig7: {run.path}, Phi = "
            + ", ".join(f"{p:.3f}" for p, _, _ in picks))


def _draw_snapshots(run, picks, snaps, path) -> None:
    """Panels of deformed particles coloured by Psi / mu, one colour scale,
    in the current box (black), all at the scale of the initial box."""
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    scaled = [psi / run.shear_modulus for _, _, psi, _ in snaps]
    vmax = max(float(np.percentile(s, 99.5)) for s in scaled) or 1.0
    fig, axes = plt.subplots(1, len(snaps), figsize=(4.2 * len(snaps), 3.6),
                             squeeze=False)
    for ax, (phi, _, length), (x, cells, _, t), psi in zip(
            axes[0], picks, snaps, scaled):
        image = ax.tripcolor(Triangulation(x[:, 0], x[:, 1], cells),
                             facecolors=psi, vmin=0, vmax=vmax,
                             cmap="viridis")
        ax.plot([0, length, length, 0, 0], [0, 0, run.width, run.width, 0],
                "k-", lw=1.5)
        ax.set_xlim(-0.01 * run.length, 1.01 * run.length)
        ax.set_ylim(-0.01 * run.width, 1.01 * run.width)
        ax.set_aspect("equal")
        ax.set_title(f"Phi = {phi:.3f} (t = {t:.3g} s)", fontsize=9)
        ax.axis("off")
    fig.colorbar(image, ax=axes[0].tolist(), label="Psi / mu", shrink=0.8)
    fig.suptitle(f"mu_f = {run.friction:g}, seed {run.seed}", fontsize=9)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def snapshot_run(groups) -> Run:
    """The run drawn in Fig. 7: mu_f = 0.3 if present, lowest seed."""
    mu = 0.3 if 0.3 in groups else next(iter(groups))
    return groups[mu][0]


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack plot``."""
    p = argparse.ArgumentParser(
        prog="softpack plot",
        description="Draw the paper's Figs. 4, 6, 7, 8, 9 from run"
        " directories (grouped by friction, averaged over seeds).")
    p.add_argument("runs", nargs="+", type=Path, metavar="DIR",
                   help="run directories written by ./softpack run")
    p.add_argument("--out", type=Path, metavar="FIGDIR",
                   help="figure directory (default: DIR/figures for one"
                   " run, ./figures for several)")
    return p


def main(argv=None) -> int:
    """Entry point of ``./softpack plot``; returns the exit status."""
    import matplotlib
    matplotlib.use("Agg")

    args = _parser().parse_args(argv)
    runs = load_runs(args.runs)
    if not runs:
        print("softpack plot: no complete run to plot", file=sys.stderr)
        return 1
    out = args.out or (args.runs[0] / "figures" if len(args.runs) == 1
                       else Path("figures"))
    out.mkdir(parents=True, exist_ok=True)
    groups = group_by_friction(runs)
    written = [
        plot_curves(groups, "eps", "phi", "eps = -ln(1 - delta / L)", "Phi",
                    out / "fig4_phi_eps.png"),
        plot_curves(groups, "phi", "E_over_WHLmu", "Phi", "E / (W H L mu)",
                    out / "fig6_energy.png"),
        plot_curves(groups, "phi", "cv_psi", "Phi", "c_v(Psi_p)",
                    out / "fig9_cv_psi.png")]
    fit = plot_connectivity(groups, out / "fig8_connectivity.png")
    written.append(out / "fig8_connectivity.png")
    (out / "fig8_fit.txt").write_text("\n".join(fit) + "\n")
    for line in fit:
        print(f"fig8: {line}")
    message = plot_snapshots(snapshot_run(groups), out / "fig7_snapshots.png")
    print(message)
    if not message.endswith("skipped"):
        written.append(out / "fig7_snapshots.png")
    print(f"softpack plot: {len(runs)} run(s) in {len(groups)} friction"
          f" group(s); wrote {', '.join(str(p) for p in written)}")
    return 0
