"""Loading stages ([[stages]], docs/loading.md; issue 12 item 2; a stage's
friction, issue 38 item 4).

Validation: a wall driven two ways in a stage, unknown walls and keys, a
stage without a time bound and a global Phi target with stages are refused
in one line naming the file and the key; derived bounds and the resolved
TOML. End to end on the 14-disk box of examples/isotropic_small.toml: the
pressure on the right and top servo walls stepped from 4 to 8 kPa, then the
walls stopped (velocity control): the steps.csv stage column switches, at
the end of the 8 kPa stage (at rest) each servo wall holds 8 kPa within
1 %, and the energy balance closes across the stage changes; a stage that
cannot meet its criterion ends the run, incomplete, naming it.
"""

import json
import os
import tomllib
from pathlib import Path

import numpy as np
import pytest

from softpack.contract.run_directory import EXIT_FLAGGED
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.simulation.run import RunError, run
from driver_required import require_driver

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
SERVO = {"right": {"control": "pressure", "pressure": 4e3},
         "top": {"control": "pressure", "pressure": 4e3}}


def stages_config(stages, walls=SERVO, stop=None):
    return {"walls": walls, "stages": stages, **({"stop": stop} if stop
                                                 else {})}


@pytest.mark.parametrize("stage, key", [
    ({"walls": {"right": {"control": "velocity", "pressure": 1e3}}},
     r"a.toml: \[stages.0\] walls.right.pressure = 1000.0: the wall is under"
     r" control = \"velocity\""),
    ({"walls": {"right": {"control": "pressure", "pressure": 1e3,
                          "velocity": [-0.1, 0.0]}}},
     r"\[stages.0\] walls.right.velocity"),
    ({"walls": {"right": {"velocity": [-0.1, 0.0], "force": 5.0}}},
     r"\[stages.0\] walls.right.force"),
    # a key of another drive is refused even at 0 (the schema's [stages])
    ({"walls": {"right": {"control": "pressure", "pressure": 1e3,
                          "velocity": [0.0, 0.0]}}},
     r"\[stages.0\] walls.right.velocity = \[0.0, 0.0\]: the wall is under"),
    ({"walls": {"right": {"control": "pressure"}}},
     r"\[stages.0\] walls.right.pressure missing"),
    ({"walls": {"lid": {"velocity": [0.0, -0.1]}}},
     r"\[stages.0\] walls.lid: unknown wall \(walls: left, right"),
    ({"walls": {"right": {"pressur": 1e3}}},
     r"unknown key \[stages.0.walls.right\] pressur"),
    ({"stop": {"strainn": 0.1, "max_time": 1.0}},
     r"unknown key \[stages.0.stop\] strainn \(allowed: packing_fraction"),
    ({"stopp": {"max_time": 1.0}}, r"unknown key \[stages.0\] stopp"),
    ({"stop": {"equilibrium": 1e-3}}, r"\[stages.0\] stop.max_time missing"),
    ({"stop": {"strain": 0.1, "max_time": 1.0}},
     r"\[stages.0\] stop.strain = 0.1: the stage has no moving"),
    ({"stop": {"equilibrium": 2.0, "max_time": 1.0}},
     r"\[stages.0\] stop.equilibrium = 2.0: must be in \[0, 1\)"),
    ({"walls": {"right": {"velocity": [-50.0, 0.0]}}},
     r"\[stages.0\] walls.right.velocity = \[-50.0, 0.0\]: moves"),
])
def test_bad_stages_are_refused_naming_the_key(stage, key):
    with pytest.raises(cfg.ConfigError, match=key) as err:
        cfg.validate(stages_config([stage]), "a.toml")
    assert "\n" not in str(err.value)


def test_a_global_phi_target_or_short_bound_is_refused_with_stages():
    stage = {"stop": {"equilibrium": 1e-3, "max_time": 0.2}}
    with pytest.raises(cfg.ConfigError,
                       match=r"\[stop\] packing_fraction = 0.8: must be 0"):
        cfg.validate(stages_config([stage], stop={"packing_fraction": 0.8}),
                     "a.toml")
    with pytest.raises(cfg.ConfigError,
                       match=r"\[stop\] max_time = 0.1: must be >= 0.2"):
        cfg.validate(stages_config([stage], stop={"max_time": 0.1}),
                     "a.toml")


def test_derived_bounds_and_the_resolved_toml():
    c = cfg.validate(stages_config([
        {"name": "hold", "stop": {"equilibrium": 1e-3, "max_time": 0.2}},
        {"walls": {"right": {"velocity": [-0.1, 0.0]}},
         "stop": {"strain": 0.1}},
    ]), "a.toml")
    first, second = c["stages"]
    assert first["name"] == "hold" and first["walls"] == {}
    assert second["name"] == "stage1"
    assert second["walls"] == {"right": {"control": "velocity",
                                         "velocity": [-0.1, 0.0],
                                         "pressure": 0.0, "force": 0.0}}
    # derived: the strain of the moving wall, half the box at its speed
    assert second["stop"]["strain_wall"] == "right"
    assert second["stop"]["max_time"] == pytest.approx(
        c["box"]["length"] / (2 * 0.1))
    assert c["stop"]["packing_fraction"] == 0.0
    assert c["stop"]["max_time"] == pytest.approx(
        0.2 + second["stop"]["max_time"])
    # walls not named keep their drive; the top wall is still a servo wall
    again = cfg.validate(tomllib.loads(cfg.to_toml(c)), "b.toml")
    assert again["stages"] == c["stages"] and again["stop"] == c["stop"]


def test_no_stages_is_one_stage_from_walls_and_stop():
    c = cfg.load_config(ROOT / "examples" / "paper.toml")
    assert c["stages"] == []
    assert c["stop"]["packing_fraction"] == 0.88


def small_config(stages, **sections):
    with open(ROOT / "examples" / "isotropic_small.toml", "rb") as f:
        data = tomllib.load(f)
    data.pop("stop")
    data["stages"] = stages
    data["output"]["fields"] = False
    data.update(sections)
    return cfg.validate(data, "isotropic_small+stages")


@pytest.fixture(scope="module")
def stepped_run(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("stages") / "run"
    # equilibrium 5e-3: a servo wall then ends its stage within 0.5 % of
    # its load at the last step, so its force averaged over the output
    # interval is within the 1 % asserted below
    config = small_config([
        {"name": "p4k", "stop": {"equilibrium": 5e-3, "max_time": 0.15}},
        {"name": "p8k",
         "walls": {"right": {"pressure": 8e3}, "top": {"pressure": 8e3}},
         "stop": {"equilibrium": 5e-3, "max_time": 0.15}},
        # the servo walls stopped (velocity control): their kinetic energy
        # leaves the accounts and wall_work with them
        {"name": "stop", "walls": {"right": {"control": "velocity"},
                                   "top": {"control": "velocity"}},
         "stop": {"max_time": 0.005}},
    ])
    assert run(config, out) == 0
    return out


def test_the_stage_column_switches_and_the_run_is_complete(stepped_run):
    steps = read_table(stepped_run / "raw" / "steps.csv")
    stage = np.asarray(steps["stage"])
    assert stage[0] == 0 and stage[-1] == 2
    assert np.all(np.diff(stage) >= 0) and set(stage) == {0, 1, 2}
    done = json.loads((stepped_run / "raw" / "done.json").read_text())
    assert done["reason"] == "stages" and done["complete"] is True
    assert done["stage"] == 2 and done["stage_name"] == "stop"
    assert done["ended_by"] == ["equilibrium", "equilibrium", "max_time"]


def test_a_servo_wall_holds_its_new_pressure_at_rest(stepped_run):
    steps = read_table(stepped_run / "raw" / "steps.csv")
    last = np.flatnonzero(np.asarray(steps["stage"]) == 1)[-1]
    width = steps["top_y"][last] - steps["bottom_y"][last]
    length = steps["right_x"][last] - steps["left_x"][last]
    # the force the walls received (averaged over the output interval;
    # measured 2026-12-03: +0.40 % right, -0.07 % top, the equilibrium
    # criterion 5e-3 allowing 0.5 %)
    assert steps["right_fx"][last] / width == pytest.approx(8e3, rel=0.01)
    assert steps["top_fy"][last] / length == pytest.approx(8e3, rel=0.01)
    # and it moved: the assembly was compacted further than at 4 kPa
    end4 = np.flatnonzero(np.asarray(steps["stage"]) == 0)[-1]
    assert steps["phi"][last] > steps["phi"][end4] + 1e-3


def test_the_energy_balance_closes_across_stage_changes(stepped_run):
    """At every output row: measured 2026-12-03 at most 2.0e-5 of the final
    work and 3.4e-5 of the work done so far (the first row has no work and
    a zero residual)."""
    steps = read_table(stepped_run / "raw" / "steps.csv")
    work = steps["wall_work"]
    residual = np.abs(steps["energy_residual"])
    assert work[-1] > 0 and work[0] == 0
    assert np.max(residual) < 2e-4 * work[-1]
    done = work > 0
    assert done.sum() == len(work) - 1
    assert np.all(residual[done] < 3.5e-4 * work[done]), \
        (residual[done] / work[done]).max()


def test_a_stage_that_cannot_meet_its_criterion_ends_the_run(tmp_path):
    require_driver()
    config = small_config([
        {"name": "settle", "stop": {"equilibrium": 1e-9, "max_time": 0.01}},
        {"name": "never", "stop": {"max_time": 0.01}},
    ])
    out = tmp_path / "run"
    assert run(config, out) == EXIT_FLAGGED  # finished, incomplete
    done = json.loads((out / "raw" / "done.json").read_text())
    assert done["complete"] is False and done["stage"] == 0
    assert done["reason"].startswith(
        'stage 0 "settle" reached its max_time 0.01 s before equilibrium')
    steps = read_table(out / "raw" / "steps.csv")
    assert set(np.asarray(steps["stage"])) == {0}  # "never" never began
    assert steps["time"][-1] == pytest.approx(0.01)
    log = "".join(p.read_text() for p in out.glob("*.log"))
    assert 'stage 0 "settle" reached its max_time' in log
    assert "the run ends incomplete" in log
    assert "WARNING: incomplete: the run ended in stage 0 'settle'" in log


def test_a_run_continued_from_a_state_inside_a_stage_is_the_same(
        stepped_run, tmp_path):
    """The stage record next to raw/state.bin carries the stage: a run cut
    inside the 8 kPa stage ([stop] steps) and continued from its state ends
    where the uninterrupted one does, bit for bit."""
    whole = read_table(stepped_run / "raw" / "steps.csv")
    stages = cfg.load_config(stepped_run / "config.toml")["stages"]
    data, cut_at, first, rest, steps = _cut_and_continue(stepped_run, 1,
                                                         tmp_path)
    done = json.loads((first / "raw" / "done.json").read_text())
    assert done["reason"] == "steps" and done["complete"] is False
    record = json.loads((first / "raw" / "state.stage.json").read_text())
    assert record["stage"] == 1 and record["step"] == cut_at
    assert record["ended_by"] == done["ended_by"] == ["equilibrium"]
    for key in ("right_x", "top_y", "wall_work", "energy_residual", "stage"):
        assert steps[key][-1] == whole[key][-1], key
    assert cfg.load_config(rest / "config.toml")["stages"] == stages
    # the stages ended before the cut are named after it too
    assert json.loads((rest / "raw" / "done.json").read_text())[
        "ended_by"] == json.loads((stepped_run / "raw" / "done.json")
                                  .read_text())["ended_by"]
    # without the record a staged run refuses to continue
    lone = tmp_path / "lone"
    lone.mkdir()
    (lone / "state.bin").write_bytes((first / "raw" / "state.bin")
                                     .read_bytes())
    with pytest.raises(RunError):
        run(cfg.validate(data, "lone"), tmp_path / "lone-run",
            initial_state=lone / "state.bin")
    log = "".join(p.read_text() for p in (tmp_path / "lone-run").glob("*.log"))
    assert "state.stage.json: missing" in log


def test_a_stage_friction_is_validated_and_kept_by_the_next_stages():
    c = cfg.validate(stages_config([
        {"contact": {"friction": 0.0},
         "stop": {"equilibrium": 1e-3, "max_time": 0.2}},
        {"stop": {"max_time": 0.1}},
        {"contact": {"friction": 0.5}, "stop": {"max_time": 0.1}},
    ]), "a.toml")
    assert [s["contact"]["friction"] for s in c["stages"]] == [0.0, 0.0, 0.5]
    assert c["contact"]["friction"] == 0.3  # the run's own stays
    first = cfg.validate(stages_config([{"stop": {"max_time": 0.1}}]), "b")
    assert first["stages"][0]["contact"]["friction"] == 0.3
    for table, match in [({"friction": -0.1}, r"a.toml: \[stages.0\]"
                          r" contact.friction = -0.1: must be >= 0"),
                         ({"frictio": 0.1}, r"unknown key"
                          r" \[stages.0.contact\] frictio"),
                         (0.2, r"\[stages.0\] contact must be a table")]:
        with pytest.raises(cfg.ConfigError, match=match):
            cfg.validate(stages_config([{"contact": table,
                                         "stop": {"max_time": 0.1}}]),
                         "a.toml")


FRICTION_STAGES = [
    {"name": "frictionless", "contact": {"friction": 0.0},
     "stop": {"max_time": 0.1}},
    {"name": "pushed", "contact": {"friction": 0.5},
     "walls": {"right": {"velocity": [-0.05, 0.0]}},
     "stop": {"max_time": 0.03}},
]


@pytest.fixture(scope="module")
def friction_run(tmp_path_factory):
    """A preparation protocol in small: consolidated without friction at
    4 kPa, then pushed by the right wall with friction 0.5 ([contact]
    friction 0.3)."""
    require_driver()
    out = tmp_path_factory.mktemp("stages") / "friction"
    assert run(small_config(FRICTION_STAGES), out) == 0
    return out


def test_each_stage_solves_contacts_with_its_own_friction(friction_run,
                                                         tmp_path):
    """No frictional dissipation while loaded contacts slide without
    friction; dissipation once friction is on; and the value the stage
    sets is the one used: the same program under [contact] friction 0.5
    gives the same raw steps, bit for bit."""
    steps = read_table(friction_run / "raw" / "steps.csv")
    stage = np.asarray(steps["stage"])
    dissipated = np.asarray(steps["friction"])
    assert np.all(dissipated[stage == 0] == 0)
    assert np.max(np.asarray(steps["contacts"])[stage == 0]) > 0
    assert np.asarray(steps["wall_work"])[stage == 0][-1] > 0
    assert dissipated[-1] > 1e-3 * steps["wall_work"][-1]
    other = tmp_path / "contact-0.5"
    config = small_config(FRICTION_STAGES)
    config["contact"]["friction"] = 0.5
    assert run(config, other) == 0
    again = read_table(other / "raw" / "steps.csv")
    for key in steps:
        if not key.startswith("seconds"):
            assert np.array_equal(np.asarray(again[key]),
                                  np.asarray(steps[key])), key


def _cut_and_continue(run_dir, stage, tmp_path):
    """The run's program cut in the middle of ``stage`` ([stop] steps) and
    continued from the cut's state: (the program, the step cut at, the cut
    run, the continued run, its steps), the continued run ending at the
    uninterrupted one's last step."""
    whole = read_table(run_dir / "raw" / "steps.csv")
    inside = np.flatnonzero(np.asarray(whole["stage"]) == stage)
    cut_at = int(whole["step"][inside[len(inside) // 2]])
    data = tomllib.loads(cfg.to_toml(cfg.load_config(run_dir /
                                                     "config.toml")))
    data["stop"]["steps"] = cut_at
    first = tmp_path / "first"
    assert run(cfg.validate(data, "cut"), first) == EXIT_FLAGGED
    data["stop"]["steps"] = 0
    rest = tmp_path / "rest"
    assert run(cfg.validate(data, "rest"), rest,
               initial_state=first / "raw" / "state.bin") == 0
    steps = read_table(rest / "raw" / "steps.csv")
    assert steps["step"][-1] == whole["step"][-1]
    return data, cut_at, first, rest, steps


def test_a_run_continued_inside_a_friction_stage_is_the_same(friction_run,
                                                             tmp_path):
    whole = read_table(friction_run / "raw" / "steps.csv")
    steps = _cut_and_continue(friction_run, 1, tmp_path)[-1]
    for key in ("right_x", "top_y", "wall_work", "friction",
                "energy_residual"):  # friction: the stage's 0.5 restored
        assert steps[key][-1] == whole[key][-1], key
