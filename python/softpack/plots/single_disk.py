"""``./softpack plot-single-disk DIR``: the paper's Figs. 2 and 3 for one cylinder.

Reads from DIR whatever exists of
  force_2d.csv, force_3d_nu0495.csv, force_3d_incompressible.csv     (eps,f_norm)
  profile_2d.csv, profile_3d_nu0495.csv, profile_3d_incompressible.csv,
  profile_3d_nu0495_endface.csv                                       (eps,w,ux_over_D)
and writes DIR/fig2_force.png (with its PDF beside it; f/(D l mu) against eps: 2D as markers, 3D as
lines, plus Johnson's small-strain line-contact curves) and DIR/fig3_profile.png
(u_x/D along the transverse diameter, w = X/R, at eps = 0.05 ... 0.20). It says
which files it used and which it did not find; the 2D files are optional.
"""

import argparse
import os
import sys

import numpy as np

from softpack.contract.tables import read_table
from softpack.plots import style, write_figure

FORCE_FILES = (  # file, label, style (2D: markers, 3D: lines)
    ("force_2d.csv", r"2D plane strain, $\tilde\nu$ = 1/3",
     dict(ls="none", marker="^", mfc="none", ms=3, mew=0.6)),
    ("force_3d_nu0495.csv", r"3D, $\nu$ = 0.495", dict(ls="-")),
    ("force_3d_incompressible.csv", "3D, incompressible", dict(ls="--")),
)
PROFILE_FILES = (
    ("profile_2d.csv", "2D", dict(ls="none", marker="^", mfc="none", ms=2.5, mew=0.5)),
    ("profile_3d_nu0495.csv", r"3D $\nu$ = 0.495, mid-plane", dict(ls="-")),
    ("profile_3d_incompressible.csv", "3D incompressible, mid-plane", dict(ls="--")),
    ("profile_3d_nu0495_endface.csv", r"3D $\nu$ = 0.495, end face", dict(ls=":", lw=0.8)),
)
PROFILE_STRAINS = (0.05, 0.10, 0.15, 0.20)


def _load(directory, files, used, missing):
    """[(data, label, style)] for the files that exist; fills used/missing."""
    found = []
    for name, label, line in files:
        path = os.path.join(directory, name)
        if os.path.isfile(path):
            found.append((read_table(path), label, line))
            used.append(name)
        else:
            missing.append(name)
    return found


def _figure():
    """A one-column figure in softpack's style."""
    import matplotlib.pyplot as plt

    with style.context():
        return plt.subplots(figsize=(style.SINGLE_COLUMN, 0.85 * style.SINGLE_COLUMN))


def _save(fig, ax, title, out, ncols=1):
    """Title, and the legend under the axes (it would cover the curves
    inside them), then write the PNG and PDF and close the figure."""
    with style.context():
        ax.legend(frameon=False, loc="upper center", bbox_to_anchor=(0.5, -0.25),
                  ncols=ncols, fontsize=6)
        ax.set_title(title)
        write_figure(fig, out)


def plot_force(curves, out):
    """Fig. 2: f/(D l mu) against eps, with Johnson's line-contact curves.

    ``curves``: (table with columns eps, f_norm; label; line style) triples;
    ``out``: the PNG file.
    """
    import matplotlib.pyplot as plt
    from softpack.references.cylinder3d import johnson_line_contact

    fig, ax = _figure()
    for data, label, line in curves:
        if line.get("ls") == "none" and len(data["eps"]) > 40:
            # a driver run writes hundreds of rows: about 25 markers
            line = dict(line, markevery=max(1, len(data["eps"]) // 25))
        ax.plot(data["eps"], data["f_norm"], color="k", label=label, **line)
    eps = np.linspace(0.0, 0.25, 101)
    ax.plot(eps, johnson_line_contact(eps, 0.495, plane_strain=True), color="tab:red",
            lw=0.8, label=r"Johnson line contact, $E^* = E/(1-\nu^2)$, $\nu$ = 0.495")
    ax.plot(eps, johnson_line_contact(eps, 1.0 / 3.0, plane_strain=True), color="tab:blue",
            lw=0.8, ls="-.", label=r"Johnson line contact, plane strain $\nu$ = 1/3")
    with style.context():
        ax.set_xlabel(r"$\varepsilon = -\ln(1 - \delta/D)$")
        ax.set_ylabel(r"$f / (D \ell \mu)$")
    ax.set_xlim(0, 0.25)
    ax.set_ylim(bottom=0)
    _save(fig, ax, "single cylinder between plates (paper Fig. 2)", out)


def plot_profile(curves, out):
    """Fig. 3: u_x/D against w = X/R at the strains of PROFILE_STRAINS.

    ``curves``: (table with columns eps, w, ux_over_D; label; line style)
    triples; ``out``: the PNG file.
    """
    import matplotlib.pyplot as plt

    fig, ax = _figure()
    colors = dict(zip(PROFILE_STRAINS, ("tab:blue", "tab:orange", "tab:green", "tab:red")))
    for data, label, line in curves:
        for eps, color in colors.items():
            sel = np.abs(data["eps"] - eps) < 1e-6
            if np.any(sel):
                order = np.argsort(data["w"][sel])
                ax.plot(data["w"][sel][order], data["ux_over_D"][sel][order], color=color, **line)
    for eps, color in colors.items():
        ax.plot([], [], color=color, label=rf"$\varepsilon$ = {eps:.2f}")
    for _, label, line in curves:
        ax.plot([], [], color="k", label=label, **line)
    ax.axhline(0, color="0.7", lw=0.5)
    with style.context():
        ax.set_xlabel(r"$w = X/R$ (normal to the loading)")
        ax.set_ylabel(r"$u_x / D$")
    ax.set_xlim(-1, 1)
    ax.set_xticks(np.linspace(-1, 1, 5))
    _save(fig, ax, "transverse displacement (paper Fig. 3)", out, ncols=2)


def main(argv=None):
    """Entry point of ``./softpack plot-single-disk``; returns the exit status."""
    parser = argparse.ArgumentParser(prog="softpack plot-single-disk", description=__doc__.split("\n")[0])
    parser.add_argument("dir", help="directory holding the single-disk CSV files")
    args = parser.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")

    used, missing = [], []
    forces = _load(args.dir, FORCE_FILES, used, missing)
    profiles = _load(args.dir, PROFILE_FILES, used, missing)
    if not forces and not profiles:
        print(f"plot-single-disk: none of the expected CSV files in {args.dir}: "
              f"{', '.join(missing)}", file=sys.stderr)
        return 1
    written = []
    with style.context():
        if forces:
            plot_force(forces, os.path.join(args.dir, "fig2_force.png"))
            written.append("fig2_force.png")
        if profiles:
            plot_profile(profiles, os.path.join(args.dir, "fig3_profile.png"))
            written.append("fig3_profile.png")
    print(f"plot-single-disk: used {', '.join(used)}")
    if missing:
        print(f"plot-single-disk: not found (skipped): {', '.join(missing)}")
    print(f"plot-single-disk: wrote {', '.join(os.path.join(args.dir, w) for w in written)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
