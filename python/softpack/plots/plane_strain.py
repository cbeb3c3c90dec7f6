"""``./softpack plot-plane-strain LABEL=RUN... --out FIGDIR``: the
plane-strain model of a compaction against the standing cylinders it
models (issue 40, item 4), at the assembly level.

Each RUN is a run directory of ``./softpack run`` (2D or 3D; its
``series.csv`` and ``raw/setup.json``) or a per-seed CSV of
``docs/paper/seeds`` (``./softpack plot --export-seeds``; its constants
from ``runs.csv`` beside it). The first RUN is the reference of the
ratios. Per run, on the rows of its output:

Phi
    2D: ``phi`` (the disks' area over the box's); 3D: ``phi_base``, the
    bottom faces' area over the box's plan (what the experiment's scanner
    saw).
F / H, E / H
    the piston's force and the strain energy per unit height (N/m, J/m), H
    the model's thickness (2D) or the cylinders' height (3D): the same
    division in both dimensions.
Z (retained)
    2D: ``z``; 3D: ``z_without_base`` (the base and lid are out of the 2D
    model's plane), both under the same exclusion rule
    (docs/paper/exclusion_rule.md), with the particles Z counts.

The Phi of a run is its mesh's: the polygons (2D) and faces (3D)
inscribed in the circles lose area as the elements grow (100 disks at
Phi0 0.748: 0.7467 at 1.065 mm, 0.7338 at 4 mm), so runs on different
meshes are compared at equal piston travel eps as well.

It writes ``plane_strain.png`` / ``.pdf`` (Phi, F/H, E against eps; F/H,
E, Z against Phi) and ``plane_strain.md`` (tables at ``--phi`` and at
``--eps``: force, energy and the other abscissa interpolated linearly
between output rows, Z of the first row at or above), and prints them.
For 3D runs with fields, also the cylinders' axial strain eps_zz (which
plane strain holds at 0) and their lift off the base
(:mod:`softpack.analysis.standing`) at each stored field against Phi:
``axial_strain.png`` / ``.pdf`` and a table.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis.setup import SetupError, read_setup
from softpack.analysis.standing import standing
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.plots import style

#: Packing fractions of the table.
TABLE_PHIS = (0.76, 0.78, 0.80, 0.82, 0.84, 0.86, 0.88)
#: Strains of the table at equal piston travel.
TABLE_EPS = (0.05, 0.10, 0.15, 0.20)


class PlaneStrainError(ValueError):
    """A RUN argument that cannot be read."""


@dataclass(frozen=True)
class Curve:
    """One run's rows: Phi, eps, F/H (N/m), E/H (J/m), Z, retained."""

    label: str
    dimension: int
    phi: np.ndarray
    eps: np.ndarray
    force: np.ndarray
    energy: np.ndarray
    z: np.ndarray
    retained: np.ndarray
    #: A 3D run with fields: Phi at each stored field and the cylinders'
    #: axial strains and lifts there (:class:`..standing.Standing`).
    axial: tuple | None = None


def read_curve(label: str, path) -> Curve:
    """A run directory's or a per-seed CSV's curve (see the module doc)."""
    path = Path(path)
    if path.is_dir():
        return _run_curve(label, path)
    if path.suffix == ".csv" and path.is_file():
        return _seed_curve(label, path)
    raise PlaneStrainError(f"{path}: neither a run directory nor a per-seed"
                           " CSV of docs/paper/seeds")


def _run_curve(label, run_dir) -> Curve:
    try:
        s = read_table(run_dir / "series.csv")
        setup = read_setup(run_dir)
    except (OSError, SetupError) as err:
        raise PlaneStrainError(
            f"{run_dir}: {err} (./softpack run --observables-only --out"
            f" {run_dir} writes series.csv)") from None
    three = setup.dimension == 3
    phi = s["phi_base"] if three else s["phi"]
    axial = None
    fields_h5 = RunDirectory(run_dir).fields_h5
    if three and fields_h5.is_file():
        st = standing(fields_h5)
        axial = (np.interp(st.times, s["time"], phi), st)
    return Curve(label, setup.dimension, phi, s["eps"],
                 s["piston_force"] / setup.thickness,
                 s["strain_energy"] / setup.thickness,
                 s["z_without_base"] if three else s["z"],
                 s["retained_without_base"] if three else s["retained"],
                 axial)


def _seed_curve(label, csv_path) -> Curve:
    index = csv_path.parent / "runs.csv"
    try:
        with open(index) as f:
            rows = {r["name"]: r for r in csv.DictReader(f)}
        run = rows[csv_path.stem]
    except (OSError, KeyError):
        raise PlaneStrainError(f"{csv_path}: no row {csv_path.stem!r} in"
                               f" {index}") from None
    s = read_table(csv_path)
    thickness = float(run["thickness"])
    return Curve(label, 2, s["phi"], s["eps"],
                 s["piston_force"] / thickness, s["E_J"] / thickness,
                 s["z"], s["retained"])


def interpolated(curve: Curve, values, axis: str, at: float) -> float:
    """``values`` where ``axis`` (``"phi"`` or ``"eps"``) first reaches
    ``at``, linear between rows; NaN outside the run's range."""
    x = getattr(curve, axis)
    k = first_row(curve, axis, at)
    if k is None or at < x[0]:
        return math.nan
    if k == 0:
        return float(values[0])
    w = (at - x[k - 1]) / (x[k] - x[k - 1])
    return float(values[k - 1] + w * (values[k] - values[k - 1]))


def first_row(curve: Curve, axis: str, at: float):
    """The index of the first row whose ``axis`` is at or above ``at``
    (None beyond the run)."""
    above = np.flatnonzero(getattr(curve, axis) >= at)
    return int(above[0]) if len(above) else None


def table(curves, axis: str, values) -> list[str]:
    """Markdown rows at each of ``values`` of ``axis`` (``"phi"`` or
    ``"eps"``): the other of the two, F/H, E/H and Z per run, and
    each run's F and E over the first run's."""
    ref, other = curves[0], {"phi": "eps", "eps": "phi"}[axis]
    head = [{"phi": "Phi", "eps": "eps"}[axis]]
    for c in curves:
        head += [f"{other.replace('phi', 'Phi')} {c.label}",
                 f"F/H {c.label} (N/m)", f"E/H {c.label} (J/m)",
                 f"Z {c.label} (retained)"]
    for c in curves[1:]:
        head += [f"F {c.label} / {ref.label}", f"E {c.label} / {ref.label}"]
    lines = ["| " + " | ".join(head) + " |",
             "|" + " ---: |" * len(head)]
    for at in values:
        cells = [f"{at:.3g}"]
        for c in curves:
            k = first_row(c, axis, at)
            z = "-" if k is None else f"{c.z[k]:.2f} ({c.retained[k]:.0f})"
            cells += [f"{interpolated(c, getattr(c, other), axis, at):.4f}",
                      f"{interpolated(c, c.force, axis, at):.4g}",
                      f"{interpolated(c, c.energy, axis, at):.4g}", z]
        for c in curves[1:]:
            for name in ("force", "energy"):
                a = interpolated(c, getattr(c, name), axis, at)
                b = interpolated(ref, getattr(ref, name), axis, at)
                cells.append(f"{a / b:.3f}" if b > 0 else "-")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def figure(curves, out) -> list:
    """Six panels: Phi, F/H and E against eps (the piston's travel, which
    the mesh does not change), F/H, E and Z against Phi."""
    import matplotlib.pyplot as plt

    with style.context():
        fig, axes = plt.subplots(2, 3, figsize=(style.DOUBLE_COLUMN, 4.4),
                                 constrained_layout=True)
        for curve in curves:
            kw = {"label": curve.label,
                  "ls": "-" if curve.dimension == 2 else "--"}
            force = np.where(curve.force > 0, curve.force, np.nan)
            energy = np.where(curve.energy > 0, curve.energy, np.nan)
            axes[0, 0].plot(curve.eps, curve.phi, **kw)
            axes[0, 1].semilogy(curve.eps, force, **kw)
            axes[0, 2].semilogy(curve.eps, energy, **kw)
            axes[1, 0].semilogy(curve.phi, force, **kw)
            axes[1, 1].semilogy(curve.phi, energy, **kw)
            axes[1, 2].plot(curve.phi, curve.z, **kw)
        eps, phi = r"$\varepsilon$", r"$\Phi$"
        force, energy = r"$F/H$ (N/m)", r"$E/H$ (J/m)"
        for ax, (x, y) in zip(axes.flat, [(eps, phi), (eps, force),
                                          (eps, energy), (phi, force),
                                          (phi, energy), (phi, r"$Z$")]):
            ax.set(xlabel=x, ylabel=y)
        for ax, tag in zip(axes.flat, "abcdef"):
            ax.set_title(f"({tag})", loc="left")
        axes[0, 0].legend(frameon=False)
        return style.save(fig, Path(out) / "plane_strain.png")


def axial_figure(curves, out) -> list:
    """The cylinders' axial strain against Phi (mean, and the band from
    the least to the most stretched) of the 3D runs with fields."""
    import matplotlib.pyplot as plt

    with style.context():
        fig, ax = plt.subplots(figsize=(style.SINGLE_COLUMN, 2.4),
                               constrained_layout=True)
        for curve in curves:
            if curve.axial is None:
                continue
            phi, st = curve.axial
            strains = st.axial
            line, = ax.plot(phi, strains.mean(axis=1), "o-", ms=2.5,
                            label=f"{curve.label}: mean")
            ax.fill_between(phi, strains.min(axis=1), strains.max(axis=1),
                            color=line.get_color(), alpha=0.2, lw=0,
                            label=f"{curve.label}: min to max")
        ax.axhline(0, color="k", lw=0.6, label="plane strain")
        ax.set(xlabel=r"$\Phi$",
               ylabel=r"$\varepsilon_{zz} = \ln(h / H)$")
        ax.legend(frameon=False)
        return style.save(fig, Path(out) / "axial_strain.png")


def axial_table(curves) -> list[str]:
    """Markdown rows of each 3D run's axial strain and lift at its stored
    fields."""
    lines = ["| run | Phi | eps_zz mean | min | max | lifted > 0.1 mm |"
             " max lift (mm) |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for curve in curves:
        if curve.axial is not None:
            phi, st = curve.axial
            for k in range(len(phi)):
                e, lift = st.axial[k], st.lift[k]
                lines.append(
                    f"| {curve.label} | {phi[k]:.4f} | {e.mean():.4f} |"
                    f" {e.min():.4f} | {e.max():.4f} |"
                    f" {int(np.sum(lift > 1e-4))} | {1e3 * lift.max():.2f} |")
    return lines


def _parser():
    p = argparse.ArgumentParser(
        prog="softpack plot-plane-strain",
        description="Plane-strain 2D runs against 3D runs of standing"
        " cylinders: Phi, F/H and E against eps; F/H, E and Z against Phi;"
        " tables at both.")
    p.add_argument("runs", nargs="+", metavar="LABEL=RUN",
                   help="a label and a run directory or a per-seed CSV of"
                   " docs/paper/seeds; the first is the ratios' reference")
    p.add_argument("--out", type=Path, required=True, metavar="FIGDIR")
    p.add_argument("--phi", type=float, nargs="+", default=list(TABLE_PHIS),
                   help="the Phi table's packing fractions")
    p.add_argument("--eps", type=float, nargs="+", default=list(TABLE_EPS),
                   help="the eps table's strains")
    return p


def write_outputs(runs, out, phis=TABLE_PHIS, eps=TABLE_EPS) -> list[str]:
    """The figure and tables of ``runs`` (``(label, path)`` pairs, the
    first the reference) in ``out``; returns ``plane_strain.md``'s lines.
    Raises :class:`PlaneStrainError` for a run it cannot read."""
    curves = [read_curve(label, path) for label, path in runs]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    lines = ["At equal Phi:", "", *table(curves, "phi", phis), "",
             "At equal eps:", "", *table(curves, "eps", eps), "",
             "Initial Phi: " + ", ".join(f"{c.label} {c.phi[0]:.4f}"
                                          for c in curves)]
    figure(curves, out)
    if any(c.axial is not None for c in curves):
        lines += ["", "The cylinders' axial strain at the stored fields:",
                  "", *axial_table(curves)]
        axial_figure(curves, out)
    (out / "plane_strain.md").write_text("\n".join(lines) + "\n")
    return lines


def main(argv=None) -> int:
    """Entry point of ``./softpack plot-plane-strain``."""
    import matplotlib
    matplotlib.use("Agg")

    parser = _parser()
    args = parser.parse_args(argv)
    pairs = [text.split("=", 1) for text in args.runs]
    if any(len(pair) != 2 or not all(pair) for pair in pairs):
        parser.error("each RUN is LABEL=PATH")
    try:
        lines = write_outputs(pairs, args.out, args.phi, args.eps)
    except PlaneStrainError as err:
        print(f"softpack plot-plane-strain: {err}", file=sys.stderr)
        return 2
    print("\n".join(lines))
    print(f"softpack plot-plane-strain: wrote {args.out}/plane_strain.png,"
          " .pdf, .md")
    return 0
