"""``./softpack adhesion``: a soft disk pressed on a cohesive flat, pulled off.

The adhesion check of issue 39 (docs/adhesion/README.md): one neo-Hookean
disk (the paper's material, mu = 0.15 MPa, lambda~ = 2 mu: plane strain
nu = 1/3, E* = E / (1 - nu^2) = 3 mu), D = 20 mm, between two rigid plates
run by the project's driver (Moreau–Jean, theta = 0.6: theta = 1/2
diverges on the fine meshes, docs/adhesion/README.md; NLGS):

* the BOTTOM plate is cohesive (``law = "cohesive"``, docs/contact_laws.md:
  a Dugdale zone of tension sigma_c within the gap g_c, w = sigma_c g_c),
  frictionless (the theory's contact is frictionless);
* the TOP plate is bonded (``law = "bonded"``, strengths far above any
  force of the run) to the nodes within ``TOP_BOND`` of it at the first
  step: it holds the disk in tension and pins its rolling and sliding, so
  the force on the bottom plate is the one cohesive contact's;
* both plates move towards the centre at ``speed`` (the centre stays at
  rest: the mass-proportional damping does not act on a translation) by
  ``press`` each, then apart at the same speed by ``pull`` each (two
  stages ending on ``stop.strain``).

The disk is a gmsh mesh (:func:`disk_mesh`, ``shape = "msh"``) of size
``h_fine`` on the arc |x| < ``fine_arc`` around the lowest point (a node on
the axis), growing by ``GROWTH`` per unit distance from it to ``h_coarse``.

Measured (:mod:`softpack.references.adhesion_measure`): the bottom plate's
force P (N/m, compressive > 0), the contact half-width a (the edge of the
closed nodes, whose reaction is above the cohesion's bound) and the
cohesive zone's edge c, against :mod:`softpack.references.adhesion_theory`.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import asdict, dataclass
from pathlib import Path

from softpack.references import between_plates
from softpack.scene.config import validate

#: The size grows by this per unit distance from the fine arc.
GROWTH = 0.3
#: The top plate bonds to the nodes within this of it at the first step, m.
TOP_BOND = 1.0e-4
#: The bond's strengths, Pa: far above any traction of the run.
TOP_STRENGTH = 1.0e9
SOURCE = "adhesion"


@dataclass
class Params:
    """The adhesion protocol (SI units). Defaults: Baney & Hui's lambda =
    2.5 (the cohesive zone's length comparable with a: c/a = 1.54 at the
    pull-off), a_0 = 0.91 mm = 0.09 R."""

    diameter: float = 0.020
    cohesion: float = 2.8e4          # sigma_c, Pa
    cohesive_distance: float = 1.57e-5  # g_c, m
    h_fine: float = 2.5e-5
    h_coarse: float = 1.0e-3
    fine_arc: float = 2.5e-3         # half-length of the fine arc, m
    speed: float = 1.0e-3            # each plate, m/s
    press: float = 1.0e-4            # each plate's travel, pressing, m
    pull: float = 2.0e-4             # ... pulling
    time_step: float = 5.0e-5
    theta: float = 0.6               # 0.5 diverges on fine meshes (README)
    alpha: float = 200.0
    every: int = 20

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter


def disk_mesh(path, radius, h_fine, h_coarse, fine_arc) -> int:
    """Write a gmsh disk mesh, fine near (0, -radius); return triangles."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("adhesion_disk")
        geo = gmsh.model.geo
        centre = geo.addPoint(0, 0, 0)
        half = fine_arc / radius
        angles = (-math.pi / 2 - half, -math.pi / 2, -math.pi / 2 + half,
                  math.pi / 2)
        points = [geo.addPoint(radius * math.cos(t), radius * math.sin(t), 0)
                  for t in angles]
        arcs = [geo.addCircleArc(points[i], centre, points[(i + 1) % 4])
                for i in range(4)]
        geo.addPlaneSurface([geo.addCurveLoop(arcs)])
        geo.synchronize()
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "EdgesList", arcs[:2])
        field.setNumber(distance, "NNodesByEdge",
                        int(4 * fine_arc / h_fine))
        size = field.add("MathEval")
        field.setString(size, "F", f"Min({h_coarse}, {h_fine} + {GROWTH}"
                        f" * F{distance})")
        field.setAsBackgroundMesh(size)
        for key in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints",
                    "MeshSizeFromCurvature"):
            gmsh.option.setNumber("Mesh." + key, 0)
        gmsh.model.mesh.generate(2)
        _, _, nodes = gmsh.model.mesh.getElements(2)
        gmsh.write(str(path))
        return len(nodes[0]) // 3
    finally:
        gmsh.finalize()


def config_data(params: Params, mesh_file, y_bottom, y_top) -> dict:
    """The run's configuration as TOML data (module doc)."""
    v, l0 = params.speed, y_top - y_bottom
    return {
        "box": {"enabled": False},
        "species": [{"name": "disk", "shape": "msh", "file": str(mesh_file),
                     "diameter": params.diameter, "count": 1,
                     "orientation": "fixed", "angle": 0.0}],
        "mesh": {"element_size": params.h_coarse},
        "walls": {"bottom": {"point": [0.0, y_bottom], "normal": [0.0, 1.0],
                             "velocity": [0.0, v]},
                  "top": {"point": [0.0, y_top], "normal": [0.0, -1.0],
                          "velocity": [0.0, -v]}},
        "friction": [
            {"species": "disk", "against": "bottom", "coefficient": 0.0,
             "law": "cohesive", "cohesion": params.cohesion,
             "cohesive_distance": params.cohesive_distance},
            {"species": "disk", "against": "top", "coefficient": 0.0,
             "law": "bonded", "tensile_strength": TOP_STRENGTH,
             "shear_strength": TOP_STRENGTH, "bonding_distance": TOP_BOND}],
        "stages": [
            {"name": "press", "stop": {"strain": 2 * params.press / l0,
                                       "max_time": 2 * params.press / v}},
            {"name": "pull",
             "walls": {"bottom": {"velocity": [0.0, -v]},
                       "top": {"velocity": [0.0, v]}},
             "stop": {"strain": 2 * params.pull / (l0 - 2 * params.press),
                      "strain_wall": "bottom",
                      "max_time": 2 * params.pull / v}}],
        "stop": {"packing_fraction": 0.0},
        "contact": {"friction": 0.0, "nlgs_tolerance": 1e-8},
        "time": {"time_step": params.time_step, "theta": params.theta,
                 "max_step_factor": 1.0},
        "damping": {"alpha": params.alpha},
        "output": {"every_steps": params.every, "fields": True,
                   "fields_every": 1, "state": False},
    }


def simulate(params: Params, out_dir) -> dict:
    """Mesh, scene, driver.json and softpack-simulate in ``out_dir/sim``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    mesh_file = (out_dir / "disk.msh").resolve()
    triangles = disk_mesh(mesh_file, params.radius, params.h_fine,
                          params.h_coarse, params.fine_arc)

    def config_of(p, y_bottom=None, y_top=None):
        if y_bottom is None:
            y_bottom, y_top = -p.radius, p.radius
        return validate(config_data(p, mesh_file, y_bottom, y_top), SOURCE)

    meta = between_plates.simulate(config_of, params, out_dir / "sim",
                                   "disk")
    meta.pop("node_coordinates")
    meta["gmsh_triangles"] = triangles
    return meta


def _parser():
    from softpack import cli

    d = Params()
    p = argparse.ArgumentParser(
        prog="softpack adhesion",
        description="A neo-Hookean disk pressed on a cohesive rigid flat "
        "and pulled off, against the Maugis-Dugdale and JKR line contact "
        "(docs/adhesion/README.md).")
    for name, value, unit in (
            ("cohesion", d.cohesion, "sigma_c, Pa"),
            ("cohesive-distance", d.cohesive_distance, "g_c, m"),
            ("h-fine", d.h_fine, "element size at the contact, m"),
            ("h-coarse", d.h_coarse, "element size far from it, m"),
            ("speed", d.speed, "each plate, m/s"),
            ("press", d.press, "each plate's travel pressing, m"),
            ("pull", d.pull, "each plate's travel pulling, m"),
            ("time-step", d.time_step, "s"),
            ("theta", d.theta, "Moreau-Jean theta")):
        p.add_argument("--" + name, type=cli.positive_float, default=value,
                       help=f"{unit} (default {value:g})")
    p.add_argument("--every", type=cli.positive_int, default=d.every,
                   help=f"output every this many steps (default {d.every})")
    p.add_argument("--out", type=Path, required=True,
                   help="output directory (sim/, result.json)")
    return p


def main(argv=None) -> int:
    from softpack.contract.run_directory import RunError
    from softpack.references import adhesion_measure

    args = _parser().parse_args(argv)
    params = Params(cohesion=args.cohesion,
                    cohesive_distance=args.cohesive_distance,
                    h_fine=args.h_fine, h_coarse=args.h_coarse,
                    speed=args.speed, press=args.press, pull=args.pull,
                    time_step=args.time_step, theta=args.theta,
                    every=args.every)
    try:
        meta = simulate(params, args.out)
        result = adhesion_measure.measure(args.out / "sim", params)
    except (RunError, adhesion_measure.MeasureError) as err:
        print(f"softpack adhesion: {err}", file=sys.stderr)
        return 1
    result["params"] = asdict(params)
    result["mesh"] = {"triangles": meta["triangles"], "nodes": meta["nodes"]}
    result["driver_seconds"] = round(meta["driver_seconds"], 1)
    (Path(args.out) / "result.json").write_text(
        json.dumps(result, indent=1) + "\n")
    print(adhesion_measure.summary(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
