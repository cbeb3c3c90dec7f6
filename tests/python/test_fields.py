"""The one fields.h5 reader on a hand-written file in the dolfinx layout."""

import numpy as np
import pytest

from fake_runs import write_fields
from softpack.analysis import fields

h5py = pytest.importorskip("h5py")


def test_snapshot_at_the_nearest_stored_time(tmp_path):
    path = write_fields(tmp_path / "fields.h5", [0.0, 0.0010000000000000002,
                                                 0.003])
    snap = fields.read_snapshot(path, 0.0012)
    assert snap.time == 0.0010000000000000002
    assert snap.points.shape == (4, 2) and snap.cells.shape == (2, 3)
    assert np.allclose(snap.displacement, [[0.001, -0.002]] * 4)
    assert np.allclose(snap.current, snap.points + [0.001, -0.002])
    assert np.allclose(snap.psi, 1.0) and snap.psi.shape == (2,)
    assert list(snap.body) == [0, 1]
    assert np.array_equal(fields.stored_times(path),
                          [0.0, 0.0010000000000000002, 0.003])
    psi, t = fields.read_function(path, "psi", 0.0029)
    assert t == 0.003 and np.allclose(psi, 3.0)


def test_displacements_in_time_order_and_missing_functions(tmp_path):
    path = write_fields(tmp_path / "fields.h5", [0.003, 0.0, 0.001])
    series = fields.read_displacements(path)
    assert [t for t, _ in series] == [0.0, 0.001, 0.003]
    assert np.allclose(series[2][1][:, 1], -0.006)
    points, cells = fields.read_mesh(path)
    assert points.shape == (4, 2) and cells.dtype == np.int64
    with pytest.raises(KeyError, match="no function 'velocity'"):
        fields.read_function(path, "velocity", 0.0)
    with h5py.File(tmp_path / "bare.h5", "w") as f:
        f["Mesh/mesh/geometry"] = np.zeros((3, 2))
        f["Mesh/mesh/topology"] = np.array([[0, 1, 2]])
    with pytest.raises(KeyError, match="displacement"):
        fields.read_snapshot(tmp_path / "bare.h5", 0.0)


def test_a_resumed_runs_killed_part_is_read_beside_its_fields(tmp_path):
    """--resume keeps the killed part's frames in fields.part.h5: the
    readers of fields.h5 see both files' frames; at a time stored in both,
    the resumed driver's (fields.h5) frame is the one read."""
    write_fields(tmp_path / "fields.part.h5", [0.0, 0.001, 0.002])
    path = write_fields(tmp_path / "fields.h5", [0.002, 0.003])
    with h5py.File(path, "a") as f:  # mark the resumed driver's frame
        f["Function/Psi/0_002"][...] = -1.0
    assert np.array_equal(fields.stored_times(path),
                          [0.0, 0.001, 0.002, 0.003])
    assert fields.read_snapshot(path, 0.0011).time == 0.001
    assert np.allclose(fields.read_snapshot(path, 0.0021).psi, -1.0)
    assert [t for t, _ in fields.read_displacements(path)] == [
        0.0, 0.001, 0.002, 0.003]
    psi, t = fields.read_function(path, "Psi", 0.0)
    assert t == 0.0 and np.allclose(psi, 0.0)


def test_an_unreadable_killed_part_is_left_out_with_a_warning(tmp_path):
    (tmp_path / "fields.part.h5").write_bytes(b"not an HDF5 file")
    path = write_fields(tmp_path / "fields.h5", [0.002, 0.003])
    with pytest.warns(UserWarning, match="fields.part.h5: unreadable"):
        assert np.array_equal(fields.stored_times(path), [0.002, 0.003])
