"""RunDirectory names the files of docs/contract.md (sections 4-6) and the
launch checks that the driver finished."""

import json

import pytest

from softpack.contract.run_directory import (RUN_OUTPUTS, RunDirectory,
                                             RunError)


def test_every_path_of_a_run(tmp_path):
    run = RunDirectory(tmp_path)
    names = {
        "config.toml": run.config_toml, "driver.json": run.driver_json,
        "run.log": run.run_log, "driver.log": run.driver_log,
        "mesh/packing": run.mesh_stem("packing"),
        "raw/steps.csv": run.raw.steps_csv,
        "raw/particles.csv": run.raw.particles_csv,
        "raw/contacts/step_00000120.csv": run.raw.contact_file(120),
        "raw/failed_contact_problems": run.raw.step_dirs[1],
        "raw/setup.json": run.raw.setup_json,
        "raw/state.bin": run.raw.state_bin,
        "raw/state.stage.json": run.raw.stage_record,
        "raw/done.json": run.raw.done_json,
        "raw.part/steps.csv": run.raw_part.steps_csv,
        "resume-state.bin": run.resume_state,
        "resume-state.stage.json": run.resume_stage_record,
        "fields.h5": run.fields_h5, "fields.xdmf": run.fields("xdmf"),
        "fields": run.field_frames,
        "series.csv": run.series_csv, "particles.csv": run.particles_csv,
        "stress.csv": run.stress_csv, "network.csv": run.network_csv}
    for name, path in names.items():
        assert path == tmp_path / name, name
    # what --force replaces is what a run writes at the top level
    tops = {name.split("/")[0] for name in names} - {
        "driver.log", "resume-state.stage.json"}
    assert tops <= set(RUN_OUTPUTS) | {"mesh"}


def test_done_says_the_run_did_not_finish(tmp_path):
    run = RunDirectory(tmp_path)
    with pytest.raises(RunError, match="did not finish"):
        run.done()
    run.raw.path.mkdir()
    run.raw.done_json.write_text(json.dumps({"steps": 3}))
    assert run.done() == {"steps": 3}


def test_launch_reports_a_failed_driver(tmp_path, fake_bin, monkeypatch):
    """The one launch: a driver that fails raises RunError with its exit
    status and the last lines of its log."""
    from softpack.simulation import driver

    (fake_bin / "softpack-simulate").write_text(
        "#!/bin/sh\necho 'fake: out of luck'\nexit 4\n")
    run = RunDirectory(tmp_path / "run")
    run.path.mkdir()
    run.driver_json.write_text("{}\n")
    with pytest.raises(driver.DriverFailed, match="exit status 4") as err:
        driver.launch(run, log=run.driver_log)
    assert err.value.status == 4 and "out of luck" in str(err.value)
