"""docs/paper's numbers and figures from small per-seed CSV files.

``./softpack plot --export-seeds SEEDDIR DIR...`` writes, for each run
directory DIR (a complete run with ``raw/contacts``), ``SEEDDIR/NAME.csv``
(NAME = the directory's name) with the series columns the paper needs
(:data:`SERIES`) and Z under every reading of the unbalanced-particle
exclusion (:data:`READINGS` x :data:`THRESHOLDS`, and without exclusion),
and adds the run's constants to ``SEEDDIR/runs.csv``.

``./softpack plot --seeds SEEDDIR --out FIGDIR`` then regenerates, from
those files only: Figs. 4, 6, 8, 9 (Phi0 groups averaged over seeds),
``fig8_fit.txt``, ``summary.md`` (Phi_T, where Z leaves 3, E and c_v at
Phi 0.80, 0.84, 0.88, mean and spread over seeds) and ``exclusion_table.md`` (max |dZ| between
f_p* = 0.05 % and 0.1 % under each reading). Runs are grouped by their
nominal initial packing fraction (``phi0`` of ``runs.csv``: the disks'
area over the initial box, rounded to 3 digits), their element size and
their preparation (``protocol``: the stages that compact with a friction
other than the run's, e.g. ``mu_f 1 to Phi 0.78``; empty without).

E is given in J (``E_J``) and normalised in the summary with the paper's
set-up, L = 286 mm (:data:`PAPER_LENGTH`), for every group: a run started
at Phi0 = 0.78 has a shorter initial box, whose own E/(W H L mu) would be
4.3 % larger for the same energy.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np

from softpack.analysis import connectivity as net_
from softpack.analysis import fits
from softpack.analysis.observables import piston_force
from softpack.analysis.setup import read_rules, read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table

#: series.csv columns kept per seed.
SERIES = ("step", "time", "eps", "phi", "E_over_WHLmu", "cv_psi", "z",
          "z_without_walls", "z_undefined", "retained", "rattlers",
          "unbalanced", "piston_force")
#: Readings of the exclusion rule: (unbalanced_reference, excluded_contacts).
READINGS = tuple((r, e) for r in net_.REFERENCES
                 for e in net_.EXCLUDED_CONTACTS)
#: The paper's f_p* range (Sec. VI).
THRESHOLDS = (5e-4, 1e-3)
#: The paper's set-up length, the L of E/(W H L mu) in the summary (m).
PAPER_LENGTH = 0.286
#: Packing fractions of the summary table.
SUMMARY_PHIS = (0.80, 0.84, 0.88)
RUN_COLUMNS = ("name", "seed", "phi0", "length", "width", "thickness",
               "shear_modulus", "friction", "element_size", "protocol")
#: The numeric columns of runs.csv (after the name).
NUMERIC = RUN_COLUMNS[1:-1]


def reading_column(reference, excluded, threshold) -> str:
    """``z_piston_dropped_0.001``-like column name of a reading."""
    return f"z_{reference.split('_')[0]}_{excluded}_{threshold:g}"


def unbalanced_column(reference, threshold) -> str:
    return f"unbalanced_{reference.split('_')[0]}_{threshold:g}"


def seed_columns(run_dir) -> dict:
    """The per-seed columns of one run (see the module doc)."""
    run = RunDirectory(run_dir)
    series = read_table(run.series_csv)
    steps = read_table(run.raw.steps_csv)
    setup, rules = read_setup(run_dir), read_rules(run_dir)
    force = piston_force(steps, setup)
    out = {name: series[name] for name in SERIES if name in series}
    out["E_J"] = series["strain_energy"]
    names = [reading_column(r, e, t) for (r, e) in READINGS
             for t in THRESHOLDS]
    extra = {name: np.full(len(series["step"]), np.nan) for name in
             [*names, "z_no_exclusion",
              *(unbalanced_column(r, t) for r in net_.REFERENCES
                for t in THRESHOLDS)]}
    weight = setup.body_weight
    for k, step in enumerate(steps["step"]):
        path = run.raw.contact_file(step)
        if not path.is_file():
            continue
        contacts = net_.read_contacts(path)
        for (reference, excluded) in READINGS:
            for threshold in THRESHOLDS:
                net = net_.contact_network(
                    contacts, setup.count, force[k], dataclasses.replace(
                        rules, unbalanced_threshold=threshold,
                        unbalanced_reference=reference,
                        excluded_contacts=excluded), weight)
                extra[reading_column(reference, excluded, threshold)][k] = \
                    net.z
                extra[unbalanced_column(reference, threshold)][k] = \
                    net.unbalanced.sum()
        extra["z_no_exclusion"][k] = net_.contact_network(
            contacts, setup.count, force[k], dataclasses.replace(
                rules, unbalanced_threshold=np.inf), weight).z
    out.update(extra)
    return out, setup


def export_seeds(run_dirs, seed_dir) -> list[Path]:
    """Write ``SEEDDIR/NAME.csv`` per run and update ``SEEDDIR/runs.csv``."""
    seed_dir = Path(seed_dir)
    seed_dir.mkdir(parents=True, exist_ok=True)
    index = seed_dir / "runs.csv"
    rows = _read_index(index)
    written = []
    for run_dir in map(Path, run_dirs):
        columns, setup = seed_columns(run_dir)
        written.append(write_table(seed_dir / f"{run_dir.name}.csv",
                                   _rounded(columns)))
        # the nominal Phi0 (disk areas over the box): the mesh's polygons
        # are 0.14 % smaller, so series.csv's first phi is a little lower
        phi0 = float(np.sum(np.pi * setup.radii**2)
                     / (setup.length * setup.width))
        rows[run_dir.name] = ([setup.seed, phi0,
                               setup.length, setup.width, setup.thickness,
                               setup.shear_modulus, setup.friction,
                               setup.element_size], protocol(setup))
    lines = [",".join(RUN_COLUMNS)] + [
        ",".join([name, *(repr(v) for v in values), label])
        for name, (values, label) in sorted(rows.items())]
    index.write_text("\n".join(lines) + "\n")
    return written


def protocol(setup) -> str:
    """The run's preparation: each stage that compacts to a Phi with a
    friction other than the run's (``mu_f 1 to Phi 0.78``; ``; `` between
    two), or ``""``."""
    return "; ".join(f"mu_f {mu:g} to Phi {phi:g}" for mu, phi in
                     zip(setup.stage_frictions, setup.stage_phis)
                     if mu != setup.friction and phi > 0)


def _read_index(path) -> dict:
    """``name -> (numbers, protocol)``; an index written before a column
    existed reads element_size as the paper's mesh and no protocol."""
    if not path.is_file():
        return {}
    out = {}
    for line in path.read_text().splitlines()[1:]:
        if not line:
            continue
        f = line.split(",")
        values = [float(v) for v in f[1:1 + len(NUMERIC)]]
        values += [default_element_size()] * (len(NUMERIC) - len(values))
        out[f[0]] = (values, f[1 + len(NUMERIC)] if len(f) > 1 + len(NUMERIC)
                     else "")
    return out


def _rounded(columns) -> dict:
    """Seven significant digits: the files stay small."""
    return {k: np.array([float(f"{v:.7g}") for v in np.asarray(c, float)])
            for k, c in columns.items()}


@dataclasses.dataclass(frozen=True)
class Seed:
    """One seed's CSV and its constants."""

    name: str
    seed: int
    phi0: float
    length: float
    width: float
    thickness: float
    shear_modulus: float
    series: dict
    element_size: float = float("nan")

    def at(self, column, phi) -> float:
        """``column`` where Phi first reaches ``phi`` (linear between rows);
        NaN when it never does."""
        p, y = self.series["phi"], self.series[column]
        above = np.flatnonzero(p >= phi)
        if not len(above) or above[0] == 0:
            return float("nan")
        k = above[0]
        w = (phi - p[k - 1]) / (p[k] - p[k - 1])
        return float(y[k - 1] + w * (y[k] - y[k - 1]))


def load_seeds(seed_dir) -> dict:
    """``{group label: [Seed, ...]}`` from ``SEEDDIR/runs.csv``: runs are
    grouped by Phi0 and element size (:func:`group_label`); an index
    written before ``element_size`` was a column holds runs at the schema's
    default size."""
    seed_dir = Path(seed_dir)
    groups = {}
    for name, (values, prepared) in _read_index(seed_dir
                                                / "runs.csv").items():
        seed, phi0, length, width, thickness, mu, _, h = values
        series = read_table(seed_dir / f"{name}.csv")
        s = Seed(name, int(seed), phi0, length, width, thickness, mu, series,
                 h)
        groups.setdefault(group_label(phi0, h, prepared), []).append(s)
    return {k: sorted(v, key=lambda s: s.seed)
            for k, v in sorted(groups.items())}


def default_element_size() -> float:
    """``[mesh] element_size``'s default: the paper's mesh (m)."""
    from softpack.contract.schema import load_schema

    return float(load_schema()["mesh"].parameters["element_size"].default)


def group_label(phi0, element_size, prepared="") -> str:
    """``0.748``, ``0.748, h = 0.753 mm`` off the paper's mesh (an unknown
    size, NaN, is not marked), ``0.748, prepared: mu_f 1 to Phi 0.78``."""
    label = f"{phi0:.3f}"
    if np.isfinite(element_size) and not np.isclose(
            element_size, default_element_size(), rtol=1e-6):
        label += f", h = {element_size * 1e3:.3g} mm"
    return label + (f", prepared: {prepared}" if prepared else "")


def energy(seed, phi) -> float:
    """E / (W H L mu) at ``phi`` with L = :data:`PAPER_LENGTH`."""
    return seed.at("E_J", phi) / (seed.width * seed.thickness
                                  * PAPER_LENGTH * seed.shear_modulus)


def _spread(values) -> str:
    v = np.array([x for x in values if np.isfinite(x)])
    if not len(v):
        return "n/a"
    if len(v) == 1:
        return f"{v[0]:.3g} (1 seed)"
    return f"{v.mean():.3g} +- {v.std(ddof=1):.2g}"


def summary(groups) -> list[str]:
    """The summary table (markdown lines): Phi_T of Eq. 14 with the default
    rules (``z``) and without the exclusion, where Z first leaves Z_T
    (:func:`~softpack.analysis.fits.rigidity_onset`), Z at Phi = 0.88, E
    and c_v at :data:`SUMMARY_PHIS`, mean +- std over seeds."""
    head = ["| Phi0 | seeds | Phi_T (Eq. 14) | Phi_T, no exclusion |"
            " Z > 3 from | Z at 0.88 |"
            + "".join(f" E/(WHLmu) at {p:.2f} |" for p in SUMMARY_PHIS)
            + "".join(f" c_v at {p:.2f} |" for p in SUMMARY_PHIS),
            "|" + " --- |" * (6 + 2 * len(SUMMARY_PHIS))]
    rows = []
    for label, seeds in groups.items():
        rows.append(
            f"| {label} | {', '.join(str(s.seed) for s in seeds)} |"
            f" {_fit_text(seeds, 'z')} |"
            f" {_fit_text(seeds, 'z_no_exclusion')} |"
            f" {_onset_text(seeds)} |"
            f" {_spread([s.at('z', 0.88 - 1e-9) for s in seeds])} |"
            + "".join(f" {_spread([energy(s, p) for s in seeds])} |"
                      for p in SUMMARY_PHIS)
            + "".join(f" {_spread([s.at('cv_psi', p) for s in seeds])} |"
                      for p in SUMMARY_PHIS))
    return head + rows


def exclusion_table(groups, ranges=((0.80, 0.88), (0.82, 0.88))
                    ) -> list[str]:
    """max |Z(0.05 %) - Z(0.1 %)| per reading (markdown lines): per seed
    over each Phi range, the mean over the first range, the mean number of
    unbalanced particles at 0.1 % and the Eq. 14 fit at 0.1 %."""
    lines = ["| Phi0 | f | excluded particles' contacts |"
             + "".join(f" max abs(dZ), Phi {lo:.2f}-{hi:.2f} (per seed) |"
                       for lo, hi in ranges)
             + f" mean abs(dZ), Phi {ranges[0][0]:.2f}-{ranges[0][1]:.2f} |"
             " unbalanced at 0.1 % (mean over seeds, Phi 0.80 / 0.84 /"
             " 0.88) | Phi_T (Eq. 14) at 0.1 % |",
             "|" + " --- |" * (6 + len(ranges))]
    for label, seeds in groups.items():
        for reference, excluded in READINGS:
            a, b = (reading_column(reference, excluded, t)
                    for t in THRESHOLDS)
            changes = []
            for r in ranges:
                values = [net_.z_change(s.series["phi"], s.series[a],
                                        s.series[b], r) for s in seeds]
                changes.append(f" {', '.join(f'{v:.2f}' for v in values)} |")
            means = []
            for s in seeds:
                p = s.series["phi"]
                keep = (p >= ranges[0][0]) & (p <= ranges[0][1]) \
                    & np.isfinite(s.series[a]) & np.isfinite(s.series[b])
                means.append(float(np.mean(np.abs(
                    s.series[a][keep] - s.series[b][keep])))
                    if keep.any() else np.nan)
            count = unbalanced_column(reference, THRESHOLDS[-1])
            excluded_n = " / ".join(
                f"{np.nanmean([s.at(count, p) for s in seeds]):.0f}"
                for p in SUMMARY_PHIS)
            lines.append(
                f"| {label} | {reference} | {excluded} |{''.join(changes)}"
                f" {np.nanmean(means):.3f} | {excluded_n} |"
                f" {_fit_text(seeds, b)} |")
        lines.append(f"| {label} | (no exclusion) | |" + " |" * len(ranges)
                     + f" | 0 / 0 / 0 | {_fit_text(seeds, 'z_no_exclusion')} |")
    return lines


def _onset_text(seeds) -> str:
    """Mean +- std over seeds of the Phi where Z first leaves Z_T."""
    v = np.array([fits.rigidity_onset(s.series["phi"], s.series["z"])
                  for s in seeds])
    v = v[np.isfinite(v)]
    if not len(v):
        return "n/a"
    if len(v) == 1:
        return f"{v[0]:.4f} (1 seed)"
    return f"{v.mean():.4f} +- {v.std(ddof=1):.4f}"


def _fit_text(seeds, column) -> str:
    """Phi_T +- spread of the Eq. 14 fit of a Z column over the seeds (for
    one seed, +- its block bootstrap: marked "(1 seed)")."""
    fit = fits.fit_runs([(s.series["phi"], s.series[column]) for s in seeds])
    if not fit.ok:
        return "no fit"
    one = " (1 seed)" if len(seeds) == 1 else ""
    return f"{fit.phi_t:.3f} +- {fit.error:.3f}{one}"


def regenerate(seed_dir, out) -> list[Path]:
    """Every figure and table of docs/paper that the seeds give."""
    from softpack.plots import curves

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    groups = load_seeds(seed_dir)
    if not groups:
        raise FileNotFoundError(f"{seed_dir}/runs.csv: no seeds")
    runs = {f"Phi0 = {label}": [curves.Run(Path(s.name), 0.3, s.seed,
                                          s.shear_modulus, s.length,
                                          s.width, s.series) for s in seeds]
            for label, seeds in groups.items()}
    written = [
        curves.plot_curves(runs, "eps", "phi",
                           r"$\varepsilon = -\ln(1 - \delta / L_0)$",
                           r"$\Phi$", out / "fig4_phi_eps.png"),
        curves.plot_curves(runs, "phi", "E_over_WHLmu", r"$\Phi$",
                           r"$E/(WHL_0\mu)$", out / "fig6_energy.png"),
        curves.plot_curves(runs, "phi", "cv_psi", r"$\Phi$",
                           r"$c_v(\Psi_p)$", out / "fig9_cv_psi.png")]
    fit = curves.plot_connectivity(runs, out / "fig8_connectivity.png")
    written.append(out / "fig8_connectivity.png")
    (out / "fig8_fit.txt").write_text("\n".join(fit) + "\n")
    written.append(_write(out / "summary.md", [
        "<!-- generated by ./softpack plot --seeds; do not edit -->",
        *summary(groups)]))
    written.append(_write(out / "exclusion_table.md", [
        "<!-- generated by ./softpack plot --seeds; do not edit -->",
        *exclusion_table(groups)]))
    return written


def _write(path, lines) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


def main_seeds(args) -> int:
    """``--export-seeds`` / ``--seeds`` of ``./softpack plot``."""
    if args.export_seeds:
        for path in export_seeds(args.runs, args.export_seeds):
            print(f"softpack plot: wrote {path}")
        return 0
    try:
        written = regenerate(args.seeds, args.out or args.seeds)
    except FileNotFoundError as err:
        print(f"softpack plot: {err}", file=sys.stderr)
        return 1
    print("softpack plot: wrote " + ", ".join(map(str, written)))
    return 0
