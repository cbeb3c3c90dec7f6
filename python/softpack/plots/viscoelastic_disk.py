"""The viscoelastic disk check's figure and table (docs/materials.md).

``python -m softpack.plots.viscoelastic_disk RUN... --out DIR`` reads each
run's ``cycle.csv`` and ``viscoelastic_disk.json`` (written by
``./softpack viscoelastic-disk --out RUN``) and writes

``DIR/viscoelastic_disk.csv``
    one row per run: the plates' speed, the mesh, the step, the peak force
    of both computations, the largest force difference over the cycle (of
    the peak), the dissipated energy of both, the driver's energy residual;
``DIR/cycle.png`` (and ``.pdf``)
    left: the plates' force against their approach over the cycle,
    softpack (lines) and dolfinx (dashed); right: the dissipated energy
    against time, softpack's `viscous` account and dolfinx's plate work
    less its stored energy.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from softpack.contract.tables import write_rows

COLUMNS = ("run", "speed_m_s", "max_strain", "element_size_m", "triangles",
           "time_step_s", "peak_f_norm_softpack", "peak_f_norm_dolfinx",
           "at_peak_relative_difference", "max_abs_difference_over_peak",
           "viscous_softpack_J_m", "dissipated_dolfinx_J_m",
           "viscous_relative_difference", "energy_residual_over_work")


def row(name, doc) -> dict:
    """The table's row of one run."""
    p, f, e = doc["params"], doc["force"], doc["energy"]
    s = e["softpack"]
    return {"run": name, "speed_m_s": p["speed"],
            "max_strain": p["max_strain"],
            "element_size_m": p["element_size"],
            "triangles": doc["mesh"]["triangles"],
            "time_step_s": p["time_step"],
            "peak_f_norm_softpack": f["peak_f_norm_softpack"],
            "peak_f_norm_dolfinx": f["peak_f_norm_dolfinx"],
            "at_peak_relative_difference": f["at_peak_relative_difference"],
            "max_abs_difference_over_peak": f["max_abs_difference_over_peak"],
            "viscous_softpack_J_m": s["viscous"],
            "dissipated_dolfinx_J_m": e["dolfinx"]["dissipated"],
            "viscous_relative_difference": e["viscous_relative_difference"],
            "energy_residual_over_work": abs(s["energy_residual"])
            / s["wall_work"]}


def figure(runs, path) -> None:
    """Force loops and dissipation (module doc)."""
    import matplotlib.pyplot as plt

    from softpack.plots import style

    with style.context():
        fig, (left, right) = plt.subplots(
            1, 2, figsize=(style.DOUBLE_COLUMN, 2.6),
            gridspec_kw={"wspace": 0.3})
        for k, (name, doc, cycle) in enumerate(runs):
            colour = f"C{k}"
            label = f"{doc['params']['speed']:g} m/s"
            d = doc["params"]["diameter"]
            ref = np.isfinite(cycle["f_norm_dolfinx"])
            left.plot(cycle["delta"] / d, cycle["f_norm_softpack"], "-",
                      color=colour, lw=1.0, label=f"softpack, {label}")
            left.plot(cycle["delta"][ref] / d, cycle["f_norm_dolfinx"][ref],
                      "--", color="k", lw=0.7,
                      label="dolfinx" if k == 0 else None)
            t = cycle["time"] / cycle["time"][-1]
            right.plot(t, cycle["viscous_softpack"], "-", color=colour,
                       lw=1.0, label=f"softpack viscous, {label}")
            right.plot(t[ref], cycle["dissipated_dolfinx"][ref], "--",
                       color="k", lw=0.7,
                       label="dolfinx work - stored" if k == 0 else None)
        left.set_xlabel(r"plates' approach $\delta / D$")
        left.set_ylabel(r"force $f / (D \mu)$")
        left.legend(frameon=False)
        right.set_xlabel(r"time / cycle time")
        right.set_ylabel("dissipated energy (J/m)")
        right.legend(frameon=False)
        style.save(fig, path)


def main(argv=None) -> int:
    from softpack.contract.tables import read_table

    parser = argparse.ArgumentParser(
        prog="python -m softpack.plots.viscoelastic_disk",
        description="Table and figure of ./softpack viscoelastic-disk runs.")
    parser.add_argument("runs", nargs="+", type=Path,
                        help="run directories (each with cycle.csv and"
                        " viscoelastic_disk.json)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    runs = []
    for run in args.runs:
        paths = [run / "viscoelastic_disk.json", run / "cycle.csv"]
        missing = [p for p in paths if not p.is_file()]
        if missing:
            print(f"{missing[0]}: missing (run ./softpack viscoelastic-disk"
                  f" --out {run})", file=sys.stderr)
            return 2
        runs.append((run.name, json.loads(paths[0].read_text()),
                     read_table(paths[1])))
    args.out.mkdir(parents=True, exist_ok=True)
    write_rows(args.out / "viscoelastic_disk.csv",
               [row(n, d) for n, d, _ in runs], COLUMNS)
    figure(runs, args.out / "cycle.png")
    print(f"wrote {args.out}/viscoelastic_disk.csv, cycle.png/.pdf")
    return 0


if __name__ == "__main__":
    sys.exit(main())
