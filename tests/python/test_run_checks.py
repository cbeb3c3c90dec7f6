"""Issue 16 item 4 through the real driver: a run whose solves do not
converge is marked as not converged in ``raw/done.json``, in
``series.csv`` (steps since the previous row, so that no step is unseen)
and in the summary line.
"""

import json
import os
from pathlib import Path

import numpy as np
import pytest

from softpack.contract.tables import read_table
from softpack.contract.run_directory import EXIT_FLAGGED
from softpack.scene import config as cfg
from softpack.simulation.run import run
from driver_required import require_driver

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))


def test_unconverged_steps_reach_series_and_summary(tmp_path, capsys):
    require_driver()
    config = cfg.load_config(ROOT / "examples" / "small.toml")
    config["time"]["newton_max_iterations"] = 1
    config["stop"]["steps"] = 30
    out = tmp_path / "run"
    assert run(config, out) == EXIT_FLAGGED  # finished, flagged
    done = json.loads((out / "raw" / "done.json").read_text())
    assert done["converged"] is False
    assert done["newton_unconverged_steps"] > 0
    s = read_table(out / "series.csv")
    # Every unconverged step is in some row, though 27 of 30 are no row.
    assert len(s["step"]) == 4
    assert np.nansum(s["newton_unconverged_steps"]) == \
        done["newton_unconverged_steps"]
    assert np.nansum(s["nlgs_unconverged_steps"]) == \
        done["nlgs_unconverged_steps"]
    assert np.all(s["max_overlap_depth"] >= 0)
    printed = capsys.readouterr()
    assert "marked as not converged" in printed.out + printed.err
    assert "Newton did not converge" in (out / "run.log").read_text()


def test_max_penetration_is_bounded_by_the_element_size_and_the_step():
    """Issue 16 item 5: 1e-9 m let bodies pass through each other unseen."""
    from softpack.scene.config import ConfigError
    small = ROOT / "examples" / "small.toml"  # h = 3 mm, piston 0.1 m/s
    with pytest.raises(ConfigError, match=r"\[contact\] max_penetration ="
                       r" 1e-09: must be >= 0.0003 m \(0.1 x \[mesh\]"
                       r" element_size"):
        cfg.load_config(small, {"contact.max_penetration": 1e-9})
    # h / 10 is accepted ...
    cfg.load_config(small, {"contact.max_penetration": 3e-4})
    # ... unless a wall moves farther in one step (1 m/s x 7.2e-4 s).
    with pytest.raises(ConfigError, match=r"max_penetration = 0.0003: must"
                       r" be >= 0.00072 m \(the travel of \[walls.right\]"):
        cfg.load_config(small, {"contact.max_penetration": 3e-4,
                                "contact.alert_distance": 1e-3,
                                "walls.right.velocity": [-1.0, 0.0],
                                "time.time_step": 7.2e-4})
