"""Issue 42 item 8: the field output is crash-consistent.

A driver writing a frame at every step is killed (SIGKILL) 20 times, each
time a random number of frames after it started and a random part of a step
later, and resumed after each kill. After every kill each frame fields.xdmf
lists reads back through meshio, and each frame file through
softpack.analysis.fields; the run finished through the kills holds the
uninterrupted run's frames, bit for bit (a resume is bit for bit).

With every frame inside one fields.h5 (before this layout), a kill inside a
frame's write could leave the whole file unreadable ("Link iteration
failed", seen once in the full suite).
"""

import random
import signal
import threading
import time

import numpy as np
import pytest

import softpack
from driver_required import require_driver
from fake_driver import SMALL
from softpack.analysis import fields
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.scene.config import load_config
from softpack.simulation import driver

pytestmark = pytest.mark.usefixtures("registry")

KILLS = 20
#: A frame per step (about 6 ms each on this machine, of which the frame's
#: write is about a third), for at least 20 x 10 frames; the piston slow
#: enough for these steps.
SETTINGS = {"walls.right.velocity": [-0.1, 0.0], "stop.max_time": 1.0,
            "stop.steps": 260, "output.every_steps": 1,
            "output.fields_every": 1}


class _Killer:
    """Kills each driver the run starts once it has written a random number
    (1-10) of frames more, a random part (0-6 ms) of a step later."""

    def __init__(self, frames, rng):
        self._frames, self._rng = frames, rng
        self._start = driver.start
        self.kills = 0

    def start(self, *args, **kwargs):
        proc = self._start(*args, **kwargs)
        threading.Thread(target=self._kill, args=(proc,), daemon=True).start()
        return proc

    def _written(self) -> int:
        return sum(1 for p in self._frames.glob("[!.]*.h5"))

    def _kill(self, proc):
        target = self._written() + self._rng.randint(1, 10)
        delay = self._rng.uniform(0.0, 6e-3)
        while proc.poll() is None and self._written() < target:
            time.sleep(5e-4)
        time.sleep(delay)
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            self.kills += 1


def _every_frame_reads(out) -> dict:
    """Every frame fields.xdmf lists (meshio) and every frame file
    (softpack's reader) reads back; ``{time: (displacement, Psi,
    particle)}`` as meshio read them."""
    meshio = pytest.importorskip("meshio")
    run = RunDirectory(out)
    frames = {}
    with meshio.xdmf.TimeSeriesReader(run.fields("xdmf")) as reader:
        points, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            assert point_data["displacement"].shape == (len(points), 3)
            assert t not in frames and all(t > s for s in frames)
            frames[t] = (point_data["displacement"], cell_data["Psi"][0],
                         cell_data["particle"][0])
    stored = dict(fields.read_displacements(run.fields_h5))
    assert set(frames) <= set(stored)
    return frames


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    """The run of :data:`SETTINGS` never killed: ``(config, directory)``."""
    require_driver()
    config = load_config(SMALL, SETTINGS)
    clean = RunDirectory(tmp_path_factory.mktemp("fields") / "clean")
    softpack.run(config, clean.path)
    return config, clean


def _same_frames(run, clean):
    killed, uninterrupted = (_every_frame_reads(r.path) for r in (run, clean))
    assert list(killed) == list(uninterrupted)
    for t, values in uninterrupted.items():
        for a, b in zip(killed[t], values):
            np.testing.assert_array_equal(a, b)


def test_a_driver_killed_20_times_in_its_frame_writes_loses_no_frame(
        uninterrupted, tmp_path, monkeypatch):
    config, clean = uninterrupted
    out = RunDirectory(tmp_path / "killed")
    killer = _Killer(out.field_frames, random.Random(8))
    monkeypatch.setattr(driver, "start", killer.start)
    monkeypatch.setattr(driver, "POLL_SECONDS", 0.02)  # a kill seen at once
    resume, listed = (lambda: softpack.run(config, out.path)), []
    for _ in range(KILLS):
        with pytest.raises(RunError):
            resume()
        listed.append(len(_every_frame_reads(out.path)))
        resume = lambda: softpack.resume(out.path)  # noqa: E731
    assert killer.kills == KILLS
    monkeypatch.setattr(driver, "start", killer._start)
    softpack.resume(out.path)
    # each kill came after more frames were written, and none was lost
    assert listed == sorted(listed) and listed[0] > 0
    _same_frames(out, clean)


def test_a_run_of_the_one_file_layout_is_continued(uninterrupted, tmp_path,
                                                   monkeypatch):
    """A run killed under an earlier version (every frame inside fields.h5,
    one more frame past its state) resumed by this one: that frame goes, the
    others stay in fields.h5, the new ones follow in fields/."""
    h5py = pytest.importorskip("h5py")
    config, clean = uninterrupted
    out = RunDirectory(tmp_path / "old")
    killer = _Killer(out.field_frames, random.Random(3))
    monkeypatch.setattr(driver, "start", killer.start)
    with pytest.raises(RunError):
        softpack.run(config, out.path)
    monkeypatch.setattr(driver, "start", killer._start)
    frames = sorted(out.field_frames.glob("*.h5"))
    with h5py.File(out.fields_h5, "a") as f:
        for file in frames:
            with h5py.File(file, "r") as frame:
                for name in frame["Function"]:
                    frame.copy(f"Function/{name}/{file.stem}", f,
                               f"Function/{name}/{file.stem}")
        for name in f["Function"]:  # a frame written after the last state
            f[f"Function/{name}/9_5"] = f[f"Function/{name}/{file.stem}"][()]
    for file in frames:
        file.unlink()
    softpack.resume(out.path)
    assert 9.5 not in fields.stored_times(out.fields_h5)
    # the frames before the state's stay in fields.h5 (the state's own is
    # written again by the resumed driver; a kill between a frame and its
    # state leaves one more, removed with 9.5)
    xdmf = out.fields("xdmf").read_text()
    assert len(frames) - 2 <= xdmf.count(">fields.h5:/Function/displacement")
    _same_frames(out, clean)
