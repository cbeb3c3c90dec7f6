"""One body squeezed between two rigid plates, through the production pipeline.

What the single-disk check (:mod:`softpack.references.single_disk`) and
the polygon check (:mod:`softpack.references.plates`) share: the
protocol's settings (:class:`Params`) and configuration overrides
(:func:`config_data`; the single-disk module doc explains each), the run
(:func:`simulate`: scene, plates at the mesh's extreme nodes, driver.json,
``softpack-simulate`` in ``DIR/sim``), the plates' force curve
(:func:`force_curve`), the command-line options both take
(:func:`add_plate_arguments`) and the checks before anything is meshed
(:func:`refused`).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis.strain import approach, cumulative_strain
from softpack.contract.run_directory import (RunDirectory, UsageError,
                                             check_out_directory)
from softpack.scene.config import ConfigError, to_toml


@dataclass
class Params:
    """What the single-disk protocol sets (SI units); the rest of the
    configuration is the production default (single_disk's module doc)."""

    diameter: float = 0.020
    element_size: float = 1.065e-3
    max_strain: float = 0.25
    speed: float = 0.01          # each plate, m/s (approach speed 2 speed)
    time_step: float = 1e-4
    alpha: float = 200.0
    theta: float = 0.5
    friction: float = 1e-2       # pins the rolling mode (module doc)
    every: int = 10              # output every this many steps
    orientation: str = "node_up"  # or "as_meshed" (see put_node_up)
    lame_lambda: float | None = None  # Pa; None: the material's default
    law: str | None = None       # None: the configuration's default law

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter

    @property
    def max_approach(self) -> float:
        """delta_max = D (1 - exp(-max_strain))."""
        return float(approach(self.max_strain, self.diameter))

    @property
    def duration(self) -> float:
        """Time for the two plates to approach by delta_max."""
        return self.max_approach / (2.0 * self.speed)


class SingleDiskError(RuntimeError):
    """The driver's output is unusable."""


def config_data(params: Params, y_bottom: float, y_top: float) -> dict:
    """The protocol's overrides as TOML data (single_disk's module doc),
    plates at ``y_bottom`` and ``y_top``."""
    v = params.speed
    # a few steps beyond the target so that the last output passes it
    max_time = params.duration + 2 * params.every * params.time_step
    return {
        "box": {"enabled": False},
        "species": [{"name": "disk", "shape": "disk",
                     "diameter": params.diameter, "count": 1}],
        "mesh": {"element_size": params.element_size},
        "walls": {"bottom": {"point": [0.0, y_bottom], "normal": [0.0, 1.0],
                             "velocity": [0.0, v]},
                  "top": {"point": [0.0, y_top], "normal": [0.0, -1.0],
                          "velocity": [0.0, -v]}},
        "stop": {"packing_fraction": 0.0, "max_time": max_time},
        "contact": {"friction": params.friction},
        # Fixed steps: the reference is compared at its own step.
        "time": {"time_step": params.time_step, "theta": params.theta,
                 "max_step_factor": 1.0},
        "damping": {"alpha": params.alpha},
        "output": {"every_steps": params.every, "fields": True,
                   "fields_every": 1, "state": False},
        **material_overrides(params),
    }


def material_overrides(params: Params) -> dict:
    """The [material] overrides: another law, another lambda, or none."""
    material = {}
    if params.law is not None:
        material["law"] = params.law
    if params.lame_lambda is not None:
        material["parameters"] = {"lame_lambda": params.lame_lambda}
    return {"material": material} if material else {}


def simulate(config_of, params, sim_dir, mesh_name: str,
             turn_mesh=None) -> dict:
    """Scene, driver.json and softpack-simulate in ``sim_dir``.

    Parameters
    ----------
    config_of : callable
        ``config_of(params)``: the validated configuration with the plates
        anywhere; ``config_of(params, y_bottom, y_top)``: with the plates
        at the mesh's extreme nodes (the one run).
    params
        The protocol's settings.
    sim_dir : path-like
        The run directory (driver.json, config.toml, mesh/, raw/,
        fields.*, driver.log).
    mesh_name : str
        The mesh's stem under ``mesh/``.
    turn_mesh : callable, optional
        ``turn_mesh(mesh_h5)``: rotates the mesh in place before the plates
        are placed; returns the angle (rad).

    Returns
    -------
    dict
        The configuration, the mesh (file, size), the plates' initial
        positions and the driver's wall time.

    Raises
    ------
    softpack.contract.run_directory.RunError
        The driver is not built, failed or did not finish.
    """
    from softpack.scene.build import build_scene
    from softpack.simulation import driver

    run = RunDirectory(sim_dir)
    run.path.mkdir(parents=True, exist_ok=True)
    for stale in (run.raw.done_json, run.raw.steps_csv, run.fields("h5"),
                  run.fields("xdmf")):
        stale.unlink(missing_ok=True)
    scene = build_scene(config_of(params), run.mesh_stem(mesh_name))
    rotation = turn_mesh(scene.mesh.h5) if turn_mesh is not None else 0.0
    nodes = reference_nodes(scene.mesh.h5)
    y_bottom, y_top = float(nodes[:, 1].min()), float(nodes[:, 1].max())
    config = config_of(params, y_bottom, y_top)
    run.config_toml.write_text(to_toml(config))
    started = time.time()
    driver.launch(run, config, scene.record(), log=run.driver_log)
    return {"config": config, "mesh_h5": str(scene.mesh.h5),
            "triangles": scene.mesh.n_triangles, "nodes": int(len(nodes)),
            "node_coordinates": nodes, "mesh_rotation_rad": rotation,
            "y_bottom0": y_bottom, "y_top0": y_top,
            "driver_seconds": time.time() - started}


def reference_nodes(mesh_h5) -> np.ndarray:
    """Node coordinates (n, 2) of a mesh written by mesh_disks."""
    from softpack.analysis.fields import read_mesh

    return read_mesh(mesh_h5)[0]


def read_fields(fields_h5):
    """Geometry (n, 2), triangles (k, 3), and [(time, u (n, 2))] by time."""
    from softpack.analysis.fields import read_displacements, read_mesh

    x, cells = read_mesh(fields_h5)
    return x, cells, read_displacements(fields_h5)


def force_curve(steps: dict, diameter: float, y_bottom0, y_top0,
                shear_modulus) -> dict:
    """eps, f_norm (mean of the plates), and each plate's f_norm, with
    eps = -ln(1 - delta/diameter) and f_norm = f/(diameter mu).

    The driver's wall forces are averages over the steps since the previous
    output row (docs/driver_io.md); the plates move at constant speed, so
    they belong to the approach midway between the two rows.
    """
    end = (y_top0 - steps["top_y"]) + (steps["bottom_y"] - y_bottom0)
    delta = end.copy()
    delta[1:] = 0.5 * (end[1:] + end[:-1])
    delta[np.abs(delta) < 1e-12 * diameter] = 0.0  # round-off at t = 0
    eps = cumulative_strain(delta, diameter)
    scale = diameter * shear_modulus
    top = steps["top_fy"] / scale          # the body pushes the top plate up
    bottom = -steps["bottom_fy"] / scale   # ... and the bottom plate down
    return {"eps": eps, "delta": delta, "f_norm": 0.5 * (top + bottom),
            "f_norm_top": top, "f_norm_bottom": bottom}


def add_material_arguments(parser) -> None:
    """Add --lame-lambda and --law (Params.lame_lambda, Params.law: the
    material's overrides, material_overrides())."""
    from softpack import cli

    parser.add_argument("--lame-lambda", type=cli.positive_float, default=None,
                        help="the material's lame_lambda (Pa; default the"
                        " configuration's, 2 mu: nu = 1/3); e.g. 499 mu for"
                        " a nearly incompressible nu = 0.499")
    parser.add_argument("--law", default=None,
                        help="the material's law (a file of forms/materials/;"
                        " default the configuration's, neo_hookean), e.g."
                        " neo_hookean_nodal for a nearly incompressible body"
                        " (docs/incompressible.md)")


def add_plate_arguments(parser, defaults: Params, out: Path) -> None:
    """Add the options both plate checks take (the body's size and mesh,
    the loading, the driver's step, damping, friction and output interval),
    with the check's own defaults (``defaults``, ``out``)."""
    from softpack import cli

    d = defaults
    parser.add_argument("--diameter", type=cli.positive_float,
                        default=d.diameter,
                        help=f"diameter D, equal-area for a polygon (m,"
                        f" default {d.diameter:g})")
    parser.add_argument("--element-size", type=cli.positive_float,
                        default=d.element_size,
                        help=f"triangle size h (m, default {d.element_size:g})")
    parser.add_argument("--max-strain", type=cli.positive_float,
                        default=d.max_strain,
                        help=f"final eps = -ln(1 - delta/D) (default"
                        f" {d.max_strain:g})")
    parser.add_argument("--out", type=Path, default=out,
                        help=f"output directory (default {out})")
    parser.add_argument("--speed", type=cli.positive_float, default=d.speed,
                        help=f"speed of each plate (m/s, default {d.speed:g})")
    parser.add_argument("--time-step", type=cli.positive_float,
                        default=d.time_step,
                        help=f"time step (s, default {d.time_step:g})")
    parser.add_argument("--alpha", type=cli.nonnegative_float,
                        default=d.alpha,
                        help=f"Rayleigh mass coefficient (1/s, default"
                        f" {d.alpha:g})")
    parser.add_argument("--friction", type=cli.nonnegative_float,
                        default=d.friction,
                        help=f"plate friction coefficient (default"
                        f" {d.friction:g}: pins the body's rolling; 0 ="
                        " exactly frictionless)")
    parser.add_argument("--every", type=cli.positive_int, default=d.every,
                        help=f"driver output every this many steps (default"
                        f" {d.every})")


def refused(params, config_of, out, prog="softpack single-disk") -> bool:
    """Whether ``prog`` refuses to start (exit status 2),
    having printed why: ``--max-strain`` outside (0, 1), what the schema
    refuses in ``config_of(params)``, an unusable ``out`` (made, writable).
    Nothing is meshed before."""
    if not 0 < params.max_strain < 1:
        print(f"{prog}: --max-strain must be in (0, 1)", file=sys.stderr)
        return True
    try:
        config_of(params)
        check_out_directory(out)
    except (ConfigError, UsageError) as err:
        print(f"{prog}: {err}", file=sys.stderr)
        return True
    return False
