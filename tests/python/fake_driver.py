"""A fake ``softpack-simulate`` for the tests of ``./softpack run``.

The fake driver (the Python script :data:`FAKE_DRIVER`) follows
docs/contract.md (sections 4-5): it reads driver.json (schema version 2)
and the mesh's body table, writes raw/setup.json, moves the piston (wall
"right") at the given speed, writes raw/steps.csv, raw/particles.csv,
raw/contacts/ and finally raw/done.json. Every particle is held between the
bottom and top walls by two nodes each (balanced), so Z = 2 (walls only).
``FAKE_DRIVER=crash`` in the environment makes it fail after three outputs,
``slow`` makes it take 0.2 s a step and write its pid. The fixtures that
use it (``fake_bin``, ``fake_mesh``) are in conftest.py.
"""

from pathlib import Path

#: The small example every fake run uses.
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
    "friction,contact_normal,cohesion,numerical,energy_residual"
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
                    "0,0,0,1,0,%r,0,-1,%r,%r,0,%r,0,0,0,0,0,0,0,0.1\n"
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
