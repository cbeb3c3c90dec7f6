"""``./softpack plot DIR... [--out FIGDIR]``: the paper's Figs. 4, 6, 7, 8, 9.

(``--export-seeds SEEDDIR DIR...`` and ``--seeds SEEDDIR``: docs/paper's
figures and tables from small per-seed CSVs, :mod:`.paper_seeds`.) The
curves averaged over seeds are :mod:`.curves`'.

Only draws. Reads each run directory written by ``./softpack run`` through
the analysis stage: ``series.csv`` (:mod:`softpack.contract.tables`), the
run's identity (friction, seed, mu, L, W) from ``raw/setup.json``
(:mod:`softpack.analysis.setup`), the fields for Fig. 7
(:mod:`softpack.analysis.fields`) and the Eq. 14 fit
(:mod:`softpack.analysis.fits`). It groups the runs by
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
    for one run (mu_f = 0.3 if present, lowest seed), from ``fields.h5``.
    Skipped, with a message, when fields are missing.
fig8_connectivity.png, fig8_fit.txt
    Z against Phi (Fig. 8), with and without wall contacts, and the fit of
    Eq. 14 of each group (:func:`softpack.analysis.fits.fit_runs`: its
    error from the data, or the reason there is no fit); the paper's
    Phi_T = 0.785 +- 0.005 is drawn dashed.
fig9_cv_psi.png
    c_v(Psi_p) against Phi over all particles (Fig. 9).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from softpack.analysis.fields import read_snapshot
from softpack.analysis.setup import SetupError, read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.plots import write_figure
from softpack.plots.curves import Run, plot_connectivity, plot_curves

#: Packing fractions of the paper's snapshots (Fig. 7).
SNAPSHOT_PHIS = (0.78, 0.83, 0.88)
#: A snapshot is drawn only if an output step is this close in Phi.
SNAPSHOT_TOLERANCE = 0.01


def load_runs(directories) -> list[Run]:
    """Runs of the directories that have ``series.csv`` and ``raw/setup.json``.

    Directories without them are reported on stderr and skipped.
    """
    runs = []
    for d in map(Path, directories):
        series = RunDirectory(d).series_csv
        if not series.is_file():
            print(f"softpack plot: {d}: no series.csv (not a complete run);"
                  " skipped", file=sys.stderr)
            continue
        try:
            setup = read_setup(d)
        except SetupError as err:
            print(f"softpack plot: {err}; skipped", file=sys.stderr)
            continue
        runs.append(Run(d, setup.friction, setup.seed, setup.shear_modulus,
                        setup.length, setup.width,
                        read_table(series)))
    return runs


def group_by_friction(runs) -> dict:
    """``{friction: [runs sorted by seed]}``, frictions ascending."""
    groups = {}
    for r in runs:
        groups.setdefault(r.friction, []).append(r)
    return {mu: sorted(groups[mu], key=lambda r: r.seed)
            for mu in sorted(groups)}


def plot_snapshots(run: Run, path) -> str:
    """Fig. 7 for one run; returns a message saying what was drawn."""
    h5 = RunDirectory(run.path).fields_h5
    if not h5.is_file():
        return f"fig7: {h5} missing (run with [output] fields = true); skipped"
    phi, time = run.series["phi"], run.series["time"]
    delta = run.series["piston_displacement"]
    picks, targets = [], []
    for target in SNAPSHOT_PHIS:
        k = int(np.nanargmin(np.abs(phi - target)))
        if abs(phi[k] - target) <= SNAPSHOT_TOLERANCE:
            picks.append((phi[k], time[k], run.length - delta[k]))
            targets.append(target)
    if not picks:
        return (f"fig7: {run.path} never came within {SNAPSHOT_TOLERANCE}"
                f" of Phi = {SNAPSHOT_PHIS}; skipped")
    try:
        snaps = [read_snapshot(h5, t) for _, t, _ in picks]
    except (KeyError, OSError) as err:
        return f"fig7: cannot read {h5}: {err}; skipped"
    if any(snap.psi is None for snap in snaps):
        return f"fig7: {h5} has no Psi; skipped"
    # The frame drawn is the stored one nearest each pick: label it with
    # its own Phi, and leave out a frame too far from the Phi asked for.
    framed = [(float(np.interp(snap.time, time, phi)), snap.time,
               run.length - float(np.interp(snap.time, time, delta)))
              for snap in snaps]
    near = [abs(p - target) <= SNAPSHOT_TOLERANCE
            for (p, _, _), target in zip(framed, targets)]
    far = "".join(f"; no frame near Phi = {target:.3f} (nearest {p:.3f})"
                  for (p, _, _), target, ok in zip(framed, targets, near)
                  if not ok)
    if not any(near):
        return f"fig7: {h5}: no frame within {SNAPSHOT_TOLERANCE}{far}; skipped"
    picks = [f for f, ok in zip(framed, near) if ok]
    _draw_snapshots(run, picks, [s for s, ok in zip(snaps, near) if ok],
                    path)
    return (f"fig7: {run.path}, Phi = "
            + ", ".join(f"{p:.3f}" for p, _, _ in picks) + far)


def _draw_snapshots(run, picks, snaps, path) -> None:
    """Panels of deformed particles coloured by Psi / mu (Psi in Pa when the
    law has no mu), one colour scale, in the current box (black), all at the
    scale of the initial box."""
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    has_mu = np.isfinite(run.shear_modulus)
    scale = run.shear_modulus if has_mu else 1.0
    scaled = [snap.psi / scale for snap in snaps]
    vmax = max(float(np.percentile(s, 99.5)) for s in scaled) or 1.0
    fig, axes = plt.subplots(1, len(snaps), figsize=(4.2 * len(snaps), 3.6),
                             squeeze=False)
    for ax, (phi, _, length), snap, psi in zip(axes[0], picks, snaps,
                                                scaled):
        x, t = snap.current, snap.time
        image = ax.tripcolor(Triangulation(x[:, 0], x[:, 1], snap.cells),
                             facecolors=psi, vmin=0, vmax=vmax,
                             cmap="viridis")
        ax.plot([0, length, length, 0, 0], [0, 0, run.width, run.width, 0],
                "k-", lw=1.5)
        ax.set_xlim(-0.01 * run.length, 1.01 * run.length)
        ax.set_ylim(-0.01 * run.width, 1.01 * run.width)
        ax.set_aspect("equal")
        ax.set_title(f"Phi = {phi:.3f} (t = {t:.3g} s)", fontsize=9)
        ax.axis("off")
    fig.colorbar(image, ax=axes[0].tolist(),
                 label="Psi / mu" if has_mu else "Psi (Pa)", shrink=0.8)
    fig.suptitle(f"mu_f = {run.friction:g}, seed {run.seed}", fontsize=9)
    write_figure(fig, path, tight=False)


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
    p.add_argument("runs", nargs="*", type=Path, metavar="DIR",
                   help="run directories written by ./softpack run")
    p.add_argument("--out", type=Path, metavar="FIGDIR",
                   help="figure directory (default: the first DIR's"
                   " figures/; nothing is written in the current directory)")
    seeds = p.add_mutually_exclusive_group()
    seeds.add_argument("--export-seeds", type=Path, metavar="SEEDDIR",
                       help="write each DIR's per-seed CSV (series and Z"
                       " under every exclusion reading) to SEEDDIR")
    seeds.add_argument("--seeds", type=Path, metavar="SEEDDIR",
                       help="draw the figures and tables of docs/paper from"
                       " the per-seed CSVs of SEEDDIR (no DIR)")
    return p


def main(argv=None) -> int:
    """Entry point of ``./softpack plot``; returns the exit status."""
    import matplotlib
    matplotlib.use("Agg")

    parser = _parser()
    args = parser.parse_args(argv)
    if args.seeds or args.export_seeds:
        if bool(args.seeds) == bool(args.runs):
            parser.error("--seeds takes no DIR; --export-seeds needs DIRs")
        from softpack.plots.paper_seeds import main_seeds
        return main_seeds(args)
    if not args.runs:
        parser.error("expected run directories DIR...")
    runs = load_runs(args.runs)
    if not runs:
        print("softpack plot: no complete run to plot", file=sys.stderr)
        return 1
    out = args.out or args.runs[0] / "figures"
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
