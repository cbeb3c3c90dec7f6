"""Figures of a loading run: compaction and shear.

``./softpack plot-loading RUN [--out DIR] [--estimate fe|contact|wall]
[--rest R] [--stage K] [--unchecked]`` writes, from a run directory (its analysis, ``series.csv`` and
``stress.csv``, is done first when missing):

- ``pressure_phi.png``: P(Phi) of the three stress estimates and the fitted
  compaction law (:mod:`softpack.analysis.compaction_law`) on the chosen
  estimate (default: the finite elements' when the run has it, which needs
  no ``fields.h5`` and is not biased by wall friction as the wall-total
  fallback is; else Love-Weber, else the walls), or the reason it was
  refused. With loading stages (the ``stage`` column of ``raw/steps.csv``)
  the law is fitted to the rows at rest only (kinetic energy <= R x strain
  energy, default R = 1e-3: P(Phi) is an equilibrium relation) and the
  bootstrap resamples whole stages; a run without stages (a continuous,
  slow loading) uses every row unless ``--rest`` is given;
- ``z_phi.png``: the coordination number Z(Phi) (the analysis' rules);
- ``stress_estimates.png``: the relative differences of the three
  estimates against the step (they must vanish at rest);
- ``shear.png``: q/P and eps_v against eps_q (a shear test);
- ``loading.json``: the fit (values, errors, method or reason) and the
  last row's P, q and differences;
- with ``--unchecked``, ``law_unchecked.png`` and ``fit_unchecked`` in
  ``loading.json``: the law fitted to the same rows with every refusal
  switched off (what a refused fit would have drawn), for illustration.

Figures only: every number comes from the analysis modules.
"""

from __future__ import annotations

import argparse
import json
import sys
import textwrap
from pathlib import Path

import numpy as np

from softpack.analysis import compaction_law
from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table
from softpack.cli import positive_float
from softpack.plots import style, write_figure

ESTIMATES = ("wall", "contact", "fe")
LABELS = {"wall": "walls", "contact": "Love-Weber (contacts)",
          "fe": "finite elements (particles' stress)"}


def load(run_dir) -> tuple[dict, dict]:
    """``(series, stress)`` of a run, running its analysis when missing."""
    run = RunDirectory(run_dir)
    if not run.series_csv.is_file() or not run.stress_csv.is_file():
        from softpack.analysis.observables import process_run
        process_run(run_dir)
    if not run.stress_csv.is_file():
        raise RunError(f"{run.path}: no {run.stress_csv.name} (a run"
                       " without a box has no assembly stress)")
    return read_table(run.series_csv), read_table(run.stress_csv)


def _figure(rows=1):
    """A one-column figure (``rows`` panels) in softpack's style."""
    import matplotlib.pyplot as plt
    with style.context():
        return plt.subplots(rows, 1, sharex=True, figsize=(
            style.SINGLE_COLUMN, 0.78 * style.SINGLE_COLUMN * rows ** 0.8))


def _save(fig, ax, xlabel, ylabel, path) -> str:
    with style.context():
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6, frameon=False)
        write_figure(fig, path)
    return str(path)


def mark_stages(ax, steps, stage) -> None:
    """A dotted line at each step where a stage begins, labelled with it."""
    stage = np.asarray(stage)
    for k in np.flatnonzero(np.diff(stage)) + 1:
        ax.axvline(steps[k], color="0.5", ls=":", lw=0.8)
        ax.text(steps[k], 1.0, f" stage {int(stage[k])}", rotation=90,
                va="top", ha="left", fontsize=6, color="0.4",
                transform=ax.get_xaxis_transform())


def rows_at_rest(steps: dict, rest: float) -> np.ndarray:
    """Rows whose kinetic energy is at most ``rest`` x the strain energy."""
    kinetic = np.asarray(steps["kinetic_energy"], float)
    strain = np.asarray(steps["strain_energy"], float)
    return (strain > 0) & (kinetic <= rest * strain)


def plot_pressure(phi, stress, fit, estimate, rest, path, note="") -> str:
    """P(Phi) of each estimate (rows at rest filled), the law on one;
    ``note``: a title (else the refusal's reason when there is one)."""
    fig, ax = _figure()
    top = 0.0
    for i, name in enumerate(ESTIMATES):
        p = np.asarray(stress[f"{name}_P"], float)
        if np.isfinite(p).any():
            top = max(top, float(np.nanmax(p)) / 1e3)
            line, = ax.plot(phi, p / 1e3, ("o", "s", "^")[i], ms=2.5,
                            mfc="none", alpha=0.35)
            ax.plot(phi[rest], p[rest] / 1e3, ("o", "s", "^")[i], ms=3.5,
                    color=line.get_color(), label=LABELS[name]
                    + ("" if rest.all() else " (rows at rest)"))
    if fit.ok:
        v = fit.values
        grid = np.linspace(v["phi_0"], min(np.nanmax(phi) + 0.01,
                                           v["phi_max"] - 1e-4), 200)
        ax.plot(grid, compaction_law.pressure(grid, **v) / 1e3, "k-", lw=1,
                label=rf"law on {estimate}: $\Phi_{{max}}$ ="
                      f" {v['phi_max']:.4f} +- {fit.errors['phi_max']:.4f}")
        ax.axvline(v["phi_max"], color="k", ls=":", lw=0.8)
        if top > 0:  # the law diverges at Phi_max: the data's range
            ax.set_ylim(top=1.15 * top)
    if note or not fit.ok:
        # wrapped by hand: a long line widens the one-column figure
        ax.set_title(textwrap.fill(note or fit.summary(), 60), fontsize=7)
    return _save(fig, ax, r"packing fraction $\Phi$", "$P$ (kPa)", path)


def plot_connectivity(series, path) -> str:
    """Z(Phi) of the analysis."""
    fig, ax = _figure()
    ax.plot(series["phi"], series["z"], "o", ms=3, mfc="none", label="$Z$")
    return _save(fig, ax, r"packing fraction $\Phi$",
                 "coordination number $Z$", path)


def plot_differences(stress, path, stage=None) -> str:
    """Relative differences of the three estimates against the step, the
    stages marked."""
    fig, ax = _figure()
    for column, label in (("difference", "walls vs contacts"),
                          ("difference_wall_fe", "walls vs FE"),
                          ("difference_contact_fe", "contacts vs FE")):
        values = np.asarray(stress.get(column, []), float)
        if np.isfinite(values).any():
            ax.semilogy(stress["step"], values, ".", ms=3, label=label)
    ax.axhline(0.02, color="k", ls=":", lw=0.8)
    if stage is not None:
        mark_stages(ax, np.asarray(stress["step"]), stage)
    return _save(fig, ax, "step", "relative difference $|a - b|/|a|$", path)


def plot_shear(shear, path, stage=0) -> str:
    """q/P and eps_v against eps_q (two panels), strains from the stage's
    start."""
    fig, (top, bottom) = _figure(2)
    top.set_title(f"stage {stage}, strains from its start", fontsize=8)
    top.plot(shear["eps_q"], shear["q_over_p"], "-", lw=1)
    top.set_ylabel("$q/P$")
    bottom.plot(shear["eps_q"], shear["eps_v"], "-", lw=1)
    bottom.axhline(0, color="k", lw=0.5)
    return _save(fig, bottom,
                 r"deviatoric strain $\varepsilon_q = \varepsilon_{xx} -"
                 r" \varepsilon_{yy}$",
                 r"volumetric strain $\varepsilon_v$", path)


def choose_estimate(stress: dict, rigid: int = 0) -> str:
    """The first of fe, contact, wall with a finite P in some row; not fe
    when ``rigid`` bodies (the finite elements give no stress inside a
    rigid body)."""
    for name in ("fe", "contact", "wall"):
        if name == "fe" and rigid:
            continue
        if np.isfinite(np.asarray(stress[f"{name}_P"], float)).any():
            return name
    return "wall"


def check_estimate(estimate: str, rigid: int, count: int) -> None:
    """Refuse the finite-element estimate of a run with rigid bodies: it
    leaves their stress out (measured on a rigid+soft run: 2.6 kPa against
    4.7 kPa from the contacts and 5.5 kPa from the walls)."""
    if estimate == "fe" and rigid:
        raise RunError(f"estimate 'fe': {rigid} of the {count} bodies are"
                       " rigid and the finite elements give no stress inside"
                       " them; use 'contact' (Love-Weber) or 'wall'")


def stage_shear(stress: dict, estimate: str, rows) -> dict:
    """The shear series of one stage's rows, its strains counted from the
    stage's first row (a biaxial test's strains start at its consolidated
    state, not at the box of the approach)."""
    shear = compaction_law.shear_series(
        {k: np.asarray(v)[rows] for k, v in stress.items()}, estimate)
    for name in ("eps_q", "eps_v"):
        shear[name] = shear[name] - shear[name][0]
    return shear


def write_figures(run_dir, out, estimate=None, rest=None,
                  shear_stage=None, unchecked=False) -> dict:
    """Write the figures and ``loading.json``; return the summary dict.

    ``shear_stage``: the stage (index) whose q/P and strains ``shear.png``
    draws; default the last stage (the whole run without stages).
    ``unchecked``: also ``law_unchecked.png`` and ``fit_unchecked``, the
    law fitted to the same rows with its refusals switched off (for
    illustration only: a curve the law does not describe)."""
    import matplotlib
    matplotlib.use("Agg")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    series, stress = load(run_dir)
    steps = read_table(RunDirectory(run_dir).raw.steps_csv)
    phi = np.asarray(series["phi"], float)
    setup = read_setup(run_dir)
    rigid = int(np.count_nonzero(setup.body_rigid))
    estimate = estimate or choose_estimate(stress, rigid)
    check_estimate(estimate, rigid, setup.count)
    p = np.asarray(stress[f"{estimate}_P"], float)
    stage = np.asarray(steps.get("stage", np.zeros(len(phi))))
    if rest is None and len(np.unique(stage)) > 1:
        rest = 1e-3
    at_rest = (rows_at_rest(steps, rest) if rest is not None
               else np.ones(len(phi), bool))
    groups = stage[at_rest] if len(np.unique(stage[at_rest])) > 1 else None
    fit = compaction_law.fit_compaction(phi[at_rest], p[at_rest],
                                        groups=groups)
    shear_stage = int(stage.max()) if shear_stage is None else shear_stage
    if shear_stage not in set(stage.astype(int)):
        raise RunError(f"{run_dir}: no stage {shear_stage} (the run has"
                       f" stages {sorted(set(stage.astype(int)))})")
    shear = stage_shear(stress, estimate, stage == shear_stage)
    files = [plot_pressure(phi, stress, fit, estimate, at_rest,
                           out / "pressure_phi.png"),
             plot_connectivity(series, out / "z_phi.png"),
             plot_differences(stress, out / "stress_estimates.png",
                              stage[:len(stress["step"])]),
             plot_shear(shear, out / "shear.png", shear_stage)]
    free = None
    if unchecked:
        free = compaction_law.fit_compaction(phi[at_rest], p[at_rest],
                                             groups=groups, checked=False)
        files.append(plot_pressure(
            phi, stress, free, estimate, at_rest, out / "law_unchecked.png",
            note="the law with its checks switched off: for illustration"
                 " only" if free.ok else ""))
    last = {c: float(stress[c][-1]) for c in stress
            if c.startswith(tuple(f"{e}_" for e in ESTIMATES))
            and c.endswith(("_P", "_q")) or c.startswith("difference")}
    summary = {"run": str(run_dir), "estimate": estimate,
               "rows": len(phi), "rows_at_rest": int(at_rest.sum()),
               "rest": rest, "stages": int(len(np.unique(stage))),
               "phi_last": float(phi[-1]),
               "fit": {"values": fit.values, "errors": fit.errors,
                       "method": fit.method, "reason": fit.reason,
                       "points": fit.points,
                       "pressure_max": fit.pressure_max},
               "last_row": last,
               **({} if free is None else {"fit_unchecked": {
                   "values": free.values, "errors": free.errors,
                   "method": free.method, "reason": free.reason,
                   "points": free.points}}),
               "shear": {"stage": shear_stage, "estimate": estimate,
                         **{f"{k}_end": float(v[-1]) for k, v in
                            shear.items()},
                         "q_over_p_max": float(np.nanmax(shear["q_over_p"]))
                         if np.isfinite(shear["q_over_p"]).any() else None},
               "figures": files}
    (out / "loading.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def main(argv=None) -> int:
    """``./softpack plot-loading RUN [--out DIR] [--estimate E]``."""
    parser = argparse.ArgumentParser(
        prog="softpack plot-loading", description=__doc__.splitlines()[0])
    parser.add_argument("run", help="a finished run directory with a box")
    parser.add_argument("--out", help="output directory (default:"
                        " RUN/figures/loading)")
    parser.add_argument("--estimate", choices=ESTIMATES,
                        help="the stress estimate the law is fitted to"
                        " (default: fe if the run has it and no rigid"
                        " body, else contact, else wall; fe is refused"
                        " with rigid bodies)")
    parser.add_argument("--rest", type=positive_float,
                        help="fit the rows at rest only: kinetic energy <="
                        " REST x strain energy (default: 1e-3 with loading"
                        " stages, every row without)")
    parser.add_argument("--stage", type=int, metavar="K",
                        help="the stage (index, as raw/steps.csv's stage"
                        " column) of the shear figure (default: the last)")
    parser.add_argument("--unchecked", action="store_true",
                        help="also law_unchecked.png: the law fitted with"
                        " its refusals switched off, for illustration only")
    args = parser.parse_args(argv)
    run = Path(args.run)
    if not RunDirectory(run).raw.steps_csv.is_file():
        parser.error(f"{run}: no raw/steps.csv (not a run directory)")
    out = Path(args.out) if args.out else run / "figures" / "loading"
    try:
        summary = write_figures(run, out, args.estimate, args.rest,
                                args.stage, args.unchecked)
    except RunError as err:
        print(f"softpack plot-loading: {err}", file=sys.stderr)
        return 2
    fit = summary["fit"]
    line = (compaction_law.CompactionFit(
        fit["values"], fit["errors"], fit["reason"], fit["method"],
        fit["points"], fit["pressure_max"]).summary())
    print(f"{run}: {line}")
    print(f"figures in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
