"""The DIC estimator's figures for one run (paper Figs. 5 and 6).

``/usr/bin/python3 -m softpack.plots.dic RUN --out DIR`` writes into DIR:

``dic_series.csv``
    :func:`softpack.analysis.dic.dic_series` at every stored field time
    (through :mod:`softpack.contract.tables`).
``dic_energy.png``
    E_DIC/(W H L mu) and the finite-element E/(W H L mu) against Phi (as the
    paper's Fig. 6), and their ratio.
``dic_i1_pdf.png``
    The probability density of I1 (Eq. 13) over the particles' reference
    area at the stored fields nearest Phi = 0.79, 0.84, 0.88 (Fig. 5); the
    legend gives the Phi actually drawn and says when it is far from the
    target.
``dic_summary.txt``
    E_DIC/E_FE at the fields nearest Phi = 0.80, 0.84, 0.88, and what
    Fig. 5 drew.

Only draws and formats; the numbers come from :mod:`softpack.analysis.dic`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from softpack.analysis import dic
from softpack.analysis import fields as fields_io
from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import write_table
from softpack.plots import style, write_figure

#: Packing fractions at which the summary states E_DIC / E_FE.
SUMMARY_PHI = (0.80, 0.84, 0.88)
#: Number of bins of the density, from I1 = 3 (the paper's Fig. 5 starts
#: there) to the largest I1 drawn.
I1_BINS = 60


def i1_density(estimate, bins):
    """Area-weighted probability density of I1 on the bin edges ``bins``.

    Each triangle counts with its reference area, as each DIC pixel counts
    with one reference pixel. Normalised by the whole area, so the density
    integrates to the fraction of area inside the range.

    Returns
    -------
    (ndarray, ndarray, float)
        Bin centres, density, fraction of the area above the range.
    """
    weight, edges = np.histogram(estimate.i1, bins=bins,
                                 weights=estimate.area)
    total = estimate.area.sum()
    density = weight / (total * np.diff(edges))
    above = estimate.area[estimate.i1 > edges[-1]].sum() / total
    return 0.5 * (edges[1:] + edges[:-1]), density, float(above)


def particle_spread(estimate, share=0.01) -> str:
    """Per-particle E_DIC/E_FE and the model's area change, as one line.

    Particles holding less than ``share`` of the mean particle energy are
    left out of the ratio (their ratio is noise over nothing).
    """
    fe, est = estimate.fe_per_particle, estimate.per_particle
    keep = fe > share * np.nanmean(fe)
    ratio = est[keep] / fe[keep]
    lo, mid, hi = (np.percentile(ratio, [5, 50, 95]) if ratio.size
                   else (np.nan,) * 3)
    change = np.average(np.abs(estimate.det - 1.0), weights=estimate.area)
    return (f"per particle ({keep.sum()} holding > {share:.0%} of the mean"
            f" energy): E_DIC/E_FE median {mid:.4f}, 5-95 % {lo:.4f} to"
            f" {hi:.4f}; area-weighted mean |det F_2D - 1| = {change:.4f},"
            f" min det F_2D = {estimate.det.min():.4f}")


def _nearest(series, phi):
    """Index of the row of ``series`` with Phi nearest ``phi``."""
    return int(np.nanargmin(np.abs(series["phi"] - phi)))


def plot_energy(series, path) -> None:
    """E/(W H L mu) against Phi, DIC and FE, and their ratio."""
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(style.DOUBLE_COLUMN, 2.6))
    ax.plot(series["phi"], series["E_fe_over_WHLmu"], "k-",
            label="finite elements (plane strain, $\\tilde\\lambda=2\\mu$)")
    ax.plot(series["phi"], series["E_dic_over_WHLmu"], "rs", ms=2, mfc="none",
            mew=0.6, label="DIC estimator (Eqs. 2, 12-13)")
    ax.set_xlabel("$\\Phi$")
    ax.set_ylabel("$\\mathcal{E}/WHL\\mu$")
    ax.legend(frameon=False)
    bx.plot(series["phi"], series["ratio"], "ro-", ms=2)
    bx.axhline(1.0, color="0.5", lw=0.8)
    bx.set_xlabel("$\\Phi$")
    bx.set_ylabel("$\\mathcal{E}_{DIC}/\\mathcal{E}_{FE}$")
    write_figure(fig, path)


def plot_i1_pdf(run_dir, picks, path) -> list[str]:
    """P(I1) at the picked field times; returns one line per curve."""
    import matplotlib.pyplot as plt

    setup = read_setup(run_dir)
    h5 = RunDirectory(run_dir).fields_h5
    fig, ax = plt.subplots(figsize=(style.SINGLE_COLUMN, 0.78 * style.SINGLE_COLUMN))
    lines, drawn = [], set()
    estimates = {time: dic.dic_energy(fields_io.read_snapshot(h5, time),
                                      setup.shear_modulus, setup.thickness,
                                      setup.count)
                 for _, time, _, _ in picks}
    top = max(float(e.i1.max()) for e in estimates.values())
    bins = np.linspace(3.0, 3.0 + 1.0001 * (top - 3.0), I1_BINS + 1)
    for target, time, phi, within in picks:
        estimate = estimates[time]
        centres, density, above = i1_density(estimate, bins)
        note = "" if within else f" (target {target:.2f} not reached)"
        if time not in drawn:  # a run short of a target repeats a field
            drawn.add(time)
            ax.semilogy(centres, np.where(density > 0, density, np.nan),
                        ".-", ms=2, label=f"$\\Phi$ = {phi:.3f}{note}")
        lines.append(f"Phi = {phi:.4f} (target {target:.2f}"
                     f"{'' if within else ', NOT within 0.005'}), t = "
                     f"{time:.5g} s: mean I1 = "
                     f"{np.average(estimate.i1, weights=estimate.area):.4f},"
                     f" max I1 = {estimate.i1.max():.3f}")
        lines.append("    " + particle_spread(estimate))
    ax.set_xlabel("$I_1$ (Eq. 13)")
    ax.set_ylabel("$P(I_1)$")
    ax.legend(frameon=False)
    write_figure(fig, path)
    return lines


def write_outputs(run_dir, out_dir) -> str:
    """Write the table, both figures and the summary; return the summary."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    series = dic.dic_series(run_dir)
    write_table(out_dir / "dic_series.csv", series)
    picks = dic.nearest_field_times(run_dir)
    with style.context():
        plot_energy(series, out_dir / "dic_energy.png")
        pdf_lines = plot_i1_pdf(run_dir, picks, out_dir / "dic_i1_pdf.png")
    lines = [f"run: {Path(run_dir).as_posix()}",
             f"fields at {len(series['time'])} times,"
             f" Phi {np.nanmin(series['phi']):.4f} to"
             f" {np.nanmax(series['phi']):.4f}",
             "E_DIC / E_FE at the stored fields nearest:"]
    for phi in SUMMARY_PHI:
        k = _nearest(series, phi)
        far = ("" if abs(series["phi"][k] - phi) <= 0.005
               else " (NOT within 0.005: the run has no field there)")
        lines.append(f"  Phi {phi:.2f}: field at Phi = {series['phi'][k]:.4f}"
                     f"{far}:"
                     f" E_DIC/(WHLmu) = {series['E_dic_over_WHLmu'][k]:.5g},"
                     f" E_FE/(WHLmu) = {series['E_fe_over_WHLmu'][k]:.5g},"
                     f" ratio = {series['ratio'][k]:.4f}")
    fe_check = np.nanmax(np.abs(series["E_fe_fields"] - series["E_fe_series"])
                         / np.where(series["E_fe_series"] > 0,
                                    series["E_fe_series"], np.nan))
    lines.append(f"Psi field integral vs series.csv strain energy: largest"
                 f" relative difference {fe_check:.2e}")
    lines.append("P(I1) (Fig. 5):")
    lines += ["  " + line for line in pdf_lines]
    text = "\n".join(lines) + "\n"
    (out_dir / "dic_summary.txt").write_text(text)
    return text


def main(argv=None) -> int:
    """``python -m softpack.plots.dic RUN --out DIR``."""
    import matplotlib
    matplotlib.use("Agg")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", help="a run directory with fields.h5")
    parser.add_argument("--out", required=True, help="output directory")
    args = parser.parse_args(argv)
    sys.stdout.write(write_outputs(args.run, args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
