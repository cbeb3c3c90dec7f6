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
fig7_snapshots.png (and .pdf)
    Deformed particles coloured by Psi / mu at Phi = 0.78, 0.83, 0.88 (Fig. 7),
    for one run (mu_f = 0.3 if present, lowest seed), from its fields, as
    :mod:`.snapshots` draws them (walls where they are, outlines, scale
    bar). Skipped, with a message, when fields are missing or the run does
    not reach these Phi.
snapshots.png (and .pdf; ``snapshots-DIR.png`` with several runs)
    With ``--at STATE`` (repeated): each run's particles at those states
    (:mod:`.snapshots`: ``phi=``, ``time=``, ``stage=``, ``last``).
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

from softpack.analysis.setup import SetupError, read_setup
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table
from softpack.plots import snapshots, style
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
    try:
        states = snapshots.RunStates(run.path)
    except (KeyError, OSError) as err:
        return f"fig7: cannot read {h5}: {err}; skipped"
    phi = np.asarray(states.series["phi"], float)
    picks, far = [], ""
    for target in SNAPSHOT_PHIS:
        try:
            k = snapshots.pick_row(states.series, states.stages, "phi",
                                   target)
        except RunError:
            continue
        # The frame drawn is the stored one nearest the row: it must be
        # near the Phi asked for too.
        frame = states.frame_row(k)
        if abs(phi[frame] - target) > SNAPSHOT_TOLERANCE:
            far += (f"; no frame near Phi = {target:.3f} (nearest"
                    f" {phi[frame]:.3f})")
            continue
        picks.append(("time", float(states.series["time"][frame])))
    if not picks and not far:
        return (f"fig7: {run.path} never came within {SNAPSHOT_TOLERANCE}"
                f" of Phi = {SNAPSHOT_PHIS}; skipped")
    if not picks:
        return f"fig7: {h5}: no frame within {SNAPSHOT_TOLERANCE}{far}; skipped"
    style.save(snapshots.snapshot_figure(run.path, picks), path)
    rows = [int(np.argmin(np.abs(states.series["time"] - t)))
            for _, t in picks]
    return (f"fig7: {run.path}, Phi = "
            + ", ".join(f"{phi[k]:.3f}" for k in rows) + far)


def draw_states(runs, states, out) -> list:
    """``--at``: each run's snapshots (``snapshots.png``, or
    ``snapshots-NAME.png`` with several runs); the files written."""
    written = []
    for run in runs:
        name = ("snapshots.png" if len(runs) == 1
                else f"snapshots-{run.path.name}.png")
        try:
            written += snapshots.write_snapshots(run.path, states, out / name)
        except (RunError, KeyError, OSError) as err:
            print(f"softpack plot: {run.path}: {err}; no snapshots",
                  file=sys.stderr)
    return written


def snapshot_run(groups) -> Run:
    """The run drawn in Fig. 7: mu_f = 0.3 if present, lowest seed."""
    mu = 0.3 if 0.3 in groups else next(iter(groups))
    return groups[mu][0]


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack plot``."""
    p = argparse.ArgumentParser(
        prog="softpack plot",
        description="Draw the paper's Figs. 4, 6, 7, 8, 9 from run"
        " directories (grouped by friction, averaged over seeds); with --at,"
        " each run's particles at the states asked for.")
    p.add_argument("runs", nargs="*", type=Path, metavar="DIR",
                   help="run directories written by ./softpack run")
    p.add_argument("--out", type=Path, metavar="FIGDIR",
                   help="figure directory (default: the first DIR's"
                   " figures/; nothing is written in the current directory)")
    p.add_argument("--at", action="append", metavar="STATE", default=[],
                   help="draw each DIR's particles at this state into"
                   " snapshots[-DIR].png/.pdf: phi=VALUE (the output row"
                   " nearest in Phi, within 0.01), time=SECONDS, stage=K"
                   " (the end of stage K, as raw/steps.csv's stage column)"
                   " or last; repeat for several panels")
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
    try:
        states = [snapshots.parse_at(text) for text in args.at]
    except ValueError as err:
        parser.error(str(err))
    runs = load_runs(args.runs)
    if not runs:
        print("softpack plot: no complete run to plot", file=sys.stderr)
        return 1
    out = args.out or args.runs[0] / "figures"
    out.mkdir(parents=True, exist_ok=True)
    groups = group_by_friction(runs)
    written = [
        plot_curves(groups, "eps", "phi",
                    r"$\varepsilon = -\ln(1 - \delta / L)$", r"$\Phi$",
                    out / "fig4_phi_eps.png"),
        plot_curves(groups, "phi", "E_over_WHLmu", r"$\Phi$", r"$E/(WHL\mu)$",
                    out / "fig6_energy.png"),
        plot_curves(groups, "phi", "cv_psi", r"$\Phi$", r"$c_v(\Psi_p)$",
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
    if states:
        written += draw_states(runs, states, out)
    print(f"softpack plot: {len(runs)} run(s) in {len(groups)} friction"
          f" group(s); wrote {', '.join(str(p) for p in written)}")
    return 0
