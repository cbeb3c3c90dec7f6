"""``./softpack single-disk``: one soft disk squeezed between two rigid plates.

The 2D half of the paper's single-cylinder check (Figs. 2 and 3, METHOD.md
§5): a neo-Hookean disk (plane strain, mu = 0.15 MPa, lambda~ = 2 mu, i.e.
nu~ = 1/3, rho = 1180 kg/m^3) of diameter D between two rigid frictionless
plates normal to y, run with the project's own contact driver
``softpack-simulate`` (Moreau–Jean + NLGS, docs/driver_io.md) slowly enough to
be quasi-static, up to eps = -ln(1 - delta/D) = 0.25.

Set-up: a configuration through the production pipeline
  The run is a :class:`~softpack.scene.config.Config` validated by the
  schema like any TOML file (:func:`single_disk_config`), its scene built
  by :func:`softpack.scene.build.build_scene` and its driver.json written
  by the one writer (:mod:`softpack.simulation.driver_input`). Every
  numerical setting is the production default (schema/parameters.toml)
  except these overrides, which the protocol needs:

  * ``[box] enabled = false``, ``[stop] packing_fraction = 0``: no
    container; ``[[species]]`` one disk (``diameter = D``, ``count = 1``),
    at the origin; ``[mesh] element_size = h``;
  * ``[walls.bottom]`` and ``[walls.top]``: two plates (normals +y and -y)
    starting in touch with the mesh (at y = min Y and max Y of the nodes:
    the inscribed polygon's extreme nodes lie a few micrometres inside the
    circle, and eps is counted from first contact) and BOTH moving towards
    the centre, ``velocity = [0, +-0.01]`` (``--speed``; approach speed
    2 speed), as in the 3D reference: the disk's centre then stays at rest
    and the mass-proportional Rayleigh damping (alpha M v), which resists
    absolute velocities, does not resist a rigid-body translation (with one
    plate fixed the centre would move at half the approach speed and
    alpha M v would add alpha m v/2 to the moving plate's force);
  * ``[contact] friction = 0.01`` (``--friction``; 0 for exactly
    frictionless plates). A frictionless disk between frictionless plates
    has two undetermined rigid-body modes: the x-translation and the
    ROLLING (rotation about its axis: a circle's energy does not change
    when it turns). Nothing in the driver pins them, and the mesh's
    asymmetry drives the rolling: with friction 0 the D = 20 mm disk
    (h = 1.065 mm) turns by 0.19 rad by eps = 0.25, which tilts the
    material line of Fig. 3 (u_x/D at w = 1 and eps = 0.2: 0.0260 instead
    of 0.0321). A friction coefficient of 0.01 stops both (largest
    rotation 5e-4 rad; 0.001 leaves 4e-3 rad) while changing f_norm by at
    most 0.13 % (friction 0, 0.001 and 0.01 compared in
    docs/single_disk/README.md). The profile is moreover taken relative to
    the displacement of the disk's centre (below);
  * ``[damping] alpha = 200`` 1/s (quasi-static loading; ``--alpha``),
    ``[time] time_step = 1e-4`` s (``--time-step``) and ``[time] theta =
    0.5`` (no numerical dissipation in the force);
  * ``[stop] max_time``: the time to reach delta_max = D (1 -
    exp(-max_strain)), plus two output intervals;
  * ``[output] every_steps = 10`` (``--every``), ``fields_every = 1``
    (the profiles interpolate between consecutive outputs), ``state =
    false``.

  The material is the configuration's default law and parameters (the
  paper's neo-Hookean solid, lambda~ = 2 mu); f_norm uses its shear
  modulus. The mesh is turned about the centre so that a boundary node lies
  on the loading axis (:func:`put_node_up`; ``--orientation as_meshed``
  keeps gmsh's): the two plates then touch a boundary polygon that is
  mirror-symmetric about the axis. As meshed, the nodes nearest the plates
  are off the axis (by 0.27 mm for h = 1.065 mm), which changes f_norm at
  eps = 0.02 by 3 % (README).

  Before issue 11 the check ran with its own solver settings (Newton 1e-6,
  NLGS 1e-8 with relaxation 1 and 5000 sweeps, 50 Newton iterations,
  max_penetration h/4, the iteration matrix refactored at every step, no
  Delassus drop); it now runs the production ones.

Outputs in ``--out DIR`` (default ``runs/single-disk``):

``force_2d.csv``  ``eps,f_norm``
    f = mean of the two plates' forces (per unit length, N/m), f_norm =
    f/(D mu) = f/(D l mu) with f the force per length l. The two plates'
    forces differ by the inertia and damping forces only (the largest
    difference is in run_2d.json). eps =
    -ln(1 - delta/D), delta the sum of the two plates' displacements, D the
    nominal diameter. One row per driver output (every ``--every`` steps).
``profile_2d.csv``  ``eps,w,ux_over_D``
    the displacement u_x/D along the Lagrangian transverse diameter (the
    material line Y = 0, perpendicular to the loading), w = X/R in [-1, 1]
    (the same normalisation as ``profile_3d_*.csv`` of
    :mod:`softpack.references.cylinder3d`), at eps = 0.05, 0.10, 0.15, 0.20: the P1
    field is interpolated in space (barycentric, in the reference
    triangle containing (X, 0)) and linearly in eps between the two
    bracketing field outputs; u_x(0, 0) (the centre's rigid drift) is
    subtracted.
``run_2d.json``
    parameters, mesh size, run time, the largest plate-force mismatch,
    energies, the centre's drift, the largest rigid rotation (rolling).
``sim/``
    the run directory: config.toml (the resolved configuration),
    driver.json, mesh/, raw/, fields.h5, driver.log.

The small-strain limit (Johnson, Contact Mechanics, §5.5, line contact
between two plates) is :func:`softpack.reference3d.johnson_line_contact` with
nu = 1/3, plane strain (E* = E/(1 - nu^2) = 3 mu).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table, write_table
from softpack.references import between_plates
from softpack.references.between_plates import (Params, SingleDiskError,
                                                config_data, force_curve,
                                                read_fields, refused)
from softpack.references.p1_fields import (interpolate, line_interpolator,
                                           rigid_rotation)
from softpack.scene.config import validate

#: Strains of the Fig. 3 profiles.
PROFILE_STRAINS = (0.05, 0.10, 0.15, 0.20)
#: w = X/R of the profile rows (the 3D CSVs' grid).
PROFILE_W = np.round(np.linspace(-1.0, 1.0, 41), 10)
#: The configuration's name in messages.
SOURCE = "single-disk"


# ---------------------------------------------------------------- set-up

def single_disk_config(params: Params, y_bottom=None, y_top=None):
    """The validated configuration (plates at +-R unless given).

    Raises
    ------
    softpack.scene.config.ConfigError
    """
    if y_bottom is None:
        y_bottom, y_top = -params.radius, params.radius
    return validate(config_data(params, y_bottom, y_top), SOURCE)


def simulate(params: Params, sim_dir, quiet=True) -> dict:
    """Scene, driver.json and softpack-simulate in ``sim_dir``
    (:func:`softpack.references.between_plates.simulate`), the mesh turned
    node-up unless ``params.orientation`` says otherwise.

    Returns a dict with the configuration, the mesh size, the plates'
    initial positions and the driver's wall time.
    """
    turn = None
    if params.orientation == "node_up":
        turn = lambda mesh_h5: put_node_up(mesh_h5, params.radius)  # noqa: E731
    meta = between_plates.simulate(single_disk_config, params, sim_dir,
                                   "disk", turn)
    meta["boundary_nodes"] = int(np.sum(on_circle(
        meta.pop("node_coordinates"), params.radius)))
    return meta


def on_circle(x, radius) -> np.ndarray:
    """Mask of the nodes on the disk's circle (the boundary nodes)."""
    return np.abs(np.hypot(x[:, 0], x[:, 1]) - radius) < 1e-9 * radius


def put_node_up(mesh_h5, radius) -> float:
    """Rotate a disk mesh about its centre: a boundary node on the +y axis.

    gmsh puts the n boundary nodes at the angles 2 pi k / n, so the node
    nearest the top is generally a little off the loading axis (for the
    paper's h = 1.065 mm and D = 20 mm, n = 59, by 0.027 rad). Turned so
    that one node is at angle pi/2, the boundary polygon is mirror-symmetric
    about the loading axis (for any n; for an even n a node is also at
    -pi/2), so that the two plates touch it symmetrically. Rewrites the
    geometry of ``mesh_h5`` in place; returns the angle (rad).
    """
    import h5py

    with h5py.File(mesh_h5, "r+") as f:
        geometry = f["/Mesh/mesh/geometry"]
        x = np.array(geometry)
        boundary = on_circle(x[:, :2], radius)
        angles = np.arctan2(x[boundary, 1], x[boundary, 0])
        angle = float(math.pi / 2 - angles[np.argmax(x[boundary, 1])])
        c, s = math.cos(angle), math.sin(angle)
        y = x.copy()
        y[:, 0] = c * x[:, 0] - s * x[:, 1]
        y[:, 1] = s * x[:, 0] + c * x[:, 1]
        geometry[...] = y
    return angle


# ---------------------------------------------------------------- reading

def transverse_profiles(fields_h5, steps, curve, params: Params,
                        strains=PROFILE_STRAINS, w=PROFILE_W) -> dict:
    """eps -> u_x/D at w = X/R on the material line Y = 0.

    The field of each output is matched to its row of steps.csv by time;
    at each target strain the two bracketing outputs are interpolated
    linearly in eps. u_x at the centre (X = Y = 0) is subtracted.
    """
    x, cells, snaps = read_fields(fields_h5)
    points = np.column_stack([w * params.radius, np.zeros_like(w)])
    stencil = line_interpolator(x, cells, np.vstack([points, [0.0, 0.0]]))
    times = np.array([t for t, _ in snaps])
    tol = 0.5 * params.time_step
    eps_of = np.interp(times, steps["time"], curve["eps"])
    if np.any(np.abs(np.interp(times, steps["time"], steps["time"]) - times)
              > tol):
        raise SingleDiskError("field output times do not match steps.csv")
    profiles, drift = {}, 0.0
    for target in strains:
        if target > eps_of[-1]:
            continue  # a run stopped below this strain
        after = int(np.searchsorted(eps_of, target))
        if after == 0 or after >= len(snaps):
            raise SingleDiskError(f"no field output brackets eps = {target}"
                                  f" (outputs reach {eps_of[-1]:.4f})")
        e0, e1 = eps_of[after - 1], eps_of[after]
        s = (target - e0) / (e1 - e0)
        u = (1 - s) * snaps[after - 1][1] + s * snaps[after][1]
        values = interpolate(u, cells, stencil)
        drift = max(drift, abs(values[-1, 0]))
        profiles[target] = (values[:-1, 0] - values[-1, 0]) / params.diameter
    profiles["centre_drift_over_D"] = drift / params.diameter
    profiles["max_rotation_rad"] = float(max(
        abs(rigid_rotation(x, cells, u)) for _, u in snaps))
    return profiles


# ---------------------------------------------------------------- run

def run(params: Params, out_dir, quiet=True) -> dict:
    """Simulate and write force_2d.csv, profile_2d.csv, run_2d.json."""
    out_dir = Path(out_dir)
    sim = RunDirectory(out_dir / "sim")
    started = time.time()
    meta = simulate(params, sim.path, quiet)
    steps = read_table(sim.raw.steps_csv)
    mu = meta["config"]["material"]["parameters"]["shear_modulus"]
    curve = force_curve(steps, params.diameter, meta["y_bottom0"],
                        meta["y_top0"], mu)
    profiles = transverse_profiles(sim.fields_h5, steps, curve, params)
    write_outputs(out_dir, params, steps, curve, profiles, meta,
                  time.time() - started)
    return {"curve": curve, "profiles": profiles, "meta": meta,
            "steps": steps}


def write_outputs(out_dir, params, steps, curve, profiles, meta, seconds):
    """force_2d.csv, profile_2d.csv, run_2d.json into out_dir."""
    out_dir = Path(out_dir)
    # every row up to the first at or beyond max_strain
    last = int(np.searchsorted(curve["eps"], params.max_strain - 1e-12))
    keep = np.arange(len(curve["eps"])) <= last
    write_table(out_dir / "force_2d.csv",
                {"eps": curve["eps"][keep], "f_norm": curve["f_norm"][keep]})
    rows = np.array([(e, w, u) for e in PROFILE_STRAINS if e in profiles
                     for w, u in zip(PROFILE_W, profiles[e])]).reshape(-1, 3)
    write_table(out_dir / "profile_2d.csv",
                {"eps": rows[:, 0], "w": rows[:, 1], "ux_over_D": rows[:, 2]})
    loaded = curve["f_norm"] > 0.0
    mismatch = np.abs(curve["f_norm_top"] - curve["f_norm_bottom"])[loaded]
    energy = {key: float(steps[key][keep][-1]) for key in
              ("strain_energy", "kinetic_energy", "wall_work", "damping",
               "friction", "numerical", "energy_residual") if key in steps}
    config = meta["config"]
    doc = {"params": asdict(params),
           "settings": {name: config[name] for name in
                        ("material", "contact", "time", "damping", "stop")},
           "mesh": {
        "triangles": meta["triangles"], "nodes": meta["nodes"],
        "boundary_nodes": meta["boundary_nodes"],
        "rotation_rad": meta["mesh_rotation_rad"]},
        "plates_initial_y": [meta["y_bottom0"], meta["y_top0"]],
        "steps": int(steps["step"][-1]),
        "driver_seconds": round(meta["driver_seconds"], 1),
        "total_seconds": round(seconds, 1),
        "max_plate_force_mismatch_f_norm": float(mismatch.max())
        if mismatch.size else 0.0,
        "max_penetration_m": float(np.nanmax(steps["max_penetration"])),
        "centre_drift_over_D": profiles["centre_drift_over_D"],
        "max_rigid_rotation_rad": profiles["max_rotation_rad"],
        "energies_at_end_J_per_m": energy,
        "eps": "-ln(1 - delta/D), delta = sum of the plates' displacements",
        "f_norm": "mean plate force per unit length / (D mu)",
        "w": "X/R on the material line Y = 0; u_x relative to the centre"}
    (out_dir / "run_2d.json").write_text(json.dumps(doc, indent=1) + "\n")


def value_at(curve, eps) -> np.ndarray:
    """f_norm interpolated at the given strains."""
    return np.interp(eps, curve["eps"], curve["f_norm"])


def _parser():
    from softpack import cli

    p = argparse.ArgumentParser(
        prog="softpack single-disk",
        description="2D plane-strain neo-Hookean disk between two rigid "
        "frictionless plates (paper Figs. 2-3): writes DIR/force_2d.csv "
        "(eps,f_norm) and DIR/profile_2d.csv (eps,w,ux_over_D).")
    d = Params()
    between_plates.add_plate_arguments(p, d, Path("runs/single-disk"))
    p.add_argument("--orientation", choices=("node_up", "as_meshed"),
                   default=d.orientation,
                   help="node_up (default): turn the mesh so that a boundary"
                   " node lies on the loading axis; as_meshed: as gmsh made"
                   " it")
    between_plates.add_material_arguments(p)
    p.add_argument("--shape", choices=("disk", "square", "pentagon",
                                       "cylinder"),
                   default="disk",
                   help="disk (default, this check); square or pentagon:"
                   " a rounded polygon against a static dolfinx solve of"
                   " the same mesh (softpack.references.plates; see"
                   " --shape square --help); cylinder: a standing cylinder"
                   " through the 3D driver (softpack.references."
                   "cylinder_plates; see --shape cylinder --help)")
    return p


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    shape = argparse.ArgumentParser(add_help=False)
    shape.add_argument("--shape")
    chosen = shape.parse_known_args(argv)[0].shape
    if chosen in ("square", "pentagon"):
        from softpack.references import plates
        return plates.main(argv)
    if chosen == "cylinder":
        from softpack.references import cylinder_plates
        return cylinder_plates.main(argv)
    args = _parser().parse_args(argv)
    params = Params(diameter=args.diameter, element_size=args.element_size,
                    max_strain=args.max_strain, speed=args.speed,
                    time_step=args.time_step, alpha=args.alpha,
                    friction=args.friction,
                    every=args.every, orientation=args.orientation,
                    lame_lambda=args.lame_lambda, law=args.law)
    if params.max_strain < max(PROFILE_STRAINS):
        print("softpack single-disk: note: --max-strain < 0.2: the"
              " profiles beyond it are not written", flush=True)
    if refused(params, single_disk_config, args.out):
        return 2
    print(f"softpack single-disk: D = {params.diameter:g} m, h ="
          f" {params.element_size:g} m, up to eps = {params.max_strain:g}"
          f" ({int(round(params.duration / params.time_step))} steps) ->"
          f" {args.out}", flush=True)
    try:
        result = run(params, args.out)
    except (SingleDiskError, RunError) as err:
        print(f"softpack single-disk: {err}", file=sys.stderr)
        return 1
    curve, meta = result["curve"], result["meta"]
    from softpack.references.cylinder3d import johnson_line_contact
    parameters = meta["config"]["material"]["parameters"]
    lam, mu = parameters["lame_lambda"], parameters["shear_modulus"]
    nu = lam / (2 * (lam + mu))
    for e in (0.01, 0.05, 0.10, 0.15, 0.20):
        if e <= curve["eps"][-1]:
            print(f"  eps = {e:.2f}: f_norm = {value_at(curve, e):.5g}"
                  f"  (Johnson nu = {nu:.4g}: "
                  f"{johnson_line_contact(e, nu)[0]:.5g})")
    print(f"softpack single-disk: {meta['triangles']} triangles, driver"
          f" {meta['driver_seconds']:.0f} s; wrote {args.out}/force_2d.csv,"
          " profile_2d.csv, run_2d.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
