"""``./softpack viscoelastic-disk``: a viscoelastic disk loaded and unloaded
between two plates, softpack against an independent dolfinx integration.

Issue 39's viscoelastic check. One disk of ``viscoelastic_neo_hookean``
(docs/materials.md) squeezed between two rigid plates to eps_max and
released, computed twice on the SAME mesh:

softpack (``sim/``)
    the production pipeline as :mod:`softpack.references.single_disk` runs
    it (its module doc lists the overrides: plates at the mesh's extreme
    nodes moving towards each other at ``--speed`` each, friction 0.01 on
    the plates, Rayleigh alpha = 200 1/s, theta = 0.5, the mesh turned
    node-up), with the law and its branches set here and two
    ``[[stages]]``: ``load`` until the plates' engineering strain reaches
    1 - exp(-eps_max), ``unload`` with the plates' velocities reversed
    until they are back where they started. Every step is an output row.
dolfinx (:class:`.maxwell_reference.MaxwellReference`)
    the same triangles, the law written out from its stress, quasi-static,
    the branch variables relaxed implicitly at each step's end
    configuration (the driver: explicitly, after the step), the plates of
    each driver step (``--reference-substeps`` substeps between two rows,
    the plates linear in time in between), a nodal penalty contact
    (:mod:`.plates_reference`), the centre node pinned.

The driver's plate force of a row is the mean over its step (theta = 1/2:
the force at mid-step), compared with the mean of the reference's forces
at the step's two ends. The dissipation of the reference is the plates'
work (trapezoidal in time) less the stored energy; the driver books its
own (`viscous`) and closes its balance with the kinetic energy, the
damping and the theta scheme's `numerical` part (docs/energy in
docs/materials.md). The comparison stops when the reference disk has left
both plates during the unloading; both forces are then zero.

Outputs in ``--out DIR``: ``cycle.csv`` (one row per driver step: time,
the plates' approach, f_norm of both, the driver's accounts and the
reference's dissipation), ``viscoelastic_disk.json`` (parameters, mesh,
the differences, the energies, the run times), ``sim/``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table
from softpack.references import between_plates
from softpack.references.between_plates import Params
from softpack.references.maxwell_reference import MaxwellReference
from softpack.references.single_disk import put_node_up
from softpack.scene.config import validate

SOURCE = "viscoelastic-disk"
#: The reference ends unloading when its force has fallen below this
#: fraction of its peak and no equilibrium follows (reference_cycle).
LEFT_PLATES = 0.01
LAW = "viscoelastic_neo_hookean"
#: The branches of examples/viscoelastic_small.toml.
BRANCHES = {"branch_ratio_1": 1.0, "relaxation_time_1": 0.01,
            "branch_ratio_2": 0.5, "relaxation_time_2": 0.1}


@dataclass
class CycleParams(Params):
    """The single-disk protocol (:class:`.between_plates.Params`), a cycle
    to ``max_strain`` and back, the law's branches and the reference's
    settings."""

    max_strain: float = 0.1
    every: int = 1
    branches: dict = field(default_factory=lambda: dict(BRANCHES))
    reference_substeps: int = 1
    penalty: float = 1e5          # the reference's plate stiffness, mu/D


def cycle_config(params: CycleParams, y_bottom=None, y_top=None):
    """The validated configuration (plates at +-R unless given)."""
    if y_bottom is None:
        y_bottom, y_top = -params.radius, params.radius
    data = between_plates.config_data(params, y_bottom, y_top)
    data["material"] = {"law": LAW, "parameters": dict(params.branches)}
    if params.lame_lambda is not None:
        data["material"]["parameters"]["lame_lambda"] = params.lame_lambda
    data["stop"] = {"packing_fraction": 0.0}
    data["output"]["fields"] = False
    load = 1 - math.exp(-params.max_strain)
    bound = 1.5 * params.duration + 0.01
    v = params.speed
    data["stages"] = [
        {"name": "load", "stop": {"strain": load, "strain_wall": "top",
                                  "max_time": bound}},
        {"name": "unload",
         "walls": {"bottom": {"velocity": [0.0, -v]},
                   "top": {"velocity": [0.0, v]}},
         "stop": {"strain": load / (1 - load), "strain_wall": "top",
                  "max_time": bound}}]
    return validate(data, SOURCE)


def simulate(params: CycleParams, sim_dir) -> dict:
    """The driver's run (:func:`.between_plates.simulate`), mesh node-up."""
    return between_plates.simulate(
        cycle_config, params, sim_dir, "disk",
        lambda mesh_h5: put_node_up(mesh_h5, params.radius))


def reference_cycle(ref: MaxwellReference, steps: dict, substeps: int,
                    diameter: float) -> dict:
    """The reference along the driver's plates (module doc): the plates'
    forces (N/m), their work and the stored energy (J/m) at each row's
    time, up to the row ``end`` where the disk leaves the plates while
    unloading (its force zero, or below LEFT_PLATES of its peak with no
    equilibrium after: the disk's translation is then undetermined)."""
    t, bottom = steps["time"], steps["bottom_y"]
    n = len(t)
    out = {k: np.full(n, np.nan) for k in ("f_bottom", "f_top", "work",
                                           "stored")}
    for key in out:
        out[key][0] = 0.0
    out["end"] = n - 1
    peak = pin = 0.0
    for i in range(1, n):
        unloading = bottom[i] < bottom[i - 1]
        try:
            forces, work, pin_i = _reference_step(ref, steps, i, substeps,
                                                  1e-10 * diameter)
        except _NoEquilibrium as err:
            if unloading and (out["f_bottom"][i - 1] + out["f_top"][i - 1]
                              < LEFT_PLATES * peak):
                out["end"] = i - 1
                break
            raise RuntimeError(f"dolfinx reference: {err}") from None
        out["f_bottom"][i], out["f_top"][i] = forces
        out["work"][i] = out["work"][i - 1] + work
        out["stored"][i] = ref.energy_value()
        peak, pin = max(peak, sum(forces)), max(pin, pin_i)
        if unloading and sum(forces) == 0.0:
            out["end"] = i
            break
    out["dissipated"] = out["work"] - out["stored"]
    out["pin_reaction_over_peak"] = pin / peak
    return out


class _NoEquilibrium(RuntimeError):
    pass


def _reference_step(ref, steps, i, substeps, tolerance):
    """The reference from row i - 1 to row i in ``substeps`` steps, the
    plates linear in time: the plates' forces at row i, their work
    (trapezoidal) and the pins' largest reaction."""
    t, bottom, top = steps["time"], steps["bottom_y"], steps["top_y"]
    forces = (0.0, 0.0) if i == 1 else ref.plate_forces(bottom[i - 1],
                                                        top[i - 1])
    plates = (bottom[i - 1], top[i - 1])
    work = pin = 0.0
    ref.set_time_step((t[i] - t[i - 1]) / substeps)
    for s in range(1, substeps + 1):
        w = s / substeps
        new = ((1 - w) * bottom[i - 1] + w * bottom[i],
               (1 - w) * top[i - 1] + w * top[i])
        _predict(ref, (plates, new))
        if ref.solve(*new, tolerance) is None:
            raise _NoEquilibrium(f"no equilibrium at t ="
                                 f" {t[i - 1] + w * (t[i] - t[i - 1]):.6g} s")
        ref.commit()
        f_new = ref.plate_forces(*new)
        work += 0.5 * (forces[0] + f_new[0]) * (new[0] - plates[0]) \
            + 0.5 * (forces[1] + f_new[1]) * (plates[1] - new[1])
        pin = max(pin, ref.pin_reaction(*new))
        forces, plates = f_new, new
    return forces, work, pin


def _predict(ref, plates):
    """Newton's first guess: the current shape compressed in y about the
    plates' middle by the ratio of their new distance to their old one (as
    they move apart, the penalty contact would otherwise start with no
    node touching, the translation free)."""
    (b0, t0), (b1, t1) = plates
    s = (t1 - b1) / (t0 - b0)
    x = ref.X + ref.displacement()
    new = np.column_stack([x[:, 0], 0.5 * (b1 + t1) + (x[:, 1] - 0.5
                                                       * (b0 + t0)) * s])
    ref.u.x.array[:] = (new - ref.X).ravel()


def compare(steps, ref, diameter, mu) -> dict:
    """f_norm of both per row (the driver's at mid-step against the mean of
    the reference's step ends) and their differences over the rows the
    reference covers."""
    scale = diameter * mu
    soft = 0.5 * (steps["top_fy"] - steps["bottom_fy"]) / scale
    f = 0.5 * (ref["f_top"] + ref["f_bottom"]) / scale
    dolf = np.full_like(f, np.nan)
    dolf[1:] = 0.5 * (f[1:] + f[:-1])
    end = ref["end"]
    rows = slice(1, end + 1)
    peak = float(np.nanmax(dolf[rows]))
    diff = soft[rows] - dolf[rows]
    loaded = dolf[rows] > 0.1 * peak
    i_peak = int(np.nanargmax(dolf[rows])) + 1
    return {"f_norm_softpack": soft, "f_norm_dolfinx": dolf,
            "summary": {
                "rows_compared": end,
                "peak_f_norm_dolfinx": peak,
                "peak_f_norm_softpack": float(np.max(soft[rows])),
                "at_peak_relative_difference": float(
                    soft[i_peak] / dolf[i_peak] - 1),
                "max_abs_difference_over_peak": float(
                    np.max(np.abs(diff)) / peak),
                "max_abs_relative_difference_above_10pc_of_peak": float(
                    np.max(np.abs(diff[loaded] / dolf[rows][loaded])))}}


def energies(steps, ref) -> dict:
    """The two computations' energy accounts at the reference's last row
    (J/m; the driver's from raw/steps.csv)."""
    end = ref["end"]
    pick = {k: float(steps[k][end]) for k in (
        "wall_work", "viscous", "strain_energy", "kinetic_energy",
        "damping", "numerical", "friction", "energy_residual")}
    return {"time_s": float(steps["time"][end]),
            "softpack": pick,
            "dolfinx": {"plate_work": float(ref["work"][end]),
                        "stored": float(ref["stored"][end]),
                        "dissipated": float(ref["dissipated"][end])},
            "viscous_relative_difference": pick["viscous"]
            / float(ref["dissipated"][end]) - 1}


def run(params: CycleParams, out_dir) -> dict:
    """Both computations; writes cycle.csv and viscoelastic_disk.json."""
    from softpack.analysis.fields import read_mesh

    out_dir = Path(out_dir)
    sim = RunDirectory(out_dir / "sim")
    meta = simulate(params, sim.path)
    steps = read_table(sim.raw.steps_csv)
    material = meta["config"]["material"]["parameters"]
    points, cells = read_mesh(meta["mesh_h5"])
    started = time.time()
    model = MaxwellReference(points, cells, material,
                             params.penalty * material["shear_modulus"]
                             / params.diameter,
                             float(steps["time_step"][1]))
    ref = reference_cycle(model, steps, params.reference_substeps,
                          params.diameter)
    seconds = time.time() - started
    mu = material["shear_modulus"]
    cmp = compare(steps, ref, params.diameter, mu)
    delta = (meta["y_top0"] - steps["top_y"]) + (steps["bottom_y"]
                                                 - meta["y_bottom0"])
    write_table(out_dir / "cycle.csv", {
        "time": steps["time"], "delta": delta,
        "f_norm_softpack": cmp["f_norm_softpack"],
        "f_norm_dolfinx": cmp["f_norm_dolfinx"],
        "viscous_softpack": steps["viscous"],
        "dissipated_dolfinx": ref["dissipated"]})
    doc = {"params": asdict(params),
           "material": material,
           "mesh": {"triangles": meta["triangles"], "nodes": meta["nodes"]},
           "plates_initial_y": [meta["y_bottom0"], meta["y_top0"]],
           "force": cmp["summary"],
           "energy": energies(steps, ref),
           "softpack": {"steps": int(steps["step"][-1]),
                        "driver_seconds": round(meta["driver_seconds"], 1),
                        "max_penetration_m": float(np.nanmax(
                            steps["max_penetration"]))},
           "dolfinx": {"seconds": round(seconds, 1),
                       "pin_reaction_over_peak_force": ref[
                           "pin_reaction_over_peak"]},
           "f_norm": "mean plate force per unit length / (D mu)"}
    (out_dir / "viscoelastic_disk.json").write_text(
        json.dumps(doc, indent=1) + "\n")
    return doc


def _parser():
    from softpack import cli

    d = CycleParams()
    p = argparse.ArgumentParser(
        prog="softpack viscoelastic-disk",
        description="A viscoelastic disk loaded to --max-strain and"
        " unloaded between two plates: softpack against an independent"
        " quasi-static dolfinx integration of the same law on the same mesh"
        " (writes DIR/cycle.csv, viscoelastic_disk.json).")
    between_plates.add_plate_arguments(p, d, Path("runs/viscoelastic-disk"))
    p.add_argument("--reference-substeps", type=cli.positive_int,
                   default=d.reference_substeps,
                   help="dolfinx: steps per driver step (default 1)")
    p.add_argument("--penalty", type=cli.positive_float, default=d.penalty,
                   help="dolfinx: plate stiffness k in mu/D (default 1e5)")
    return p


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    params = CycleParams(**{k: v for k, v in vars(args).items()
                            if k != "out"})
    if between_plates.refused(params, cycle_config, args.out,
                              "softpack viscoelastic-disk"):
        return 2
    print(f"softpack viscoelastic-disk: D = {params.diameter:g} m, h ="
          f" {params.element_size:g} m, to eps = {params.max_strain:g} and"
          f" back at {params.speed:g} m/s -> {args.out}", flush=True)
    try:
        doc = run(params, args.out)
    except RuntimeError as err:  # RunError, dolfinx's
        print(f"softpack viscoelastic-disk: {err}", file=sys.stderr)
        return 1
    f, e = doc["force"], doc["energy"]
    print(f"  force: peak f_norm softpack {f['peak_f_norm_softpack']:.5g},"
          f" dolfinx {f['peak_f_norm_dolfinx']:.5g}; largest difference"
          f" {100 * f['max_abs_difference_over_peak']:.2f} % of the peak")
    print(f"  dissipated by t = {e['time_s']:.4g} s: softpack viscous"
          f" {e['softpack']['viscous']:.5g} J/m, dolfinx"
          f" {e['dolfinx']['dissipated']:.5g} J/m"
          f" ({100 * e['viscous_relative_difference']:+.2f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
