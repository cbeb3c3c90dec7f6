"""The steady state of a shear (softpack.analysis.steady_shear,
``./softpack plot-shear``; docs/bulk_shear.md).

The statistics on synthetic series whose answers are known: the batch-means
error of independent noise is sigma / sqrt(n) (within its own scatter), a
correlated series' error is larger than the naive one, a stationary series
is called stationary and a drifting one is not. End to end,
examples/shear_small.toml to gamma 0.6: the window is the last half of the
shear, its mean mu* and Phi are those of the rows, and the figure and
tables are written by the command and its Python twin.
"""

import json

import numpy as np
import pytest

from driver_required import require_driver
from softpack import api
from softpack.analysis import steady_shear
from softpack.contract.run_directory import RunError
from softpack.contract.tables import read_table
from softpack.plots import shear
from softpack.scene.config import load_config
from softpack.simulation.run import run

from test_servo_cell import EXAMPLE


def test_batch_error_of_independent_noise_is_sigma_over_sqrt_n():
    rng = np.random.default_rng(3)
    errors = [steady_shear.batch_error(rng.normal(0, 2.0, 600))
              for _ in range(200)]
    # sigma / sqrt(n) = 0.0816; the batch estimate scatters about it
    assert np.mean(errors) == pytest.approx(2.0 / np.sqrt(600), rel=0.1)


def test_correlated_rows_get_a_larger_error_than_the_naive_one():
    rng = np.random.default_rng(4)
    walk = np.convolve(rng.normal(0, 1, 700), np.ones(40) / 40, "valid")
    naive = walk.std(ddof=1) / np.sqrt(len(walk))
    assert steady_shear.batch_error(walk) > 3 * naive


def test_stationary_and_drifting_series():
    rng = np.random.default_rng(5)
    gamma = np.linspace(0.5, 1.0, 300)
    flat = steady_shear.statistic(gamma, 0.3 + rng.normal(0, 0.05, 300))
    assert flat.stationary
    assert flat.mean == pytest.approx(0.3, abs=0.02)
    assert flat.fluctuation == pytest.approx(0.05, rel=0.15)
    rising = steady_shear.statistic(gamma, 0.3 + 1.0 * (gamma - 0.5)
                                    + rng.normal(0, 0.05, 300))
    assert not rising.stationary
    assert rising.drift == pytest.approx(0.5, rel=0.1)


def test_too_few_rows_are_refused():
    with pytest.raises(RunError, match="too few"):
        steady_shear.statistic(np.linspace(0, 1, 5), np.ones(5))


@pytest.fixture(scope="module")
def sheared(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("steady") / "shear"
    config = load_config(EXAMPLE, {"stop.max_time": 0.3,
                                   "output.every_steps": 20})
    assert run(config, out, verbose=False) == 0
    return out


def test_the_window_is_the_last_half_of_the_shear(sheared):
    state = steady_shear.steady_state(sheared)
    st = read_table(sheared / "stress.csv")
    gamma = np.asarray(st["gamma"])
    assert state.gamma_window[1] == pytest.approx(0.6, rel=1e-6)
    assert state.gamma_window[0] >= 0.3 - 1e-12
    rows = gamma >= 0.3 - 1e-12
    assert state.rows == rows.sum()
    assert state.stats["mu_star"].mean == pytest.approx(
        np.nanmean(np.asarray(st["mu_star"])[rows]))
    assert state.shear_rate == pytest.approx(2.0, rel=1e-9)
    # the example's balance (docs/periodic_cell.md: 2.2e-4 over 1.1)
    assert state.balance < 5e-4


def test_plot_shear_writes_the_figure_and_tables(sheared, tmp_path):
    out = tmp_path / "figs"
    assert shear.main([str(sheared), str(sheared), "--out", str(out)]) == 0
    summary = json.loads((out / "steady.json").read_text())
    assert (out / "shear.png").stat().st_size > 0
    assert (out / "shear.pdf").stat().st_size > 0
    (pair,) = summary["pairs"]
    assert pair["difference"] == 0.0 and pair["within_fluctuation"]
    assert "mu*" in (out / "steady.md").read_text()
    twin = api.plot_shear([sheared], out=tmp_path / "api")
    assert twin["runs"][0]["rows"] == summary["runs"][0]["rows"]


def test_a_run_without_shear_is_refused(tmp_path):
    (tmp_path / "raw").mkdir()
    assert shear.main([str(tmp_path)]) == 2
