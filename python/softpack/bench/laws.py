"""``./softpack bench --laws LAW,...``: each law's cost per step against
neo-Hookean's on the paper case (issue 39: at most 1.3x). LAW a material
of forms/materials/, or a contact law (``cohesive``, ``bonded``) on every
pair of the paper's neo-Hookean disks and the walls.

The paper case (100 disks, 92k triangles, the defaults, no fields) runs
``--steps`` steps from its initial packing with ``material.law`` set to
neo_hookean (A) and to each LAW (B), everything else the paper's. A law
whose volumetric part is at the nodes (neo_hookean_nodal) gets the same
``lame_lambda`` as neo-Hookean's default (2 mu), so that both run the same
compressible material (its own default, nu = 0.499, is another material);
Mooney-Rivlin gets c10 and c01 with 2 (c10 + c01) = mu, the paper's shear
modulus.

This host is shared (other processes on its two cores), and wall times
there move by 2x between minutes. So each run is one OpenMP thread, and
its cost per step is the driver's CPU time (user + system, from
``os.wait4``) over the steps: that of a ``--steps`` run less that of a
one-step run of the same law (the setup), divided by ``--steps`` - 1. A
and B alternate ``--law-repeats`` times (A B A B ...); the report gives
the CPU milliseconds per step (median of the repeats), each B over the A
run just before it (median and range), the wall milliseconds per step by
part (fastest repeat; one thread, from raw/done.json) and the NLGS
yardstick of the same run (sweeps per second on the 2020-contact FCLIB
problem, :func:`~softpack.bench.common.bench_nlgs`).
"""

from __future__ import annotations

import statistics

from softpack.bench.common import (FAST, PARTS, WORK, bench_nlgs,
                                   stepping_cost, scaled_config, scene_for)
from softpack.contract.run_directory import RunDirectory

BASE_LAW = "neo_hookean"
#: Per law, what it needs beyond material.law to be the paper's material
LAW_OVERRIDES = {
    "neo_hookean_nodal": {"material.parameters.lame_lambda": 0.3e6},
    # mu = 2 (c10 + c01), lambda = 2 mu: the paper's small-strain moduli
    "mooney_rivlin": {"material.parameters": {
        "c10": 0.05e6, "c01": 0.025e6, "lame_lambda": 0.3e6}},
}




def _pairs(law: str, **parameters) -> list:
    """Every pair of the paper's species (and each with the walls) under
    a contact law, the paper's friction 0.3 (docs/contact_laws.md)."""
    pairs = [("small", "small"), ("small", "large"), ("large", "large"),
             ("small", "walls"), ("large", "walls")]
    return [{"species": a, "against": b, "coefficient": 0.3, "law": law,
             **parameters} for a, b in pairs]


#: Contact laws timed on neo-Hookean disks, with examples/
#: adhesive_small.toml's and bonded_small.toml's parameters (the bonding
#: distance at most the paper's alert distance, 0.2 mm)
CONTACT_LAWS = {
    "cohesive": {"friction": _pairs("cohesive", cohesion=2.0e4,
                                    cohesive_distance=2.0e-4)},
    "bonded": {"friction": _pairs("bonded", tensile_strength=2.0e4,
                                  shear_strength=1.0e4,
                                  bonding_distance=2.0e-4)},
}


def _config(law: str, steps: int):
    """The paper case with ``law`` (a material, or a contact law on every
    pair of neo-Hookean disks), ``steps`` steps, the defaults."""
    material = {} if law in CONTACT_LAWS else {"material.law": law}
    return scaled_config(1, {**FAST, "stop.steps": steps,
                             "output.every_steps": steps, **material,
                             **LAW_OVERRIDES.get(law, {})},
                         CONTACT_LAWS.get(law))


def _timed_run(config, scene: dict, name: str) -> dict:
    """One run on one OpenMP thread in WORK/name: its CPU seconds, steps,
    Newton iterations, factorizations and wall milliseconds per step by
    part."""
    from softpack.simulation import driver
    from softpack.simulation.driver_input import write_driver_json

    run = RunDirectory(WORK / name)
    write_driver_json(config, scene, run.path, None)
    proc = driver.start(run.driver_json, None, quiet=True, threads=1)
    status, usage = driver.wait_usage(proc)
    if status != 0:
        raise driver.DriverFailed(f"{name}: the driver failed (exit status"
                                  f" {status})", status)
    done = run.done()
    cost = stepping_cost(run, done)
    return {"cpu_seconds": usage.ru_utime + usage.ru_stime,
            "steps": done["steps"],
            "newton_iterations": done["newton_iterations"],
            "factorizations": done["factorizations"],
            "ms_per_step": cost["ms_per_step"],
            **{f"ms_{p}": cost[f"ms_{p}"] for p in PARTS}}


def _law_runs(law: str, config, setup: float, scene, steps: int,
              tag: str) -> dict:
    """One timed run of ``law``, its CPU per step net of ``setup``."""
    r = _timed_run(config, scene, f"law-{law}-{tag}")
    r["cpu_ms_per_step"] = 1e3 * (r["cpu_seconds"] - setup) / (steps - 1)
    return r


def _summary(runs: list[dict]) -> dict:
    """Median CPU per step; fastest wall time per step, whole and by part."""
    out = {k: runs[0][k] for k in ("steps", "newton_iterations",
                                   "factorizations")}
    out["cpu_ms_per_step"] = statistics.median(
        r["cpu_ms_per_step"] for r in runs)
    for key in ["ms_per_step"] + [f"ms_{p}" for p in PARTS]:
        out[key] = min(r[key] for r in runs)
    out["repeats"] = len(runs)
    return out


def bench_laws(laws: list[str], steps: int, repeats: int = 2) -> dict:
    """Each law against neo-Hookean; see the module doc."""
    if steps < 2:
        raise ValueError("--laws needs --steps of at least 2")
    base = _config(BASE_LAW, steps)
    scene = scene_for(base, "n100")
    setup = {}
    rows = []
    for law in laws:
        configs = {BASE_LAW: base, law: _config(law, steps)}
        for name in configs:
            if name not in setup:
                setup[name] = _timed_run(_config(name, 1), scene,
                                         f"law-{name}-setup")["cpu_seconds"]
        runs = {BASE_LAW: [], law: []}
        for i in range(repeats):
            for name, config in configs.items():
                runs[name].append(_law_runs(name, config, setup[name], scene,
                                            steps, "timed"))
        pairs = sorted(b["cpu_ms_per_step"] / a["cpu_ms_per_step"]
                       for a, b in zip(runs[BASE_LAW], runs[law]))
        a, b = _summary(runs[BASE_LAW]), _summary(runs[law])
        rows.append({"law": law, "base": a, "law_run": b,
                     "setup_cpu_seconds": {n: setup[n] for n in configs},
                     "cpu_ratio": b["cpu_ms_per_step"] / a["cpu_ms_per_step"],
                     "pair_ratios": pairs,
                     "median_pair_ratio": statistics.median(pairs),
                     "part_ratios": {p: b[f"ms_{p}"] / a[f"ms_{p}"]
                                     for p in PARTS if a[f"ms_{p}"] > 0}})
    return {"steps": steps, "repeats": repeats, "threads": 1, "rows": rows,
            "nlgs_yardstick": bench_nlgs().get("sweeps_per_second")}


def table(report: dict) -> str:
    """A few lines for a person."""
    lines = [f"paper case, {report['steps']} steps from the initial packing,"
             f" the defaults, one thread, {report['repeats']} alternating"
             " repeats: CPU ms per step (median); wall ms per step (fastest:"
             " whole; " + ", ".join(PARTS) + ")"]
    for r in report["rows"]:
        for label, x in ((BASE_LAW, r["base"]), (r["law"], r["law_run"])):
            parts = ", ".join(f"{x['ms_' + p]:.1f}" for p in PARTS)
            lines.append(f"  {label:26s}: CPU {x['cpu_ms_per_step']:.1f};"
                         f" wall {x['ms_per_step']:.1f} ({parts});"
                         f" {x['newton_iterations']} Newton iterations,"
                         f" {x['factorizations']} factorizations")
        ratios = ", ".join(f"{p} {v:.2f}x"
                           for p, v in r["part_ratios"].items())
        pairs = ", ".join(f"{p:.2f}" for p in r["pair_ratios"])
        lines.append(f"  {r['law']} / {BASE_LAW}: CPU per step"
                     f" {r['cpu_ratio']:.2f}x (pair by pair {pairs}, median"
                     f" {r['median_pair_ratio']:.2f}x); wall by part"
                     f" {ratios}")
    lines.append(f"NLGS yardstick today: {report['nlgs_yardstick']:.0f}"
                 " sweeps/s")
    return "\n".join(lines)
