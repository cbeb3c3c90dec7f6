"""``./softpack plot-plane-strain`` on docs/paper's per-seed CSVs: the
reading of a seed's constants, the interpolation of its tables, and the
refusal of a path it cannot read (the 3D side: test_run_3d_observables.py)."""

from pathlib import Path

import numpy as np
import pytest

from softpack.contract.tables import read_table
from softpack.plots import plane_strain

SEEDS = Path(__file__).resolve().parents[2] / "docs" / "paper" / "seeds"


def test_a_seed_csv_reads_with_its_constants():
    curve = plane_strain.read_curve("2D", SEEDS / "phi0748-seed0.csv")
    s = read_table(SEEDS / "phi0748-seed0.csv")
    # runs.csv: H 15 mm
    np.testing.assert_allclose(curve.force, s["piston_force"] / 0.015,
                               rtol=1e-15)
    # E/(W H L mu) is also a column of the seed's own series (W 202 mm,
    # L 286 mm, mu 0.15 MPa): its 7 digits
    ok = s["E_over_WHLmu"] > 1e-5
    np.testing.assert_allclose(curve.energy[ok] / (0.202 * 0.286 * 0.15e6),
                               s["E_over_WHLmu"][ok], rtol=1e-6)


def test_the_tables_interpolate_between_rows_and_a_run_is_its_own_unit():
    curve = plane_strain.read_curve("a", SEEDS / "phi0748-seed0.csv")
    k = int(np.flatnonzero(curve.phi >= 0.84)[0])
    mid = 0.5 * (curve.phi[k - 1] + curve.phi[k])
    assert plane_strain.interpolated(curve, curve.force, "phi", mid) == \
        pytest.approx(0.5 * (curve.force[k - 1] + curve.force[k]))
    assert np.isnan(plane_strain.interpolated(curve, curve.force, "phi",
                                              0.95))
    lines = plane_strain.table([curve, curve], "eps", [0.1, 0.2])
    ratios = [row.split("|")[-3:-1] for row in lines[2:]]
    assert all(float(r) == 1.0 for row in ratios for r in row)


def test_a_path_that_is_neither_a_run_nor_a_seed_is_refused(tmp_path):
    (tmp_path / "x.txt").write_text("")
    with pytest.raises(plane_strain.PlaneStrainError, match="x.txt"):
        plane_strain.read_curve("x", tmp_path / "x.txt")
    (tmp_path / "orphan.csv").write_text("phi\n0.7\n")
    with pytest.raises(plane_strain.PlaneStrainError, match="runs.csv"):
        plane_strain.read_curve("x", tmp_path / "orphan.csv")
