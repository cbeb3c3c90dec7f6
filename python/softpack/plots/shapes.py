"""``python -m softpack.plots.shapes RUN[=LABEL]... --out DIR``: runs of
different particle shapes side by side (issue 13).

Only draws, from what the analysis stage wrote: each run's ``series.csv``,
``raw/setup.json`` and ``fields.h5``. Unlike ``./softpack plot`` (which
groups runs by friction and averages over seeds) every run here is its own
curve, labelled ``LABEL`` (default: the directory's name), so that a
pentagon run and a disk run at the same friction are compared, not
averaged.

phi_eps.png       Phi against eps.
energy.png        E/(W H L mu) against Phi.
z_phi.png         Z (two-node rule, rattlers removed, with wall contacts)
                  against Phi.
shape_distributions.png
                  per run, at its first and last field output: the
                  distribution of the particles' orientation (major axis of
                  the second moment of area, degrees; particles without one,
                  e.g. disks and regular polygons, are counted apart) and of
                  their asphericity P^2/(4 pi A) of the current boundary
                  and of their rigid rotation since the start (polar
                  rotation of the mean deformation gradient, degrees: the
                  orientation change of shapes without an axis)
                  (:mod:`softpack.analysis.shape`).
snapshots_LABEL.png
                  each run's deformed particles coloured by Psi/mu at
                  Phi = 0.78, 0.83, 0.88 where reached (the paper's Fig. 7
                  drawing, :func:`softpack.plots.paper.plot_snapshots`).
summary.csv       per run and target Phi (0.70 ... 0.88): eps, E/(WHL mu)
                  and Z interpolated at it; the run's largest Phi.

With ``--plates`` the directories are outputs of ``./softpack single-disk
--shape square|pentagon`` (:mod:`softpack.references.plates`) instead:
plates_force.png (f/(H0 mu) against eps, softpack as markers, dolfinx as
lines, one colour per element size; below, softpack/dolfinx - 1) and
plates_refinement.csv (:func:`softpack.references.plates.refinement`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from softpack.contract.run_directory import RunDirectory
from softpack.plots import style, write_figure

#: Packing fractions of summary.csv.
SUMMARY_PHIS = (0.70, 0.75, 0.80, 0.83, 0.85, 0.88)


def parse_runs(items) -> list[tuple[Path, str]]:
    """``DIR`` or ``DIR=LABEL`` -> (path, label)."""
    out = []
    for item in items:
        path, _, label = item.partition("=")
        out.append((Path(path), label or Path(path).name))
    return out


def monotone_part(phi, *columns):
    """Rows up to the largest Phi (the compaction branch), finite Phi."""
    phi = np.asarray(phi, float)
    ok = np.isfinite(phi)
    last = int(np.nanargmax(phi)) + 1
    ok[last:] = False
    return [np.asarray(c, float)[ok] for c in (phi, *columns)]


def at_phi(series, targets=SUMMARY_PHIS) -> list[dict]:
    """eps, E and Z interpolated at each target Phi the run reached."""
    phi, eps, energy, z = monotone_part(series["phi"], series["eps"],
                                        series["E_over_WHLmu"], series["z"])
    order = np.argsort(phi, kind="stable")
    rows = []
    for target in targets:
        if phi.size == 0 or target > phi.max():
            continue
        rows.append({"phi": target,
                     "eps": float(np.interp(target, phi[order], eps[order])),
                     "E_over_WHLmu": float(np.interp(target, phi[order],
                                                     energy[order])),
                     "z": float(np.interp(target, phi[order], z[order]))})
    return rows


def _curves(runs, x_name, y_name, xlabel, ylabel, path):
    """One curve per run of ``y(x)``, in softpack's one-column style."""
    import matplotlib.pyplot as plt

    with style.context():
        fig, ax = plt.subplots(figsize=(style.SINGLE_COLUMN,
                                        0.78 * style.SINGLE_COLUMN))
        for (run, label), marker in zip(runs, "osD^v<>"):
            x, y = run.series[x_name], run.series[y_name]
            ok = np.isfinite(x) & np.isfinite(y)
            ax.plot(x[ok], y[ok], marker=marker, ms=2, mfc="none", lw=0.8,
                    markevery=max(1, int(ok.sum()) // 40), label=label)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        ax.legend(frameon=False)
        write_figure(fig, path)


def shape_distributions(runs, path) -> list[str]:
    """Orientation and asphericity histograms; returns messages."""
    import matplotlib.pyplot as plt

    from softpack.analysis.fields import stored_times
    from softpack.analysis.shape import shapes_at

    messages, drawn = [], []
    for run, label in runs:  # only runs with fields get a column
        h5 = RunDirectory(run.path).fields_h5
        if not h5.is_file():
            messages.append(f"shape_distributions: {h5} missing; skipped")
            continue
        try:
            times = stored_times(h5)
            drawn.append((run, label, [shapes_at(h5, t)
                                       for t in (times[0], times[-1])]))
        except (OSError, KeyError) as err:
            messages.append(f"shape_distributions: cannot read {h5}: {err};"
                            " skipped")
    if not drawn:
        messages.append("shape_distributions: no run with fields; no figure")
        return messages
    with style.context():
        fig, axes = plt.subplots(
            3, len(drawn), squeeze=False,
            figsize=(style.DOUBLE_COLUMN if len(drawn) > 1
                     else style.SINGLE_COLUMN, 2.0 * 3))
    for col, (run, label, snaps) in enumerate(drawn):
        for s in snaps:
            phi = float(np.interp(s["time"], run.series["time"],
                                  run.series["phi"]))
            oriented = np.isfinite(s["orientation"])
            axes[0, col].hist(np.degrees(s["orientation"][oriented]),
                              bins=np.linspace(0, 180, 19), histtype="step",
                              lw=1.2, label=rf"$\Phi$ = {phi:.3f}"
                              f" ({(~oriented).sum()} without axis)")
            axes[1, col].hist(s["asphericity"], bins=20, histtype="step",
                              lw=1.2, label=rf"$\Phi$ = {phi:.3f}")
            axes[2, col].hist(np.degrees(s["rotation"]), bins=20,
                              histtype="step", lw=1.2,
                              label=rf"$\Phi$ = {phi:.3f}")
            messages.append(
                f"shape_distributions: {label} at Phi = {phi:.3f}:"
                f" asphericity mean {s['asphericity'].mean():.4f}, max"
                f" {s['asphericity'].max():.4f}; elongation mean"
                f" {s['elongation'].mean():.4f}; |rotation| mean"
                f" {np.degrees(np.abs(s['rotation'])).mean():.2f} deg")
        with style.context():
            axes[0, col].set_title(label)
            axes[0, col].set_xlabel("orientation (deg)")
            axes[1, col].set_xlabel(r"asphericity $P^2/(4\pi A)$")
            axes[2, col].set_xlabel("rotation since the start (deg)")
            for ax in axes[:, col]:
                ax.set_ylabel("particles")
                # room above the bars for the legend, which would cover them
                ax.set_ylim(top=1.45 * ax.get_ylim()[1])
                ax.legend(frameon=False, loc="upper right")
    with style.context():
        write_figure(fig, path)
    return messages


def write_summary(runs, path) -> None:
    lines = ["run,phi,eps,E_over_WHLmu,z,phi_max"]
    for run, label in runs:
        phi_max = float(np.nanmax(run.series["phi"]))
        for row in at_phi(run.series):
            lines.append(f"{label},{row['phi']:g},{row['eps']:.6g},"
                         f"{row['E_over_WHLmu']:.6g},{row['z']:.6g},"
                         f"{phi_max:.6g}")
        if not at_phi(run.series):
            lines.append(f"{label},,,,,{phi_max:.6g}")
    Path(path).write_text("\n".join(lines) + "\n")


def _plates_panel(axes, shape, runs) -> None:
    """One shape's force (top) and softpack/dolfinx - 1 (bottom), one
    colour per element size, finest last."""
    top, bottom = axes
    mine = sorted(runs, key=lambda r: -r[1])
    for (_, h, sp, dx), colour in zip(mine, ("C0", "C1", "C2", "C3")):
        label = f"$h$ = {h * 1e3:g} mm"
        top.plot(dx["eps"], dx["f_norm"], "-", color=colour, lw=0.8,
                 label=f"dolfinx, {label}")
        step = max(1, len(sp["eps"]) // 25)
        top.plot(sp["eps"][::step], sp["f_norm"][::step], "o", color=colour,
                 mfc="none", ms=3, mew=0.6, label=f"softpack, {label}")
        eps = dx["eps"][dx["eps"] >= 0.005]
        diff = np.interp(eps, sp["eps"], sp["f_norm"]) / np.interp(
            eps, dx["eps"], dx["f_norm"]) - 1
        bottom.plot(eps, 100 * diff, "o-", color=colour, ms=2, lw=0.8,
                    label=label)
    top.set_title(f"rounded {shape} between two plates")
    top.set_ylabel(r"$f / (H_0 \mu)$")
    top.set_ylim(bottom=0)
    bottom.axhline(0, color="k", lw=0.5)
    bottom.set_ylabel(r"softpack / dolfinx $- 1$ (%)")
    bottom.set_xlabel(r"$\varepsilon = -\ln(1 - \delta / H_0)$")


def plates_figures(directories, out) -> None:
    """plates_force.png and plates_refinement.csv (module doc)."""
    import json

    import matplotlib.pyplot as plt

    from softpack.contract.tables import read_table
    from softpack.references.plates import refinement

    runs = []
    for d in map(Path, directories):
        doc = json.loads((d / "plates.json").read_text())
        runs.append((doc["params"]["shape"], doc["params"]["element_size"],
                     read_table(d / "force_softpack.csv"),
                     read_table(d / "force_dolfinx.csv")))
    shapes = sorted({r[0] for r in runs})
    with style.context():
        fig, axes = plt.subplots(
            2, len(shapes), squeeze=False, sharex=True,
            figsize=(style.DOUBLE_COLUMN if len(shapes) > 1
                     else style.SINGLE_COLUMN, 4.2),
            gridspec_kw={"height_ratios": [2, 1]})
        for col, shape in enumerate(shapes):
            _plates_panel(axes[:, col], shape,
                          [r for r in runs if r[0] == shape])
        # one legend for the figure, under the panels: colours are the
        # element sizes, markers softpack and lines dolfinx
        handles, labels = axes[0, 0].get_legend_handles_labels()
        fig.tight_layout()
        fig.legend(handles, labels, loc="upper center", frameon=False,
                   bbox_to_anchor=(0.5, 0.0), ncols=max(1, len(labels) // 2))
        write_figure(fig, Path(out) / "plates_force.png", tight=False)
    rows = refinement(directories)
    lines = [",".join(rows[0])]
    for row in rows:
        lines.append(",".join(v if isinstance(v, str) else f"{v:.6g}"
                              for v in row.values()))
    (Path(out) / "plates_refinement.csv").write_text("\n".join(lines) + "\n")


def main(argv=None) -> int:
    import matplotlib
    matplotlib.use("Agg")

    if argv is None:
        argv = sys.argv[1:]
    if "--plates" in argv:
        p = argparse.ArgumentParser(prog="python -m softpack.plots.shapes"
                                    " --plates")
        p.add_argument("--plates", action="store_true")
        p.add_argument("dirs", nargs="+")
        p.add_argument("--out", type=Path, required=True)
        args = p.parse_args(argv)
        args.out.mkdir(parents=True, exist_ok=True)
        with style.context():
            plates_figures(args.dirs, args.out)
        print(f"wrote {args.out}/plates_force.png, plates_refinement.csv")
        return 0

    from softpack.plots.paper import load_runs, plot_snapshots

    p = argparse.ArgumentParser(prog="python -m softpack.plots.shapes",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("runs", nargs="+", help="run directory, or DIR=LABEL")
    p.add_argument("--out", type=Path, required=True,
                   help="directory of the figures")
    args = p.parse_args(argv)
    wanted = parse_runs(args.runs)
    runs = []
    for path, label in wanted:
        loaded = load_runs([path])
        if loaded:
            runs.append((loaded[0], label))
    if not runs:
        print("softpack plots.shapes: no complete run given", file=sys.stderr)
        return 1
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    with style.context():
        _curves(runs, "eps", "phi", r"$\varepsilon = -\ln(1 - \delta / L_0)$",
                r"$\Phi$", out / "phi_eps.png")
        _curves(runs, "phi", "E_over_WHLmu", r"$\Phi$", r"$E/(WHL\mu)$",
                out / "energy.png")
        _curves(runs, "phi", "z", r"$\Phi$", "$Z$", out / "z_phi.png")
        for message in shape_distributions(runs, out /
                                           "shape_distributions.png"):
            print(message)
        for run, label in runs:
            print(plot_snapshots(run, out / f"snapshots_{label}.png"))
    write_summary(runs, out / "summary.csv")
    print(f"softpack plots.shapes: wrote {out}/phi_eps.png, energy.png,"
          " z_phi.png, shape_distributions.png, snapshots_*.png,"
          " summary.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
