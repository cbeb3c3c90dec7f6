"""``./softpack run`` end to end with a fake ``softpack-simulate``.

The fake driver (a Python script written below) follows docs/contract.md
(sections 4-5): it reads driver.json (schema version 2) and the mesh's body
table, writes raw/setup.json, moves the piston (wall "right") at the given
speed, writes raw/steps.csv, raw/particles.csv, raw/contacts/ and finally
raw/done.json. Every particle is held between the bottom and top
walls by two nodes each (balanced), so Z = 2 (walls only).
"""

import math
import os
from pathlib import Path

import pytest

from material_registry import use_registry
from softpack import paths
from softpack.analysis import observables
from softpack.simulation import run
from softpack.scene.mesh import MeshInfo, output_paths

SMALL = Path(__file__).resolve().parents[2] / "examples" / "small.toml"

FAKE_DRIVER = r'''#!/usr/bin/python3
import json, os, struct, sys, time
from pathlib import Path

if sys.argv[1] == "--state-info":  # the layout written below
    head = open(sys.argv[2], "rb").read(56)
    if head[:16] != b"softpack-state-1":
        sys.exit("softpack-simulate: %s: not a softpack state file"
                 % sys.argv[2])
    print(json.dumps({"step": struct.unpack("<q", head[48:56])[0]}))
    sys.exit(0)
doc = json.load(open(sys.argv[1]))
assert doc["schema_version"] == 2
out = Path(doc["directory"])
raw = out / "raw"
(raw / "contacts").mkdir(parents=True, exist_ok=True)
bodies = doc["scene"]["bodies"]
lines = open(bodies["mesh"][:-len(".xdmf")] + ".bodies.csv").read().split()
areas = [float(line.split(",")[4]) for line in lines[1:]]
walls = doc["walls"]
assert [w["name"] for w in walls[:4]] == ["left", "right", "bottom", "top"]
json.dump({"schema_version": 2, "units": {}, "scene": doc["scene"],
           "material": doc["material"], "walls": walls,
           "parameters": {k: doc[k] for k in
                          ("stop", "contact", "time", "damping", "output",
                           "parallel")},
           "initial_state": doc["initial_state"],
           "bodies": {"count": len(areas), "species": bodies["species"],
                      "reference_area": areas, "nodes": [], "triangles": []}},
          open(raw / "setup.json", "w"))
speed = walls[1]["velocity"][0]
h, every = doc["time"]["time_step"], doc["output"]["every_steps"]
length, width = walls[1]["point"][0], walls[3]["point"][1]
mode = os.environ.get("FAKE_DRIVER", "ok")
if mode == "slow":  # a long run (0.2 s a step): its pid for kill tests
    open(out / "driver.pid", "w").write(str(os.getpid()))
print("fake driver: %d bodies" % len(areas), flush=True)
energies = "strain_energy,kinetic_energy,wall_work,external_work,damping,"\
    "friction,contact_normal,numerical,energy_residual"
head = "step,time,newton_iterations,nlgs_iterations,nlgs_error,"\
    "nlgs_converged,contacts,active_contacts,max_penetration," + "".join(
        "%s_x,%s_y,%s_fx,%s_fy," % ((w["name"],) * 4) for w in walls) \
    + "phi," + energies + ",seconds\n"
steps = open(raw / "steps.csv", "w")
parts = open(raw / "particles.csv", "w")
steps.write(head)
parts.write("step,particle,area,strain_energy,reference_area\n")
step = 0
if doc["initial_state"]:  # the state file's layout: driver/io/state_file.h
    step = struct.unpack("<q", open(doc["initial_state"], "rb").read(56)[48:])[0]
resumed_at = step if doc["initial_state"] else None
while True:
    t = step * h
    x = length + speed * t
    phi = sum(areas) / (x * width)
    stop = phi >= doc["stop"]["packing_fraction"]
    if step % every == 0 or stop:  # the last step is an output step too
        e = 1e-3 * t
        # like the real driver: no force averaged yet on a state's row
        fx = 0 if step == resumed_at else 10
        steps.write("%d,%r,2,5,1e-7,true,%d,%d,0,0,0,-10,0,%r,0,%d,0,"
                    "0,0,0,1,0,%r,0,-1,%r,%r,0,%r,0,0,0,0,0,0,0.1\n"
                    % (step, t, 4 * len(areas), 4 * len(areas), x, fx,
                       width, phi, e, 2 * e))
        steps.flush()
        with open(raw / "state.tmp", "wb") as f:
            f.write(b"softpack-state-1" + struct.pack("<qqqdq", 0, 0, 0, t,
                                                      step))
        os.replace(raw / "state.tmp", raw / "state.bin")
        for i, a in enumerate(areas):
            parts.write("%d,%d,%r,%r,%r\n" % (step, i, a, (i + 1) * e, a))
        with open(raw / "contacts" / ("step_%08d.csv" % step), "w") as f:
            f.write("candidate,node,antagonist,wall,fn,ft,fx,fy\n")
            for i in range(len(areas)):
                for node, wall, fy in ((0, 2, 1.0), (1, 2, 1.0),
                                       (5, 3, -1.0), (6, 3, -1.0)):
                    f.write("%d,%d,-1,%d,1.0,0,0,%r\n" % (i, node, wall, fy))
    if mode == "crash" and step >= 3 * every:
        print("fake driver: NLGS blew up", flush=True)
        sys.exit(3)
    if stop:
        break
    if mode == "slow":
        time.sleep(0.2)
    step += 1
steps.close()
parts.close()
json.dump({"steps": step, "seconds": 0.1, "reason": "packing_fraction"},
          open(raw / "done.json", "w"))
'''


@pytest.fixture(autouse=True)
def registry(tmp_path_factory, monkeypatch):
    return use_registry(tmp_path_factory, monkeypatch)


@pytest.fixture
def fake_bin(tmp_path, monkeypatch):
    """A directory with the fake driver, as SOFTPACK_BIN; fast polling."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    exe = bin_dir / "softpack-simulate"
    exe.write_text(FAKE_DRIVER)
    exe.chmod(0o755)
    monkeypatch.setattr(paths, "BIN", bin_dir)
    monkeypatch.setattr(run, "POLL_SECONDS", 0.02)
    return bin_dir


@pytest.fixture
def fake_mesh(monkeypatch):
    """Replace the dolfinx mesh by a body table (the driver is fake)."""
    def mesh_particles(bodies, centres, angles, out_stem):
        xdmf, h5, table = output_paths(out_stem)
        table.parent.mkdir(parents=True, exist_ok=True)
        radii = [b.bounding_radius for b in bodies]
        areas = [math.pi * r * r for r in radii]
        table.write_text("body,x,y,radius,reference_area,angle\n" + "".join(
            f"{i},{c[0]!r},{c[1]!r},{r!r},{a!r},0.0\n"
            for i, (c, r, a) in enumerate(zip(centres, radii, areas))))
        return MeshInfo(xdmf, h5, table, (1,) * len(radii),
                        (3,) * len(radii), tuple(areas))
    monkeypatch.setattr("softpack.scene.build.mesh_particles", mesh_particles)


def test_bad_config_exits_2_and_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[contact]\nfriction = -1\n")
    out = tmp_path / "out"
    assert run.main([str(bad), "--out", str(out)]) == 2
    assert "bad.toml: [contact] friction = -1: must be >= 0" in \
        capsys.readouterr().err
    assert not out.exists()
    assert run.main([str(SMALL), "--friction", "-0.5", "--out",
                     str(out)]) == 2
    assert "(from the command line)" in capsys.readouterr().err
    assert not out.exists()


def test_missing_driver_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(paths, "BIN", tmp_path / "nobin")
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 1
    assert "softpack-simulate not found" in capsys.readouterr().err
    assert not out.exists()


def test_run_with_real_mesh(tmp_path, fake_bin, capsys):
    pytest.importorskip("dolfinx")
    pytest.importorskip("gmsh")
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out), "--seed", "2"]) == 0
    printed = capsys.readouterr().out
    assert "100.0 %" in printed and "ETA" in printed
    for name in ("config.toml", "driver.json", "mesh/packing.xdmf",
                 "mesh/packing.bodies.csv", "mesh/packing.packing.csv",
                 "raw/done.json", "particles.csv", "series.csv"):
        assert (out / name).is_file(), name
    log = (out / "run.log").read_text()
    assert "fake driver: 14 bodies" in log and "[progress]" in log
    assert "seed = 2" in (out / "config.toml").read_text()
    s = observables.read_table(out / "series.csv")
    # meshed polygons (21 edges on a small disk) hold 1.2 % less area
    assert s["phi"][-1] >= 0.80 and 0.68 < s["phi"][0] < 0.6957
    assert set(s["z"]) == {2.0} and set(s["rattlers"]) == {0}
    assert s["eps"][0] == 0 and s["eps"][-1] > 0.1


def test_scene_error_names_the_file_and_the_key(tmp_path, fake_bin,
                                                fake_mesh, capsys):
    """A packing the box cannot give is refused naming the TOML file (not
    "packing:") and the key, before the driver runs."""
    pytest.importorskip("gmsh")  # the disk templates are meshed first
    bad = tmp_path / "too_full.toml"
    bad.write_text(SMALL.read_text().replace(
        "seed = 0", "seed = 0\ninitial_packing_fraction = 0.5"))
    out = tmp_path / "out"
    assert run.main([str(bad), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"softpack run: {bad}: [packing] initial_packing_fraction = 0.5" \
        in err
    assert "[box] length" in err  # and the key that would make it right
    assert not (out / "driver.json").exists()
    assert not (out / "series.csv").exists()
    assert "scene failed" in (out / "run.log").read_text()


def test_refuses_complete_run_unless_forced(tmp_path, fake_bin, fake_mesh,
                                            capsys):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    first = (out / "series.csv").read_text()
    assert run.main([str(SMALL), "--out", str(out)]) == 1
    assert "holds a complete run" in capsys.readouterr().err
    assert (out / "series.csv").read_text() == first
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 0


def test_crash_leaves_no_series(tmp_path, fake_bin, fake_mesh, monkeypatch,
                                capsys):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    monkeypatch.setenv("FAKE_DRIVER", "crash")
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 1
    err = capsys.readouterr().err
    assert "exit status 3" in err and "NLGS blew up" in err
    assert not (out / "series.csv").exists()
    assert not (out / "particles.csv").exists()
    assert (out / "raw" / "steps.csv").is_file()  # partial raw output kept
    assert run.main(["--observables-only", "--out", str(out)]) == 1
    assert "did not finish" in capsys.readouterr().err


def test_observables_only_uses_the_runs_config(tmp_path, fake_bin,
                                               fake_mesh):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    config = out / "config.toml"
    config.write_text(config.read_text().replace(
        'two_node_rule = "loaded_nodes"', 'two_node_rule = "candidate_nodes"'))
    (out / "series.csv").unlink()
    assert run.main(["--observables-only", "--out", str(out)]) == 0
    s = observables.read_table(out / "series.csv")
    assert set(s["z"]) == {2.0}  # wall contacts: two nodes of the particle


def test_default_out_dir_and_progress_line(tmp_path):
    from softpack.scene.config import load_config
    config = load_config(SMALL, {"packing.seed": 4,
                                 "contact.friction": 0.7})
    assert run.default_out_dir(config) == Path("runs/small-seed4")
    assert run.default_out_dir(config, True) == Path("runs/small-seed4-mu0.7")
    line = run.Progress(config, tmp_path / "steps.csv").line(
        [{"step": 10, "time": 0.01, "phi": 0.75}])
    # done = (0.75 - Phi0) / (0.80 - Phi0)
    assert "Phi = 0.7500" in line and " 52.1 %" in line
    # with [stop] steps, the steps done count too
    # (counted from the first row: a run from a state starts past 0)
    progress = run.Progress(load_config(SMALL, {"stop.steps": 40}),
                            tmp_path / "steps.csv")
    line = progress.line([{"step": 100, "time": 0.0, "phi": 0.0},
                          {"step": 130, "time": 0.0, "phi": 0.0}])
    assert " 75.0 %" in line
    assert os.fspath(run._default_config()).endswith("examples/paper.toml")


def test_set_overrides_are_parsed_as_toml_values():
    from softpack.scene.config import ConfigError
    from softpack.simulation.run import _parse_settings
    assert _parse_settings(["time.time_step=3.6e-5", "material.law='x'",
                            "output.fields = false",
                            "walls.right.velocity=[-0.2, 0]"]) == {
        "time.time_step": 3.6e-5, "material.law": "x",
        "output.fields": False, "walls.right.velocity": [-0.2, 0]}
    for bad in ("time_step=1", "time.time_step", "material.law=x"):
        with pytest.raises(ConfigError, match="--set"):
            _parse_settings([bad])
