"""What carries state beyond the bodies' node vectors, on several MPI
ranks (docs/mpi_design.md, "Laws with state and the periodic cell"): the
viscoelastic law's internal variables (each body's with its owner, moved at
a rebalance, gathered for the state file), the bonded law's bonds, the
adhesive law's cohesion and the periodic cell (its vectors and rates
replicated, the bodies re-wrapped and kicked from centroids summed from
their owners), each run on 2 (and 3) ranks against the same run on one.

The references are the 1-rank runs of the same configurations: the ranks
change the order of the contact solve's Gauss–Seidel sweeps only, so the
runs agree within the solver's tolerance (the bounds are ~10x the largest
differences measured on 2026-12-03, given with each).
"""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from softpack.contract.tables import read_table
from softpack.simulation import run

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
EXAMPLES = ROOT / "examples"


def _load(name, sets):
    pytest.importorskip("dolfinx")
    from driver_required import require_driver
    from softpack.scene.config import load_config
    require_driver()
    if shutil.which("mpirun") is None:
        pytest.skip("mpirun is not installed")
    return load_config(EXAMPLES / name, {"output.fields": False, **sets})


def _runs(base, name, sets, ranks, extra=None):
    """`name` with `sets` on each number of ranks (and extra[r] on r);
    the steps tables."""
    out = {}
    for r in ranks:
        config = _load(name, {**sets, **(extra or {}).get(r, {})})
        status = run.run(config, base / f"r{r}", verbose=False, ranks=r)
        assert status in (0, 3)  # 3: stopped by stop.steps, as asked
        out[r] = read_table(base / f"r{r}" / "raw" / "steps.csv")
    return out


def _assert_close(one, other, phi_abs, e_rel, columns=()):
    """Same output steps and contact counts; Phi within phi_abs; strain
    energy within e_rel of its largest; each (column, rel) within rel of
    its column's largest."""
    assert len(one["step"]) == len(other["step"]) > 5
    np.testing.assert_array_equal(other["step"], one["step"])
    np.testing.assert_array_equal(other["contacts"], one["contacts"])
    np.testing.assert_allclose(other["phi"], one["phi"], rtol=0, atol=phi_abs)
    for key, rel in (("strain_energy", e_rel), *columns):
        scale = np.abs(one[key]).max()
        assert scale > 0, key
        np.testing.assert_allclose(other[key], one[key], rtol=0,
                                   atol=rel * scale, err_msg=key)


VISCO = {"stop.steps": 100}


@pytest.fixture(scope="module")
def viscoelastic(tmp_path_factory):
    """examples/viscoelastic_small.toml's first 100 steps on 1, 2 and 3
    ranks (3: parallel.rebalance_tolerance = 0, so that bodies move with
    their internal variables)."""
    base = tmp_path_factory.mktemp("visco")
    return base, _runs(base, "viscoelastic_small.toml", VISCO, (1, 2, 3),
                       {3: {"parallel.rebalance_tolerance": 0.0}})


def test_the_viscoelastic_law_on_two_and_three_ranks_gives_the_serial_run(
        viscoelastic):
    """Measured 2026-12-03 (150 steps): Phi 5.2e-11 (2 ranks) and 4.5e-11
    (3), strain energy 1.4e-8 and 9.6e-9 of its largest, the viscous
    account 1.4e-9 and 2.5e-9 of its final value. A rank missing another's
    internal variables (NaN, or the initial ones) would move the viscous
    account by a rank's share (~0.5)."""
    base, runs = viscoelastic
    assert runs[1]["viscous"][-1] > 0
    for r in (2, 3):
        _assert_close(runs[1], runs[r], 6e-10, 2e-7,
                      (("viscous", 3e-8), ("kinetic_energy", 4e-8)))
    done = (base / "r3" / "raw" / "done.json").read_text()
    assert '"bodies_moved": 0' not in done  # the internal variables moved


def test_a_viscoelastic_state_of_two_ranks_continues_on_two_and_on_one(
        viscoelastic, tmp_path):
    """The state gathers every cell's internal variables from its owner:
    a run stopped at step 50 on 2 ranks and resumed on 2 gives the
    uninterrupted 2-rank run's rows (the split never changes on 2 ranks
    here: the same sweeps in the same order); resumed on 1 rank, the
    1-rank run's."""
    base, runs = viscoelastic
    parts = {}
    for ranks in (2, 1):  # stopped on 2 ranks, resumed on `ranks`
        part = parts[ranks] = tmp_path / f"resumed-on-{ranks}"
        assert run.run(_load("viscoelastic_small.toml", {"stop.steps": 50}),
                       part, verbose=False, ranks=2) in (0, 3)
        for name in ("series.csv", "particles.csv", "raw/done.json"):
            (part / name).unlink()
        toml = part / "config.toml"
        toml.write_text(toml.read_text().replace("steps = 50 ", "steps = 100 "))
        assert run.main(["--resume", str(part), "--ranks", str(ranks)]) in (
            0, 3)
    a, b = runs[2], read_table(parts[2] / "raw" / "steps.csv")
    assert a.keys() == b.keys() and len(a["step"]) == len(b["step"])
    for column in a:
        if not column.startswith("seconds"):
            np.testing.assert_array_equal(a[column], b[column],
                                          err_msg=column)
    # Continued on one rank: the 1-rank run, within the 2-rank run's own
    # difference from it (measured 2026-12-03, 70 steps on 2 ranks then
    # 80 on 1: Phi 1.1e-11, strain energy 1.4e-8, viscous 1.5e-9)
    _assert_close(runs[1], read_table(parts[1] / "raw" / "steps.csv"), 6e-10,
                  2e-7, (("viscous", 3e-8),))


def test_the_bonded_law_on_two_ranks_breaks_the_same_bonds(tmp_path):
    """examples/bonded_small.toml's first 300 steps: the same intact bonds
    at every output (every rank forms and breaks them from the same
    contacts and whole reactions), Phi and the strain energy as on one
    rank. Measured 2026-12-03 over the whole example (440 steps): the
    same intact_bonds (43 -> 10), Phi 6.6e-10, strain energy 4.3e-8 of
    its largest, the bond account 2.2e-5 of its largest (the work of the
    held bonds' reactions, the part of the force the solver's tolerance
    leaves free)."""
    runs = _runs(tmp_path, "bonded_small.toml", {"stop.steps": 300}, (1, 2))
    assert runs[1]["intact_bonds"].max() > runs[1]["intact_bonds"][-1] > 0
    np.testing.assert_array_equal(runs[2]["intact_bonds"],
                                  runs[1]["intact_bonds"])
    _assert_close(runs[1], runs[2], 7e-9, 4e-7, (("bond", 2e-4),))


def test_the_adhesive_law_on_two_ranks_gives_the_serial_run(tmp_path):
    """examples/adhesive_small.toml's first 300 steps (the cohesion of each
    contact integrated over its candidate's boundary segments, from the
    contacts and boundary nodes every rank has): measured 2026-12-03, Phi
    3.6e-10, strain energy 1.1e-8 of its largest, the cohesion account
    5.3e-8 of its largest, the same contacts at every output (the count of
    active ones once one apart: a contact at the threshold R_n + c = 0
    within the tolerance)."""
    runs = _runs(tmp_path, "adhesive_small.toml", {"stop.steps": 300}, (1, 2))
    assert np.abs(runs[1]["cohesion"]).max() > 0
    _assert_close(runs[1], runs[2], 4e-9, 1e-7, (("cohesion", 5e-7),))


def test_a_periodic_cell_on_two_and_three_ranks_gives_the_serial_run(
        tmp_path):
    """examples/periodic_small.toml's first 150 steps (the cell closing at
    an imposed rate; bodies re-wrapped from step 90): measured 2026-12-03
    over its whole run (340 steps), Phi 9.0e-10 (2 ranks) and 5.7e-10 (3),
    strain energy 1.2e-7 and 6.7e-8 of its largest, the cell's work 3.4e-8
    and 1.3e-8, the re-wrapping account 1.7e-8 and 4.8e-8, the kinetic
    energy 6.6e-8 and 6.2e-8; the cell's vectors the same bits (imposed
    rates); over 150 steps on 3
    ranks with rebalance_tolerance = 0 (3 bodies moved) Phi 3.9e-11,
    strain energy 4.7e-9."""
    runs = _runs(tmp_path, "periodic_small.toml", {"stop.steps": 150},
                 (1, 2, 3), {3: {"parallel.rebalance_tolerance": 0.0}})
    assert runs[1]["rewrap"][-1] != 0  # bodies crossed the edges
    for r in (2, 3):
        _assert_close(runs[1], runs[r], 1e-8, 1e-6,
                      (("cell_work", 3e-7), ("rewrap", 5e-7),
                       ("kinetic_energy", 7e-7)))
        np.testing.assert_array_equal(runs[r]["cell_a1x"], runs[1]["cell_a1x"])


def test_a_stress_controlled_cell_on_two_ranks_gives_the_serial_run(
        tmp_path):
    """examples/shear_small.toml's first 400 steps (the cell's height
    free under sigma_yy, its rate an unknown of the contact problem: W's
    rank-one term over the ranks' contacts; it closes by 13 mm here).
    Measured 2026-12-03: Phi 2.9e-10, strain energy 3.1e-9 of its largest,
    the cell's height 1.4e-10 of itself, its work 9.5e-10. Over the whole
    example (5,500 steps) the runs part: the difference grows tenfold
    every ~250 steps, from 1e-12 (Phi at step 250) to 8e-7 (step 1,500)
    and 1e-2 after step 2,250, as a 1-rank run with another NLGS tolerance
    does (docs/periodic_cell.md): a sheared dense flow amplifies any
    difference."""
    runs = _runs(tmp_path, "shear_small.toml", {"stop.steps": 400}, (1, 2))
    assert np.ptp(runs[1]["cell_a2y"]) > 0.01  # the height moved
    _assert_close(runs[1], runs[2], 3e-9, 3e-8,
                  (("cell_a2y", 2e-9), ("cell_work", 1e-8)))
