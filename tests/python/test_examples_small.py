"""Every small example (examples/small.toml and examples/*_small.toml) runs
to its end with today's defaults, serially, through the Python API (the 3D
examples: their first STEPS_3D steps).

Each takes a few seconds. A run must exit with status 0 (``run`` returns 0,
raises RunError otherwise), write raw/done.json, count no step whose Newton
iterations did not converge, compact the assembly (its largest Phi above
its first) and stay quasi-static: its kinetic energy at the written steps
below MAX_KINETIC_ENERGY (a run that goes through a jam "by luck" does not
pass). The contact solver may miss its tolerance on some steps (the
rigid-body examples do: docs/materials.md); those are counted, not failed.
"""

import csv
import json
from pathlib import Path

import pytest

from driver_required import require_driver
from softpack.scene import config as cfg
from softpack.contract.run_directory import (EXIT_DONE, EXIT_FLAGGED,
                                             run_flags)
from softpack.simulation.run import RunError, run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SMALL = sorted([EXAMPLES / "small.toml", *EXAMPLES.glob("*_small.toml")])

# mixture_small.toml with seed 0 (its seed until 2026-12-02) formed a chain
# of rigid disks from the left to the velocity-driven right wall (left wall,
# rigid 6, 13, 12, 7, right wall, every contact inside its friction cone) at
# t = 0.029-0.031 s whatever the contact solver's order or the time step:
# the right wall's force jumped from 2.8e3 to 6e5-2.5e7 N/m in one or two
# steps and the kinetic energy from 0.4 to 6-80 J; with the defaults Newton
# failed at step 309 and an element inverted. Not a solver defect: a rigid
# chain spanning the box under an imposed wall velocity cannot shorten, and
# the contact problem has no solution (its reactions grew along a self-stress
# of the chain). The example now uses seed 8, whose packing reaches
# Phi = 0.80 without such a chain (docs/materials.md).

# The largest kinetic energy written (raw/steps.csv, every output step) of
# each example is 0.19-0.84 J (2026-12-02; mixture_small 0.63 J;
# two_stage_small 1.36 J on 2026-12-03, its servo walls closing a loose
# packing of ellipses); the jam of
# mixture_small with seed 0 launched its rigid disks: 6-80 J.
MAX_KINETIC_ENERGY = 2.0

# The 3D examples run their first steps only (a run to their stop criteria
# takes minutes: docs/bodies_3d.md, "The 3D time loop"): enough for the
# piston to move and Phi to rise.
STEPS_3D: dict[str, int] = {"cylinders3d_small.toml": 12,
                            "spheres3d_small.toml": 12,
                            "mixture3d_small.toml": 12}

# Examples that finish flagged (exit status 3, run_flags), and the one flag
# expected of each. mixture_small: one contact solve of its 379 steps
# (step 162 on one rank, 146 on three) misses nlgs_tolerance 1e-8, and
# stalls there with 20,000 sweeps too (measured 2026-12-03); it is written
# to raw/failed_contact_problems/ for replay (./softpack fclib).
KNOWN_FLAGGED: dict[str, str] = {"mixture_small.toml": "not converged"}


def params():
    for path in SMALL:
        yield pytest.param(path, id=path.stem)


def test_every_small_example_is_listed():
    names = {p.name for p in SMALL}
    assert "small.toml" in names and "mixture_small.toml" in names
    assert len(names) >= 10


@pytest.mark.parametrize("example", params())
def test_small_example_runs_to_its_end(example, tmp_path):
    require_driver()
    overrides = {"output.fields": False}
    if example.name in STEPS_3D:
        overrides.update({"stop.steps": STEPS_3D[example.name],
                          "output.every_steps": 4})
    config = cfg.load_config(example, overrides)
    out = tmp_path / example.stem
    try:
        status = run(config, out, verbose=False)
    except RunError as err:
        pytest.fail(f"{example.name}: {err}")
    done_path = out / "raw" / "done.json"
    assert done_path.is_file(), f"{example.name}: no raw/done.json"
    done = json.loads(done_path.read_text())
    flags = run_flags(done)
    if example.name in KNOWN_FLAGGED:
        assert status == EXIT_FLAGGED, f"{example.name}: no longer flagged"
        assert [f.split(" (")[0] for f in flags] == [
            KNOWN_FLAGGED[example.name]], flags
    else:
        assert status == EXIT_DONE, f"{example.name}: {flags}"
    assert done["steps"] > 0
    # the key itself is checked: a done.json without it must not pass
    assert done["newton_unconverged_steps"] == 0, (
        f"{example.name}: {done['newton_unconverged_steps']} steps whose "
        "Newton iterations did not converge")
    with open(out / "raw" / "steps.csv") as f:
        rows = list(csv.DictReader(f))
    # ... and the per-interval counts of steps.csv add up to it
    assert sum(int(row["newton_unconverged_steps"]) for row in rows) == \
        done["newton_unconverged_steps"]
    phi = [float(row["phi"]) for row in rows]
    kinetic = max(float(row["kinetic_energy"]) for row in rows)
    assert all(p == p for p in phi), f"{example.name}: Phi is NaN"
    assert max(phi) > phi[0], f"{example.name}: Phi never rose above {phi[0]}"
    assert kinetic < MAX_KINETIC_ENERGY, (
        f"{example.name}: kinetic energy up to {kinetic:.3g} J: not "
        "quasi-static (a jam or a blow-up)")
