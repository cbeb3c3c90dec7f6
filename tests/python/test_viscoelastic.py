"""Viscoelastic disks in a run (docs/materials.md, law
viscoelastic_neo_hookean): the 14 disks of examples/viscoelastic_small.toml
compacted by the piston. The energy balance closes with the `viscous`
account, a run resumed from its state (which carries each cell's internal
variables) gives the uninterrupted run's rows bit for bit, and a state
written without internal variables is refused naming them."""

from pathlib import Path

import numpy as np
import pytest

from softpack.simulation import run

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "viscoelastic_small.toml"


def _config(tmp_path, sets, law="viscoelastic_neo_hookean"):
    """The example's first stage alone (the piston at 0.5 m/s), as a run
    without stages, its law `law`."""
    pytest.importorskip("dolfinx")
    from softpack.scene.config import load_config
    from driver_required import require_driver
    require_driver()
    full = EXAMPLE.read_text()
    text = full.split("[[stages]]")[0] + "[contact]" + full.split("[contact]")[1]
    if law != "viscoelastic_neo_hookean":
        lines = [line for line in text.splitlines()
                 if not line.startswith(("branch_", "relaxation_"))]
        text = "\n".join(lines).replace("viscoelastic_neo_hookean", law)
    path = tmp_path / f"{law}.toml"
    path.write_text(text + "\n[stop]\npacking_fraction = 0.78\n")
    return load_config(path, {"output.fields": False, **sets})


@pytest.fixture(scope="module")
def compacted(tmp_path_factory):
    from softpack.contract.tables import read_table
    base = tmp_path_factory.mktemp("viscoelastic")
    out = base / "whole"
    assert run.run(_config(base, {"stop.steps": 200}), out,
                   verbose=False) == 0
    return read_table(out / "raw" / "steps.csv")


def test_the_energy_balance_closes_with_the_viscous_account(compacted):
    steps = compacted
    supplied = np.abs(np.asarray(steps["wall_work"]))
    residual = np.abs(np.asarray(steps["energy_residual"]))
    viscous = np.asarray(steps["viscous"])
    assert viscous[-1] > 0.05 * supplied[-1]  # the branches dissipate
    assert np.all(np.diff(viscous) >= 0)
    # measured 2026-12-03: viscous 0.277 of a wall work of 2.72 J/m at step
    # 200; |residual| at most 1.3e-4 of the wall work (9.3e-5 at the end),
    # where the same run with neo_hookean closes to 1.1e-4 (1.9e-5): the
    # theta scheme's third-order remainder, not a missing account
    assert np.all(residual[1:] <= 2e-4 * supplied[1:] + 1e-9)


def test_a_resumed_run_gives_the_same_bits(tmp_path, compacted):
    from softpack.contract.tables import read_table
    part = tmp_path / "part"
    assert run.run(_config(tmp_path, {"stop.steps": 70}), part,
                   verbose=False) == 0
    for name in ("series.csv", "particles.csv", "raw/done.json"):
        (part / name).unlink()
    toml = part / "config.toml"
    toml.write_text(toml.read_text().replace("steps = 70", "steps = 200"))
    assert run.main(["--resume", str(part)]) == 0
    a, b = compacted, read_table(part / "raw" / "steps.csv")
    assert a.keys() == b.keys() and len(a["step"]) == len(b["step"])
    for column in a:
        if not column.startswith("seconds"):
            np.testing.assert_array_equal(a[column], b[column],
                                          err_msg=column)


def test_a_state_without_internal_variables_is_refused(tmp_path):
    plain = tmp_path / "plain"
    assert run.run(_config(tmp_path, {"stop.steps": 20}, law="neo_hookean"),
                   plain, verbose=False) == 0
    with pytest.raises(Exception) as err:
        run.run(_config(tmp_path, {"stop.steps": 40}), tmp_path / "visco",
                verbose=False, initial_state=plain / "raw" / "state.bin")
    assert "internal_variables" in str(err.value)


@pytest.mark.parametrize("key, bad", [("relaxation_time_1 = 0.01", "0.0"),
                                      ("branch_ratio_2 = 0.5", "-0.1")])
def test_a_parameter_out_of_range_is_refused_naming_it(tmp_path, key, bad):
    from softpack.scene.config import ConfigError, load_config
    name = key.split(" = ")[0]
    path = tmp_path / "bad.toml"
    path.write_text(EXAMPLE.read_text().replace(key, f"{name} = {bad}"))
    with pytest.raises(ConfigError) as err:
        load_config(path)
    assert f"[material.parameters] {name} = {bad}" in str(err.value)
