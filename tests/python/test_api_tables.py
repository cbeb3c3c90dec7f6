"""Issue 37 item 4: the API is the CLI's twin. ``dir(softpack)`` lists the
public names; ``read_run`` reads every table a run writes; ``plot_loading``
draws what ``./softpack plot-loading`` draws, and refuses the
finite-element stress of a run with rigid bodies (it leaves them out)."""

import json

import numpy as np
import pytest

import softpack
from fake_runs import write_loading_run
from softpack.contract.run_directory import RunError


def _loading_run(directory, rigid=()):
    phi = np.linspace(0.80, 0.86, 12)
    return write_loading_run(directory, phi, 1e4 * (phi - 0.78), rigid)


def test_dir_lists_the_public_names():
    names = dir(softpack)
    for name in softpack.__all__:
        assert name in names
        assert callable(getattr(softpack, name))
    assert "plot_loading" in names and "read_run" in names


def test_read_run_reads_every_table(tmp_path):
    run = _loading_run(tmp_path / "run")
    (run / "raw" / "contacts").mkdir()
    (run / "raw" / "contacts" / "step_00000003.csv").write_text(
        "candidate,node,antagonist,fn\n0,4,1,2.5\n")
    stress = softpack.read_run(run, "stress")
    assert len(stress["wall_P"]) == 12
    assert list(softpack.read_run(run, "steps")["step"]) == list(range(12))
    contacts = softpack.read_run(run, "contacts", step=3)
    assert list(contacts["fn"]) == [2.5]
    with pytest.raises(ValueError, match="'series', 'particles', 'stress'"):
        softpack.read_run(run, "nope")
    with pytest.raises(ValueError, match="step"):
        softpack.read_run(run, "contacts")
    with pytest.raises(ValueError, match="step"):
        softpack.read_run(run, "stress", step=3)
    with pytest.raises(FileNotFoundError, match="step_00000004"):
        softpack.read_run(run, "contacts", step=4)
    with pytest.raises(FileNotFoundError, match="particles.csv"):
        softpack.read_run(run, "particles")


def test_plot_loading_through_the_api(tmp_path):
    pytest.importorskip("matplotlib")
    run = _loading_run(tmp_path / "soft")
    summary = softpack.plot_loading(run, tmp_path / "fig")
    assert summary["estimate"] == "fe"
    written = json.loads((tmp_path / "fig" / "loading.json").read_text())
    assert written["figures"] == summary["figures"]
    assert written["estimate"] == "fe"
    for figure in summary["figures"]:
        assert (tmp_path / "fig").joinpath(figure).is_file()
    with pytest.raises(RunError, match="no stage 4"):
        softpack.plot_loading(run, tmp_path / "fig", stage=4)
    with pytest.raises(RunError, match="not a run directory"):
        softpack.plot_loading(tmp_path / "nothing")


def test_rigid_bodies_take_the_contacts_estimate(tmp_path):
    """The finite elements give no stress inside a rigid body: with one
    rigid species the default is Love-Weber, and 'fe' is refused."""
    pytest.importorskip("matplotlib")
    run = _loading_run(tmp_path / "mixed", rigid=(1,))
    assert softpack.plot_loading(run, tmp_path / "fig")["estimate"] == \
        "contact"
    with pytest.raises(RunError, match="1 of the 2 bodies are rigid"):
        softpack.plot_loading(run, tmp_path / "fig", estimate="fe")
