"""``./softpack bench --periodic N,...``: the periodic cell's cost per step
against the walled box with the same disks (issue 38).

For each N, the paper's disks scaled to N (:func:`~softpack.bench.common.
scaled_overrides`: same species, element size and initial packing fraction)
run ``--steps`` steps from their random placement twice, at the defaults:

- walled: the paper's box, its piston at the paper's strain rate;
- periodic: a cell with the box's edges (``examples/periodic_small.toml``'s
  cell section), compacted isotropically at the same rate of area change
  (each edge at half the piston's strain rate).

Everything else is the paper's (mesh, contact and time settings), and both
runs use ``[damping] alpha = 0`` (a cell refuses it), so the two differ only
in what bounds the disks. This host's speed moves while a benchmark runs
(other processes share its two cores), so the two runs alternate
``repeats`` times (walled, periodic, walled, ...) and each keeps its
fastest repeat, part by part. The report gives the milliseconds per step, whole
and by part, and the ratio of the detection parts: the images cost the cell
its extra detection (issue 38's target: under 10 % more).
"""

from __future__ import annotations

from softpack import paths
from softpack.bench.common import (FAST, PARTS, PISTON, WORK, bench_nlgs,
                                   run_driver, scaled_config, scene_for)
from softpack.scene.config import load_config

PERIODIC_TOML = paths.ROOT / "examples" / "periodic_small.toml"
#: The paper's settings that examples/periodic_small.toml sets otherwise.
PAPER_SETTINGS = ("mesh.element_size", "packing.gap", "contact.alert_distance",
                  "contact.max_penetration", "contact.nlgs_max_sweeps",
                  "contact.nlgs_relaxation", "contact.nlgs_order",
                  "time.time_step")


def _setting(config, key: str):
    section, name = key.split(".")
    return config[section][name]


def _cell_overrides(walled, steps: int = 0, to_phi: float = 0.0) -> dict:
    """The walled config's disks and settings in a periodic cell of its
    box's edges (no velocity gradient yet), for ``steps`` steps or to Phi =
    ``to_phi`` (0: no such bound)."""
    box = walled["box"]
    overrides = {key: _setting(walled, key) for key in PAPER_SETTINGS}
    for i, s in enumerate(walled["species"]):
        overrides[f"species.{i}.count"] = s["count"]
        overrides[f"species.{i}.diameter"] = s["diameter"]
    overrides.update({
        **FAST, "output.fields": False, "output.every_steps": 50,
        "stop.steps": steps, "stop.packing_fraction": to_phi,
        "stop.max_time": 10.0,
        "cell.a1": [box["length"], 0.0], "cell.a2": [0.0, box["width"]]})
    return overrides


def periodic_config(walled, steps: int = 0, to_phi: float = 0.0):
    """The walled config's disks and settings in a periodic cell of its
    box's edges, compacted at the piston's rate of area change for
    ``steps`` steps or to Phi = ``to_phi`` (0: no such bound)."""
    box = walled["box"]
    rate = walled["walls"][PISTON]["velocity"][0] / box["length"] / 2
    overrides = _cell_overrides(walled, steps, to_phi)
    overrides.update({"cell.velocity_gradient_x": [rate, 0.0],
                      "cell.velocity_gradient_y": [0.0, rate]})
    return load_config(PERIODIC_TOML, overrides)


#: The stress-controlled simple shear of examples/shear_small.toml: the
#: shear rate L_xy (1/s) and the normal stress on the free height (Pa).
SHEAR_RATE = 2.0
SHEAR_STRESS = 2000.0


def shear_config(walled, steps: int):
    """The walled config's disks in a cell of its box's edges under
    examples/shear_small.toml's simple shear at constant normal stress: the
    width fixed, L_xy = SHEAR_RATE, the height a servo unknown under
    SHEAR_STRESS (its coupling to every contact: W's rank-one term)."""
    overrides = _cell_overrides(walled, steps)
    overrides.update({"cell.velocity_gradient_x": [0.0, SHEAR_RATE],
                      "cell.velocity_gradient_y": [0.0, 0.0],
                      "cell.control_yy": "stress",
                      "cell.stress_yy": SHEAR_STRESS})
    return load_config(PERIODIC_TOML, overrides)


def _walled(n: int, steps: int):
    """The paper's disks scaled to n in the walled box for ``steps`` steps,
    without the mass-proportional damping a cell refuses."""
    return scaled_config(n / 100, {**FAST, "output.every_steps": 50,
                                   "stop.steps": steps, "damping.alpha": 0.0})


def bench_periodic_shear(counts, steps: int) -> dict:
    """The stress-controlled shear (:func:`shear_config`) of each count of
    disks for ``steps`` steps from the random placement: ms per step, by
    part, the contacts at the end, and the seconds per unit shear strain
    (1 / (SHEAR_RATE time_step) steps), with the NLGS yardstick."""
    from softpack.contract.tables import read_table

    rows = []
    for n in counts:
        walled = _walled(n, steps)
        cell = shear_config(walled, steps)
        tag = f"n{sum(s['count'] for s in walled['species'])}"
        result = run_driver(cell, scene_for(cell, f"cell-{tag}"),
                            f"shear-{tag}")
        steps_csv = WORK / f"shear-{tag}" / "raw" / "steps.csv"
        contacts = read_table(steps_csv)["contacts"]
        dt = cell["time"]["time_step"]
        rows.append({"disks": n, "shear": result,
                     "contacts_end": int(contacts[-1]),
                     "seconds_per_unit_strain":
                     result["ms_per_step"] / 1e3 / (SHEAR_RATE * dt)})
    return {"steps": steps, "rows": rows,
            "nlgs_yardstick": bench_nlgs().get("sweeps_per_second")}


def shear_table(report: dict) -> str:
    """A few lines for a person."""
    lines = [f"{report['steps']} steps of stress-controlled simple shear"
             f" (L_xy {SHEAR_RATE} 1/s, sigma_yy {SHEAR_STRESS} Pa) from the"
             " random placement (ms per step: whole; " + ", ".join(PARTS)
             + ")"]
    for r in report["rows"]:
        x = r["shear"]
        parts = ", ".join(f"{x['ms_' + p]:.1f}" for p in PARTS)
        lines.append(f"{r['disks']:5d} disks: {x['ms_per_step']:.1f}"
                     f" ({parts}), {r['contacts_end']} contacts at the end,"
                     f" {r['seconds_per_unit_strain']:.0f} s per unit shear"
                     f" strain, peak {x['peak_memory_mb']:.0f} MB")
    lines.append(f"NLGS yardstick today: {report['nlgs_yardstick']:.0f}"
                 " sweeps/s")
    return "\n".join(lines)


def _fastest(results: list[dict]) -> dict:
    """The first result with each timing replaced by its smallest."""
    best = dict(results[0])
    for key in ["ms_per_step", "seconds"] + [f"ms_{p}" for p in PARTS]:
        best[key] = min(r[key] for r in results)
    best["repeats"] = len(results)
    return best


def bench_periodic(counts, steps: int, repeats: int = 2) -> dict:
    """Both runs for each count of disks; see the module doc."""
    rows = []
    for n in counts:
        walled = _walled(n, steps)
        cell = periodic_config(walled, steps)
        tag = f"n{sum(s['count'] for s in walled['species'])}"
        runs = {"walled": [], "periodic": []}
        for _ in range(repeats):
            runs["walled"].append(run_driver(
                walled, scene_for(walled, tag), f"walled-{tag}"))
            runs["periodic"].append(run_driver(
                cell, scene_for(cell, f"cell-{tag}"), f"periodic-{tag}"))
        w, p = _fastest(runs["walled"]), _fastest(runs["periodic"])
        rows.append({"disks": n, "walled": w, "periodic": p,
                     "step_ratio": p["ms_per_step"] / w["ms_per_step"],
                     "detection_ratio": p["ms_detection"]
                     / w["ms_detection"]})
    return {"steps": steps, "rows": rows,
            "nlgs_yardstick": bench_nlgs().get("sweeps_per_second")}


def table(report: dict) -> str:
    """A few lines for a person."""
    lines = [f"{report['steps']} steps from the random placement, the"
             " defaults, alpha = 0, the fastest of each kind's repeats"
             " (ms per step: whole; "
             + ", ".join(PARTS) + ")"]
    for r in report["rows"]:
        for kind in ("walled", "periodic"):
            x = r[kind]
            parts = ", ".join(f"{x['ms_' + p]:.1f}" for p in PARTS)
            lines.append(f"{r['disks']:5d} disks {kind:8s}:"
                         f" {x['ms_per_step']:.1f} ({parts}),"
                         f" peak {x['peak_memory_mb']:.0f} MB")
        lines.append(f"      periodic / walled: step"
                     f" {r['step_ratio']:.2f}x, detection"
                     f" {r['detection_ratio']:.2f}x")
    lines.append(f"NLGS yardstick today: {report['nlgs_yardstick']:.0f}"
                 " sweeps/s")
    return "\n".join(lines)
