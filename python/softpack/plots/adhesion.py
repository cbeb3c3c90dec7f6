"""The adhesion check's table and figure (docs/adhesion/README.md).

``python -m softpack.plots.adhesion RUN... --out DIR`` reads each run's
``result.json`` (written by ``./softpack adhesion --out RUN``) and writes

``DIR/adhesion.csv``
    one row per run: the mesh (h_fine, triangles, boundary spacing at the
    contact), the loading (speed, time step), the measured pull-off force,
    zero-load half-width a_0 and zone edge c_0, each with its relative
    difference from the Maugis–Dugdale line contact, the energy residual;
``DIR/force_width.png`` (and ``.pdf``)
    P against a: the Maugis–Dugdale and JKR curves of the finest run's
    parameters, the measured (P, a) of the pull stage of every run at the
    finest run's speed and time step.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from softpack.contract.tables import write_rows

COLUMNS = ("run", "h_fine_m", "triangles", "spacing_m", "speed_m_s",
           "time_step_s", "pull_off_N_m", "pull_off_md_N_m", "pull_off_err",
           "a0_m", "a0_md_m", "a0_err", "c0_m", "c0_md_m", "c0_err",
           "a_pull_off_m", "a_pull_off_md_m", "residual_over_work")


def row(name, result) -> dict:
    """The table's row of one run."""
    p, t = result["params"], result["theory"]
    b = result["balance"]
    return {
        "run": name, "h_fine_m": p["h_fine"],
        "triangles": result["mesh"]["triangles"],
        "spacing_m": result["boundary_spacing_at_contact"],
        "speed_m_s": p["speed"], "time_step_s": p["time_step"],
        "pull_off_N_m": result["pull_off"],
        "pull_off_md_N_m": t["md_pull_off"],
        "pull_off_err": result["pull_off"] / t["md_pull_off"] - 1,
        "a0_m": result["a0"], "a0_md_m": t["md_a0"],
        "a0_err": result["a0"] / t["md_a0"] - 1,
        "c0_m": result["c0"], "c0_md_m": t["md_c0"],
        "c0_err": result["c0"] / t["md_c0"] - 1,
        "a_pull_off_m": result["a_pull_off"],
        "a_pull_off_md_m": t["md_a_pull_off"],
        "residual_over_work": b["max_abs_residual"] / b["max_abs_wall_work"]}


def figure(results, path) -> None:
    """P(a): theory curves and the measured points."""
    import matplotlib.pyplot as plt

    from softpack.plots import style
    from softpack.references.adhesion_theory import LineContact

    finest = min(results, key=lambda nr: nr[1]["params"]["h_fine"])[1]
    p, t = finest["params"], finest["theory"]
    theory = LineContact(finest["radius_fitted"], t["E_star"],
                         p["cohesion"], p["cohesive_distance"])
    a = np.linspace(0.05, 1.6, 120) * t["md_a0"]
    with style.context():
        fig, ax = plt.subplots(figsize=(style.SINGLE_COLUMN, 2.6))
        ax.plot(a * 1e3, [theory.md_load(x) for x in a], "k-",
                label=f"Maugis–Dugdale ($\\lambda$ = {t['lambda']:.2f})")
        ax.plot(a * 1e3, [theory.jkr_load(x) for x in a], "k--",
                label="JKR")
        same = [(n, r) for n, r in results
                if r["params"]["speed"] == p["speed"]
                and r["params"]["time_step"] == p["time_step"]]
        for name, result in sorted(same,
                                   key=lambda nr: -nr[1]["params"]["h_fine"]):
            pts = np.array(result["curve"])
            keep = pts[:, 1] > 0
            ax.plot(pts[keep, 1] * 1e3, pts[keep, 0], ".", ms=2.5,
                    label=f"softpack, h = {result['params']['h_fine'] * 1e6:g}"
                    " µm")
        ax.axhline(0.0, color="0.7", lw=0.5)
        ax.set_xlabel("contact half-width a (mm)")
        ax.set_ylabel("load P (N/m, compressive > 0)")
        ax.legend(frameon=False)
        style.save(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m softpack.plots.adhesion",
        description="Table and figure of ./softpack adhesion runs.")
    parser.add_argument("runs", nargs="+", type=Path,
                        help="run directories (each with result.json)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    results = []
    for run in args.runs:
        path = run / "result.json"
        if not path.is_file():
            print(f"{path}: missing (run ./softpack adhesion --out {run})",
                  file=sys.stderr)
            return 2
        results.append((run.name, json.loads(path.read_text())))
    args.out.mkdir(parents=True, exist_ok=True)
    write_rows(args.out / "adhesion.csv",
               [row(n, r) for n, r in results], COLUMNS)
    figure(results, args.out / "force_width.png")
    print(f"wrote {args.out}/adhesion.csv, force_width.png/.pdf")
    return 0


if __name__ == "__main__":
    sys.exit(main())
