"""The assembly-scale cases of test_assembly_runs.py and their committed
reference series (issue 43 item 2).

Three small runs of the examples, each a few seconds: a compaction of 26
disks by the piston, a staged servo run (isotropic consolidation to rest,
then a biaxial stage) and a rigid+soft mixture. Their reference series,
``tests/python/reference/<case>.csv`` (the columns of :data:`COLUMNS` from
series.csv and stress.csv at every output row), are rewritten by::

    eval "$(./softpack env)"
    /usr/bin/python3 tests/python/assembly_cases.py

A change that moves a reference updates it in the same commit and says why.
"""

from __future__ import annotations

import csv
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
REFERENCE = Path(__file__).resolve().parent / "reference"

#: case: (example, overrides)
CASES = {
    # examples/small.toml with 26 disks (18 small, 8 large) in a box of the
    # same aspect ratio and initial packing fraction: 473 steps to 0.80.
    "compaction": ("small.toml", {"box.length": 0.1515, "box.width": 0.1067,
                                  "species.0.count": 18,
                                  "species.1.count": 8}),
    # consolidation under 4 kPa to rest (equilibrium 1e-2), then 10 % axial
    # strain: 1472 steps.
    "servo": ("biaxial_small.toml", {}),
    # 7 soft and 7 rigid disks; stopped at 140 steps, before the one contact
    # solve of the whole run that misses its tolerance (step 162).
    "mixed": ("mixture_small.toml", {"stop.steps": 140}),
}

#: The columns compared with the reference: (table, column).
COLUMNS = [("series", c) for c in (
    "step", "time", "phi", "eps", "piston_force", "strain_energy",
    "kinetic_energy", "wall_work", "external_work", "damping", "friction",
    "contact_normal", "numerical", "energy_residual", "contacts",
    "active_contacts", "newton_iterations", "nlgs_iterations")] + [
    ("stress", c) for c in (
        "area", "left_stress", "right_stress", "bottom_stress", "top_stress",
        "wall_P", "wall_q", "contact_P", "contact_q", "fe_P", "fe_q")]


def config(case: str):
    """The validated configuration of a case."""
    from softpack.scene.config import load_config
    example, overrides = CASES[case]
    return load_config(ROOT / "examples" / example, overrides)


def run_case(case: str, out: Path) -> Path:
    """Run a case into ``out`` (through the API, as a user would)."""
    import softpack
    softpack.run(config(case), out)
    return out


def series(out: Path) -> dict[str, np.ndarray]:
    """The compared columns of a finished run, named ``table.column``."""
    from softpack.contract.run_directory import RunDirectory
    from softpack.contract.tables import read_table
    run = RunDirectory(out)
    tables = {"series": read_table(run.series_csv),
              "stress": read_table(run.stress_csv)}
    return {f"{t}.{c}": np.asarray(tables[t][c], dtype=float)
            for t, c in COLUMNS}


def read_reference(case: str) -> dict[str, np.ndarray]:
    """The committed reference series of a case."""
    with open(REFERENCE / f"{case}.csv", newline="") as f:
        rows = list(csv.reader(f))
    return {name: np.array([float(r[k]) for r in rows[1:]])
            for k, name in enumerate(rows[0])}


def write_reference(case: str, values: dict[str, np.ndarray]) -> Path:
    """Write a case's reference series (17 digits: every bit kept)."""
    REFERENCE.mkdir(exist_ok=True)
    path = REFERENCE / f"{case}.csv"
    names = list(values)
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(names)
        for k in range(len(values[names[0]])):
            out.writerow([repr(float(values[n][k])) for n in names])
    return path


def main() -> int:
    import tempfile
    with tempfile.TemporaryDirectory() as scratch:
        for case in CASES:
            out = run_case(case, Path(scratch) / case)
            print(write_reference(case, series(out)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
