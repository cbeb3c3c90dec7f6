"""Issue 16 item 10: fields.xdmf is one temporal collection that meshio's
time-series reader (and ParaView) read at every step with every field:
the displacement at the nodes, Psi and the particle id on the cells.

The values meshio reads through the XML are checked against the HDF5
datasets read by softpack.analysis.fields (dolfinx's layout), and the
steps against the output rows of raw/steps.csv.
"""

import os
from pathlib import Path

import numpy as np
import pytest

from softpack.analysis import fields
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.simulation.run import run
from driver_required import require_driver

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
meshio = pytest.importorskip("meshio")


@pytest.fixture(scope="module")
def fields_run(tmp_path_factory):
    require_driver()
    config = cfg.load_config(ROOT / "examples" / "small.toml")
    config["stop"]["steps"] = 20
    config["output"]["fields_every"] = 1
    out = tmp_path_factory.mktemp("fields") / "run"
    assert run(config, out, verbose=False) == 0
    return out


def test_meshio_reads_every_field_at_every_step(fields_run):
    h5 = fields_run / "fields.h5"
    steps = read_table(fields_run / "raw" / "steps.csv")
    bodies = read_table(fields_run / "raw" / "particles.csv")
    with meshio.xdmf.TimeSeriesReader(fields_run / "fields.xdmf") as reader:
        points, cells = reader.read_points_cells()
        assert [c.type for c in cells] == ["triangle"]
        assert reader.num_steps == len(steps["step"]) == 3
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            assert t == pytest.approx(steps["time"][k], abs=1e-15)
            u, stored = fields.read_function(h5, "displacement", t)
            assert stored == t
            np.testing.assert_array_equal(
                point_data["displacement"][:, :2], u)
            assert point_data["displacement"].shape == (len(points), 3)
            psi = cell_data["Psi"][0].reshape(-1)
            np.testing.assert_array_equal(
                psi, fields.read_function(h5, "Psi", t)[0])
            ids = cell_data["particle"][0].reshape(-1)
            assert len(ids) == len(cells[0].data)
            assert set(ids) == set(bodies["particle"])
        # The piston moved: the last step's displacement is not zero.
        assert np.abs(point_data["displacement"]).max() > 1e-4


def test_later_steps_include_the_first_steps_mesh(fields_run):
    """ParaView resolves the xi:include (libxml2, as lxml does here)."""
    etree = pytest.importorskip("lxml.etree")
    tree = etree.parse(str(fields_run / "fields.xdmf"))
    tree.xinclude()
    grids = tree.getroot().findall("Domain/Grid/Grid")
    assert len(grids) == 3
    for grid in grids:
        assert [c.tag for c in grid][:2] == ["Topology", "Geometry"]



def test_the_fields_end_with_the_final_state(tmp_path):
    """Fields every 2nd output of rows at steps 0, 10, 20 and 25 (the run
    stops there): frames at steps 0 and 20, and at 25, the last output,
    whatever fields_every says."""
    require_driver()
    config = cfg.load_config(ROOT / "examples" / "small.toml",
                             {"stop.steps": 25, "output.every_steps": 10,
                              "output.fields_every": 2})
    out = tmp_path / "run"
    assert run(config, out, verbose=False) == 0
    steps = read_table(out / "raw" / "steps.csv")
    assert list(steps["step"]) == [0, 10, 20, 25]
    np.testing.assert_allclose(
        fields.stored_times(out / "fields.h5"),
        steps["time"][[0, 2, 3]], rtol=1e-12)
