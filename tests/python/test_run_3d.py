"""A 3D scene stepped through the time loop (issue 40): the spheres of
examples/spheres3d_small.toml compacted by the right wall for a few dozen
steps, through the Python API as ``./softpack run`` runs it.

What is checked is physics, not only that files exist: the volume fraction
Phi rises as the piston moves in and is the bodies' volume over the box's
(particles.csv against the walls' columns of steps.csv); the piston pushes
spheres (contacts, a force on the right wall along -x, strain energy); the
energy balance closes (its residual, a small fraction of the work the
walls supplied); no Newton iteration or contact solve is left unconverged;
the raw files and the tetrahedral fields are readable (csv, meshio); the
run stopped halfway and resumed, or started from its state, is the
uninterrupted run bit for bit.
"""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from killed_run import as_killed, assert_same_rows
from softpack.contract.run_directory import EXIT_DONE, EXIT_FLAGGED
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.simulation.run import run

meshio = pytest.importorskip("meshio")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: The variant run: the example's piston at 2 m/s (the fastest its time
#: step allows: [contact] alert_distance / speed >= time_step), pushing the
#: sphere that touches it from the start and reaching more within STEPS
#: steps.
STEPS = 60
OVERRIDES = {"stop.steps": STEPS, "output.every_steps": 6,
             "output.fields_every": 5,
             "walls.right.velocity": [-2.0, 0.0]}

#: Bound on the largest |energy residual| over the walls' work at the end.
#: Measured 1.3e-4 (2.6e-5 J of 0.209 J, 2026-12-04): the Newton iterations
#: stop at time.newton_tolerance = 1e-4 of the velocities, and what they
#: leave unconverged is what the balance does not account for; 1e-3 leaves
#: a margin of 8 and still fails a missing term (the numerical dissipation
#: of theta = 0.55 alone is larger).
RESIDUAL_BOUND = 1e-3


@pytest.fixture(scope="module")
def spheres(tmp_path_factory):
    require_driver()
    config = cfg.load_config(EXAMPLES / "spheres3d_small.toml", OVERRIDES)
    out = tmp_path_factory.mktemp("spheres3d")
    status = run(config, out, verbose=False)
    return out, status


def test_the_run_ends_converged_after_its_steps(spheres):
    out, status = spheres
    assert status == EXIT_DONE
    done = json.loads((out / "raw" / "done.json").read_text())
    assert done["reason"] == "steps" and done["steps"] == STEPS
    assert done["dimension"] == 3
    assert done["converged"] is True
    assert done["newton_unconverged_steps"] == 0
    assert done["nlgs_unconverged_steps"] == 0
    assert done["overlap_steps"] == 0


def test_an_unsolved_3d_contact_problem_is_written_for_replay(tmp_path):
    """One NLGS sweep allowed: the run's contact solves fail, the run says
    so (exit status, done.json) and writes the first problems in the FCLIB
    layout of dimension 3, with the contacts of their step and the solve's
    start (replayed bit for bit by tests/cpp/dynamics3d/
    test_unsolved_problem_3d.cpp)."""
    h5py = pytest.importorskip("h5py")
    require_driver()
    config = cfg.load_config(EXAMPLES / "spheres3d_small.toml",
                             {**OVERRIDES, "stop.steps": 12,
                              "output.fields": False,
                              "contact.nlgs_max_sweeps": 1})
    out = tmp_path / "unsolved"
    assert run(config, out, verbose=False) == EXIT_FLAGGED
    done = json.loads((out / "raw" / "done.json").read_text())
    assert done["nlgs_unconverged_steps"] > 0
    files = sorted((out / "raw" / "failed_contact_problems").glob("*.hdf5"))
    assert len(files) == done["failed_contact_problems_written"] > 0
    with h5py.File(files[0]) as f:
        assert int(f["fclib_local/spacedim"][0]) == 3
        contacts = len(f["fclib_local/vectors/mu"])
        assert contacts > 0
        assert len(f["fclib_local/vectors/q"]) == 3 * contacts
        assert len(f["guesses/1/r"]) == 3 * contacts
        assert int(f["fclib_local/W/m"][0]) == 3 * contacts


def test_phi_rises_as_the_piston_moves_in(spheres):
    out, _ = spheres
    s = read_table(out / "raw" / "steps.csv")
    assert len(s["step"]) == STEPS // 6 + 1
    # the piston at 2 m/s, the other walls still
    assert np.allclose(s["right_x"], s["right_x"][0] - 2.0 * s["time"],
                       rtol=0, atol=1e-12)
    assert np.all(s["left_x"] == s["left_x"][0])
    assert np.all(s["lid_z"] == 0.060) and np.all(s["base_z"] == 0.0)
    assert np.all(np.diff(s["phi"]) > 0)
    # Phi is the bodies' volume over the box's (its walls' positions)
    p = read_table(out / "raw" / "particles.csv")
    for k, step in enumerate(s["step"]):
        volume = p["area"][p["step"] == step].sum()
        box = ((s["right_x"][k] - s["left_x"][k])
               * (s["top_y"][k] - s["bottom_y"][k])
               * (s["lid_z"][k] - s["base_z"][k]))
        assert s["phi"][k] == pytest.approx(volume / box, rel=1e-9)


def test_the_piston_pushes_the_spheres_and_the_balance_closes(spheres):
    out, _ = spheres
    s = read_table(out / "raw" / "steps.csv")
    assert s["active_contacts"][-1] > 0
    assert s["right_fx"][-1] > 0  # the spheres push the piston back, out
    assert s["strain_energy"][-1] > 0
    assert s["wall_work"][-1] > 0
    residual = np.abs(s["energy_residual"]).max()
    assert residual <= RESIDUAL_BOUND * s["wall_work"][-1], (
        residual, s["wall_work"][-1])


def test_the_3d_outputs_are_readable(spheres):
    out, _ = spheres
    s = read_table(out / "raw" / "steps.csv")
    for name in ("left", "right", "bottom", "top", "base", "lid"):
        for c in ("x", "y", "z", "fx", "fy", "fz"):
            assert f"{name}_{c}" in s
    assert "cauchy_zz" in s
    last = int(s["step"][-1])
    contacts = read_table(out / "raw" / "contacts" / f"step_{last:08d}.csv")
    assert {"triangle0", "fn", "ft1", "ft2", "fz"} <= set(contacts)
    assert np.all(contacts["fn"] >= 0)  # Signorini: no tension
    with meshio.xdmf.TimeSeriesReader(out / "fields.xdmf") as reader:
        points, cells = reader.read_points_cells()
        times = [reader.read_data(k)[0] for k in range(reader.num_steps)]
        _, point_data, _ = reader.read_data(reader.num_steps - 1)
    assert [c.type for c in cells] == ["tetra"] and points.shape[1] == 3
    # every 5th output and the last: rows 0, 5 and 10 of 11
    assert times == pytest.approx([s["time"][0], s["time"][5], s["time"][10]])
    assert np.abs(point_data["displacement"]).max() > 0


def test_standing_cylinders_slide_on_a_frictionless_base(tmp_path):
    """examples/cylinders3d_small.toml names the base in [[friction]] with
    coefficient 0 (the experiment's lubricated glass): the driver's
    friction table gives the base its own party, so the base's contacts
    carry no tangential force while the bodies' contacts keep the default
    friction."""
    require_driver()
    config = cfg.load_config(EXAMPLES / "cylinders3d_small.toml",
                             {"stop.steps": 12, "output.every_steps": 12,
                              "output.fields": False})
    assert run(config, tmp_path, verbose=False) == EXIT_DONE
    done = json.loads((tmp_path / "raw" / "done.json").read_text())
    assert done["newton_unconverged_steps"] == 0
    assert done["nlgs_unconverged_steps"] == 0 and done["overlap_steps"] == 0
    setup = json.loads((tmp_path / "raw" / "setup.json").read_text())
    assert setup["scene"]["box"]["height"] == 0.020
    c = read_table(tmp_path / "raw" / "contacts" / "step_00000012.csv")
    base = c["wall"] == 4  # left, right, bottom, top, base, lid
    assert base.sum() > 0
    assert np.all(c["ft1"][base] == 0) and np.all(c["ft2"][base] == 0)
    s = read_table(tmp_path / "raw" / "steps.csv")
    assert s["base_fx"][-1] == 0 and s["base_fy"][-1] == 0


#: The output step at which the run of ``killed`` stops (its state's)
CUT = 30


@pytest.fixture(scope="module")
def killed(tmp_path_factory):
    """The run of ``spheres`` stopped at its output step CUT, what a kill
    there leaves (raw/ up to step CUT with its state, no done.json), with
    config.toml's [stop] steps the whole run's again; and a copy of its
    state, raw/state.bin at step CUT."""
    require_driver()
    config = cfg.load_config(EXAMPLES / "spheres3d_small.toml",
                             {**OVERRIDES, "stop.steps": CUT})
    out = tmp_path_factory.mktemp("killed")
    assert run(config, out, verbose=False) == EXIT_DONE
    state = tmp_path_factory.mktemp("state") / "state.bin"
    shutil.copyfile(out / "raw" / "state.bin", state)
    as_killed(out, CUT, STEPS)
    return out, state


def test_a_run_made_before_a_key_existed_resumes(spheres, killed, tmp_path):
    """A killed run whose driver.json lacks a key the schema gained since
    (here contact.nlgs_update) resumes: the key is added with its default,
    said in run.log, and the run is still the uninterrupted one."""
    from softpack.simulation.run import main

    whole, _ = spheres
    part = tmp_path / "old"
    shutil.copytree(killed[0], part)
    driver_json = part / "driver.json"
    doc = json.loads(driver_json.read_text())
    del doc["contact"]["nlgs_update"]
    driver_json.write_text(json.dumps(doc))
    assert main(["--resume", str(part)]) == EXIT_DONE
    assert "contact.nlgs_update = 'auto'" in (part / "run.log").read_text()
    assert json.loads(driver_json.read_text())["contact"]["nlgs_update"] == \
        "auto"
    assert_same_rows(read_table(whole / "raw" / "steps.csv"),
                     read_table(part / "raw" / "steps.csv"))


def test_a_killed_3d_run_resumed_is_the_uninterrupted_run(spheres, killed):
    """./softpack run --resume of a 3D run: the state carries the six
    planes' points and the warm start in world components (and the kept
    iteration matrix, as in 2D), so the resumed run is the uninterrupted
    one, bit for bit: steps.csv in every column but seconds*,
    particles.csv and the contact files byte for byte."""
    from softpack.simulation.run import main

    whole, _ = spheres
    part, _ = killed
    assert main(["--resume", str(part)]) == EXIT_DONE
    a = read_table(whole / "raw" / "steps.csv")
    b = read_table(part / "raw" / "steps.csv")
    assert len(b["step"]) == STEPS // 6 + 1
    assert b["active_contacts"][-1] > 0  # the warm start did matter
    assert_same_rows(a, b)
    for name in ("particles.csv", "done.json"):
        if name == "done.json":
            x, y = (json.loads((d / "raw" / name).read_text())
                    for d in (whole, part))
            assert (x["steps"], x["reason"]) == (y["steps"], y["reason"])
            continue
        assert ((whole / "raw" / name).read_bytes()
                == (part / "raw" / name).read_bytes())
    files = sorted(p.name for p in (whole / "raw" / "contacts").iterdir())
    assert files == sorted(p.name for p in
                           (part / "raw" / "contacts").iterdir())
    for name in files:
        assert ((whole / "raw" / "contacts" / name).read_bytes()
                == (part / "raw" / "contacts" / name).read_bytes()), name
    assert not (part / "raw.part").exists()


def test_a_3d_run_from_a_state_continues_the_run(spheres, killed,
                                                 tmp_path):
    """--from-state with a 3D state (raw/state.bin of the run stopped at
    step CUT): the new run's rows after the state's step are the
    uninterrupted run's, bit for bit (the state's row has no forces
    averaged over an interval before it)."""
    whole, _ = spheres
    _, state = killed
    config = cfg.load_config(EXAMPLES / "spheres3d_small.toml",
                             {**OVERRIDES, "stop.steps": STEPS - CUT})
    out = tmp_path / "from"
    assert run(config, out, verbose=False, initial_state=state) == EXIT_DONE
    b = read_table(out / "raw" / "steps.csv")
    assert b["step"][0] == CUT and b["step"][-1] == STEPS
    assert_same_rows(read_table(whole / "raw" / "steps.csv"),
                     {k: v[1:] for k, v in b.items()}, first=CUT)


def test_a_3d_state_of_another_packing_is_refused(killed, tmp_path):
    """As in 2D, a state continues only the run it came from: the spheres
    placed with another seed (another mesh) refuse it, naming why."""
    _, state = killed
    config = cfg.load_config(EXAMPLES / "spheres3d_small.toml",
                             {**OVERRIDES, "packing.seed": 1,
                              "stop.steps": 6})
    with pytest.raises(Exception) as err:
        run(config, tmp_path / "other", verbose=False, initial_state=state)
    assert "the state belongs to another mesh or packing" in str(err.value)


def test_phi_base_is_the_bottom_faces_projected_on_the_base(tmp_path):
    """steps.csv's phi_base (the driver's, box_3d.cpp) equals the bottom
    faces of the reference mesh projected on the base in the current
    configuration over the box's plan, recomputed here from fields.h5's
    tetrahedra (softpack.analysis.solids.phi_base) at every written time;
    at t = 0 it is the scene's base area fraction, and it rises as the
    piston squeezes the cylinders (their bottom faces widen along y)."""
    from softpack.analysis import solids

    require_driver()
    config = cfg.load_config(EXAMPLES / "cylinders3d_small.toml",
                             {"stop.steps": 40, "output.every_steps": 20,
                              "output.fields_every": 1,
                              "walls.right.velocity": [-2.0, 0.0]})
    run(config, tmp_path, verbose=False)
    s = read_table(tmp_path / "raw" / "steps.csv")
    assert len(s["phi_base"]) == 3
    for k, t in enumerate(s["time"]):
        extent = (s["right_x"][k] - s["left_x"][k],
                  s["top_y"][k] - s["bottom_y"][k], 0.020)
        f = solids.fractions_at(tmp_path / "fields.h5", t, extent)
        assert f["time"] == pytest.approx(t, abs=1e-12)
        assert s["phi_base"][k] == pytest.approx(f["phi_base"], rel=1e-9)
        if k == 0:
            assert f["phi_base"] == pytest.approx(f["base_area_fraction"],
                                                  rel=1e-12)
    assert s["phi_base"][0] == pytest.approx(0.6826, abs=1e-4)
    assert s["phi_base"][-1] > s["phi_base"][0]
