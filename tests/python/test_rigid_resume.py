"""Rigid bodies resumed (docs/materials.md, "Rigid particles"): a run of
rigid and soft particles killed at an output step and finished with
``--resume`` is the uninterrupted run bit for bit, in 2D (three degrees of
freedom a body: the state carries its centre, angle and velocities) and in
3D (six: its centre, orientation and velocities). Every column of
raw/steps.csv but the wall-clock seconds, and raw/particles.csv byte for
byte."""

import json
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from killed_run import as_killed, assert_same_rows
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.simulation.run import main, run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: The examples' first steps, cut halfway at an output step: both have
#: rigid bodies in contact (pushed by the piston or by soft neighbours)
#: well before the cut, so the state's rigid part is what the resumed
#: steps read.
CASES = {"mixture_small.toml": (200, 100), "mixture3d_small.toml": (240, 120)}


def _rigid_moved_by(out, step):
    """The largest distance a rigid body's centroid moved from step 0 to
    `step` (m): the state's rigid part is not the initial one."""
    setup = json.loads((out / "raw" / "setup.json").read_text())
    rigid = [i for i, s in enumerate(setup["scene"]["species"])
             if s["material"] == "rigid"]
    bodies = [b for b, s in enumerate(setup["bodies"]["species"])
              if s in rigid]
    p = read_table(out / "raw" / "particles.csv")
    axes = [k for k in ("centroid_x", "centroid_y", "centroid_z") if k in p]
    at = {t: np.stack([p[k][p["step"] == t] for k in axes], axis=1)[bodies]
          for t in (0, step)}
    return float(np.linalg.norm(at[step] - at[0], axis=1).max())


@pytest.mark.parametrize("example", sorted(CASES))
def test_a_killed_rigid_run_resumed_is_the_uninterrupted_run(example,
                                                             tmp_path):
    require_driver()
    steps, cut = CASES[example]
    sets = {"output.every_steps": 20, "output.fields": False}
    whole, part = tmp_path / "whole", tmp_path / "part"
    status = run(cfg.load_config(EXAMPLES / example,
                                 {**sets, "stop.steps": steps}),
                 whole, verbose=False)
    run(cfg.load_config(EXAMPLES / example, {**sets, "stop.steps": cut}),
        part, verbose=False)
    as_killed(part, cut, steps)
    assert main(["--resume", str(part)]) == status
    assert _rigid_moved_by(whole, cut) > 1e-4
    a = read_table(whole / "raw" / "steps.csv")
    assert_same_rows(a, read_table(part / "raw" / "steps.csv"))
    assert ((whole / "raw" / "particles.csv").read_bytes()
            == (part / "raw" / "particles.csv").read_bytes())
