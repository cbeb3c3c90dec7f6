"""``./softpack bench --laws LAW,...``: each law's cost per step against
neo-Hookean's on the paper case (issue 39: at most 1.3x).

The paper case (100 disks, 92k triangles, the defaults, no fields) runs
``--steps`` steps from its initial packing with ``material.law`` set to
neo_hookean (A) and to each LAW (B), everything else the paper's. A law
whose volumetric part is at the nodes (neo_hookean_nodal) gets the same
``lame_lambda`` as neo-Hookean's default (2 mu), so that both run the same
compressible material: its own default (nu = 0.499) is a stiffer material
whose steps differ in count of Newton iterations, not only in cost.

This host is shared (other processes on its two cores), so A and B
alternate ``--law-repeats`` times (A B A B ...) and each keeps its fastest
repeat, part by part; the NLGS yardstick of the same run (sweeps per second
on the 2020-contact FCLIB problem, :func:`~softpack.bench.common.bench_nlgs`)
says how fast the host was. The report gives the milliseconds per step,
whole and by part, the Newton iterations and factorizations, and each
law's ratio to neo-Hookean.
"""

from __future__ import annotations

from softpack.bench.common import (FAST, PARTS, WORK, bench_nlgs, run_driver,
                                   scaled_config, scene_for)
from softpack.contract.run_directory import RunDirectory

BASE_LAW = "neo_hookean"
#: Per law, what it needs beyond material.law to be the paper's material
LAW_OVERRIDES = {
    "neo_hookean_nodal": {"material.parameters.lame_lambda": 0.3e6},
}


def _config(law: str, steps: int):
    """The paper case with ``law``, ``steps`` steps, the defaults."""
    return scaled_config(1, {**FAST, "stop.steps": steps,
                             "output.every_steps": steps,
                             "material.law": law,
                             **LAW_OVERRIDES.get(law, {})})


def _newton_iterations(name: str) -> int:
    """The run's Newton iterations (raw/done.json)."""
    return int(RunDirectory(WORK / name).done()["newton_iterations"])


def _fastest(results: list[dict]) -> dict:
    """The first result with each timing replaced by its smallest."""
    best = dict(results[0])
    for key in ["ms_per_step", "seconds"] + [f"ms_{p}" for p in PARTS]:
        best[key] = min(r[key] for r in results)
    best["repeats"] = len(results)
    return best


def bench_laws(laws: list[str], steps: int, repeats: int = 2) -> dict:
    """Each law against neo-Hookean; see the module doc."""
    base = _config(BASE_LAW, steps)
    scene = scene_for(base, "n100")
    rows = []
    for law in laws:
        config = _config(law, steps)
        runs = {BASE_LAW: [], law: []}
        for _ in range(repeats):
            for name, c in ((BASE_LAW, base), (law, config)):
                r = run_driver(c, scene, f"law-{name}")
                r["newton_iterations"] = _newton_iterations(f"law-{name}")
                runs[name].append(r)
        a, b = _fastest(runs[BASE_LAW]), _fastest(runs[law])
        rows.append({"law": law, "base": a, "law_run": b,
                     "step_ratio": b["ms_per_step"] / a["ms_per_step"],
                     "part_ratios": {p: b[f"ms_{p}"] / a[f"ms_{p}"]
                                     for p in PARTS if a[f"ms_{p}"] > 0}})
    return {"steps": steps, "repeats": repeats, "rows": rows,
            "nlgs_yardstick": bench_nlgs().get("sweeps_per_second")}


def table(report: dict) -> str:
    """A few lines for a person."""
    lines = [f"paper case, {report['steps']} steps from the initial packing,"
             f" the defaults, fastest of {report['repeats']} alternating"
             " repeats (ms per step: whole; " + ", ".join(PARTS) + ")"]
    for r in report["rows"]:
        for label, x in ((BASE_LAW, r["base"]), (r["law"], r["law_run"])):
            parts = ", ".join(f"{x['ms_' + p]:.1f}" for p in PARTS)
            lines.append(f"  {label:26s}: {x['ms_per_step']:.1f} ({parts});"
                         f" {x['newton_iterations']} Newton iterations,"
                         f" {x['factorizations']} factorizations")
        ratios = ", ".join(f"{p} {v:.2f}x"
                           for p, v in r["part_ratios"].items())
        lines.append(f"  {r['law']} / {BASE_LAW}: step"
                     f" {r['step_ratio']:.2f}x ({ratios})")
    lines.append(f"NLGS yardstick today: {report['nlgs_yardstick']:.0f}"
                 " sweeps/s")
    return "\n".join(lines)
