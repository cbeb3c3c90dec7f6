"""The one CSV reader/writer and Eq. 11."""

import math

import numpy as np
import pytest

from softpack.analysis.strain import approach, cumulative_strain
from softpack.contract.tables import read_table, write_table


def test_round_trip_keeps_integers_and_nan(tmp_path):
    columns = {"step": np.array([0, 10, 20]),
               "x": np.array([0.5, math.nan, 1.0 / 3.0])}
    path = write_table(tmp_path / "t.csv", columns)
    assert path.read_text().splitlines() == [
        "step,x", "0,0.5", "10,nan", "20,0.333333333333"]
    table = read_table(path)
    assert list(table) == ["step", "x"]
    assert np.array_equal(table["step"], [0, 10, 20])
    assert np.isnan(table["x"][1]) and table["x"][2] == pytest.approx(1 / 3)
    assert not list(tmp_path.glob(".*tmp*"))  # the temporary file is gone


def test_driver_words_empty_fields_and_short_rows(tmp_path):
    path = tmp_path / "steps.csv"
    path.write_text("step, phi ,converged,extra\n0,,true,1\n5,0.7,false\n")
    table = read_table(path)
    assert list(table) == ["step", "phi", "converged", "extra"]
    assert np.isnan(table["phi"][0]) and table["phi"][1] == 0.7
    assert list(table["converged"]) == [1.0, 0.0]
    assert table["extra"][0] == 1.0 and np.isnan(table["extra"][1])


def test_header_only_and_errors(tmp_path):
    (tmp_path / "h.csv").write_text("a,b\n")
    table = read_table(tmp_path / "h.csv")
    assert table["a"].shape == (0,) and table["b"].shape == (0,)
    (tmp_path / "e.csv").write_text("")
    with pytest.raises(ValueError, match="no header"):
        read_table(tmp_path / "e.csv")
    (tmp_path / "w.csv").write_text("a\nabc\n")
    with pytest.raises(ValueError):
        read_table(tmp_path / "w.csv")
    with pytest.raises(ValueError, match="different lengths"):
        write_table(tmp_path / "x.csv", {"a": [1, 2], "b": [1]})


def test_cumulative_strain_and_its_inverse():
    # eps = -ln(1 - delta/L0): a box shortened to L0/e has eps = 1
    assert cumulative_strain(0.286 * (1 - math.exp(-1.0)), 0.286) \
        == pytest.approx(1.0, rel=1e-14)
    zero = cumulative_strain(0.0, 0.286)
    assert zero == 0.0 and math.copysign(1.0, zero) == 1.0
    eps = np.linspace(0.0, 0.25, 11)
    assert np.allclose(cumulative_strain(approach(eps, 0.02), 0.02), eps,
                       rtol=1e-14, atol=1e-16)
    # small strains: eps ~ delta / L0
    assert cumulative_strain(1e-9, 1.0) == pytest.approx(1e-9, rel=1e-8)
