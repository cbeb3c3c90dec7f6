"""Figures and table of steady simple shears in a periodic cell.

``./softpack plot-shear RUN [RUN ...] [--out DIR] [--window W]`` reads each
run's analysis (done first when missing) and writes:

- ``shear.png`` (and ``.pdf``): mu*, Phi and the inertial number I against
  gamma over every run's last stage (the shear), the steady window shaded;
- ``steady.md`` and ``steady.json``: per run the window, the shear rate,
  each quantity's mean, fluctuation (std of the rows), standard error
  (batch means), drift and whether it is stationary
  (:mod:`softpack.analysis.steady_shear`); the balance residual over the
  cell's work; and, for every pair of runs, mu*'s difference against the
  fluctuation and the standard error.

Figures only: every number comes from the analysis modules.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import json
import sys
from pathlib import Path

import numpy as np

from softpack.analysis import steady_shear
from softpack.cli import positive_float
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table
from softpack.plots import style, write_figure

#: The table's columns: quantity and its label
TABLE = (("mu_star", "mu*"), ("phi", "Phi"), ("contact_yy", "sigma_yy (Pa)"),
         ("inertial_number", "I"), ("z", "Z"), ("fabric_anisotropy", "a_c"))


def ensure_analysis(run_dir) -> None:
    """Run the analysis of ``run_dir`` when its tables are missing."""
    run = RunDirectory(run_dir)
    if not run.raw.steps_csv.is_file():
        raise RunError(f"{run_dir}: no raw/steps.csv (not a run directory)")
    if not run.series_csv.is_file() or not run.stress_csv.is_file():
        from softpack.analysis.observables import process_run
        process_run(run_dir)


def figure(runs, states, out: Path) -> Path:
    """mu*, Phi and I against gamma of each run."""
    import matplotlib.pyplot as plt

    with style.context():
        fig, axes = plt.subplots(3, 1, figsize=(style.SINGLE_COLUMN, 5.2),
                                 sharex=True)
        for run, state in zip(runs, states):
            st = read_table(RunDirectory(run).stress_csv)
            rows = steady_shear.last_stage(
                read_table(RunDirectory(run).raw.steps_csv))
            st = {k: np.asarray(v)[rows] for k, v in st.items()}
            gamma = np.asarray(st["gamma"], float)
            label = f"{Path(run).name}: I = " \
                f"{state.stats['inertial_number'].mean:.2g}"
            for ax, key in zip(axes, ("mu_star", "phi", "inertial_number")):
                ax.plot(gamma, st[key], lw=0.7, label=label)
            for ax in axes:
                ax.axvspan(*state.gamma_window, color="0.9", zorder=0)
        for ax, name in zip(axes, (r"$\mu^*$", r"$\Phi$", "$I$")):
            ax.set_ylabel(name)
        axes[2].set_yscale("log")
        axes[2].set_xlabel(r"$\gamma$")
        axes[0].legend(frameon=False)
        return write_figure(fig, out / "shear.png")


def table(states, pairs) -> str:
    """``steady.md``: one row per run, then the pairs' mu* differences."""
    head = "| run | gamma window | rate (1/s) | balance | " + " | ".join(
        label for _, label in TABLE) + " |"
    lines = [head, "| --- " * (4 + len(TABLE)) + "|"]
    for s in states:
        cells = []
        for key, _ in TABLE:
            q = s.stats[key]
            if q.reason:
                cells.append("n/a")
                continue
            mark = "" if q.stationary else " (drifts)"
            cells.append(f"{q.mean:.4g} +- {q.fluctuation:.2g} "
                         f"(se {q.error:.1g}){mark}")
        lines.append(f"| {Path(s.run).name} | {s.gamma_window[0]:.2f}-"
                     f"{s.gamma_window[1]:.2f} | {s.shear_rate:.3g} | "
                     f"{s.balance:.1e} | " + " | ".join(cells) + " |")
    lines += ["", "mean +- fluctuation (std of the rows), se: standard error"
              " of the mean (batch means); balance: max |energy residual| /"
              " the cell's work at the end.", ""]
    for (a, b), c in pairs.items():
        lines.append(f"- mu* of {b} - {a}: {c['difference']:+.4f} against a"
                     f" fluctuation of {c['fluctuation']:.3f} and a standard"
                     f" error of {c['error']:.4f}: "
                     + ("within" if c["within_fluctuation"] else "beyond")
                     + " the fluctuation")
    return "\n".join(lines) + "\n"


def write_outputs(runs, out: Path, window: float = 0.5) -> dict:
    """The figure and tables of ``runs`` into ``out``; the summary."""
    for run in runs:
        ensure_analysis(run)
    states = [steady_shear.steady_state(run, window) for run in runs]
    out.mkdir(parents=True, exist_ok=True)
    pairs = {(Path(a.run).name, Path(b.run).name): steady_shear.compare(a, b)
             for a, b in itertools.combinations(states, 2)}
    (out / "steady.md").write_text(table(states, pairs))
    summary = {"runs": [dataclasses.asdict(s) for s in states],
               "pairs": [{"runs": list(k), **v} for k, v in pairs.items()],
               "figure": str(figure(runs, states, out))}
    (out / "steady.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def main(argv=None) -> int:
    """``./softpack plot-shear RUN [RUN ...] [--out DIR] [--window W]``."""
    parser = argparse.ArgumentParser(
        prog="softpack plot-shear", description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="finished shear runs in a"
                        " periodic cell (their last stage sheared)")
    parser.add_argument("--out", help="output directory (default:"
                        " RUN/figures/shear of the first run)")
    parser.add_argument("--window", type=positive_float, default=0.5,
                        help="the steady window: this last fraction of the"
                        " last stage's shear (default 0.5)")
    args = parser.parse_args(argv)
    if args.window > 1:
        parser.error(f"--window must be in (0, 1], not {args.window}")
    out = Path(args.out) if args.out else \
        Path(args.runs[0]) / "figures" / "shear"
    try:
        summary = write_outputs(args.runs, out, args.window)
    except RunError as err:
        print(f"softpack plot-shear: {err}", file=sys.stderr)
        return 2
    print((out / "steady.md").read_text(), end="")
    print(f"figures in {out} ({len(summary['runs'])} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
