"""A user's particle shape: a gmsh geometry (.geo) or mesh (.msh) file.

``shape = "geo"``: any gmsh geometry of one plane surface, in any units; it
is meshed in its own units at element size h / s and scaled by s so that its
meshed area is the given area (pi D^2 / 4, D the species' equal-area
diameter: :mod:`softpack.scene.shapes` finds the file and asks), then
centred on its area centroid. ``shape = "msh"``: an existing gmsh mesh of
one particle, its triangles scaled and centred the same way.

gmsh aborts its process on some malformed files (an open curve loop throws
a C++ string that nothing catches), so the file is read in a child process
(``python -m softpack.scene.user_shapes``); its failure is a
:class:`~softpack.scene.triangulation.MeshingError` carrying gmsh's own
message.
The checks every template passes are :mod:`softpack.scene.shapes`'.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from softpack.scene.triangulation import (MeshingError, centred,
                                          gmsh_errors, initialize_gmsh,
                                          mesh_geometry, oriented,
                                          polygon_area, surface_mesh)

#: Element size of the first pass that measures a .geo shape's area, as a
#: fraction of its bounding box diagonal.
PROBE_SIZE = 1.0 / 60


def _scaled_geo(gmsh, path, area, h):
    """A user's .geo meshed so that, scaled by s, its area is ``area``."""
    try:
        gmsh.open(str(path))
    except Exception as err:
        raise MeshingError(gmsh_errors(gmsh, err)) from None
    try:
        box = np.array(gmsh.model.getBoundingBox(-1, -1))
    finally:
        gmsh.model.remove()
    diagonal = float(np.linalg.norm(box[3:5] - box[0:2]))
    if not np.isfinite(diagonal) or diagonal <= 0:
        raise MeshingError("the geometry is empty")
    probe = mesh_geometry(gmsh, path, {}, PROBE_SIZE * diagonal)
    scale = math.sqrt(area / polygon_area(*probe))
    points, triangles = mesh_geometry(gmsh, path, {}, h / scale)
    scale = math.sqrt(area / polygon_area(points, triangles))
    return centred(points * scale, triangles), triangles


def _scaled_msh(gmsh, path, area, h):
    """A user's .msh: its triangles, scaled to ``area``."""
    try:
        gmsh.open(str(path))
        points, triangles = surface_mesh(gmsh, -1)
    except MeshingError:
        raise
    except Exception as err:
        raise MeshingError(gmsh_errors(gmsh, err)) from None
    finally:
        gmsh.model.remove()
    points, triangles = oriented(points, triangles)
    scale = math.sqrt(area / polygon_area(points, triangles))
    return centred(points * scale, triangles), triangles


def user_mesh(shape, path, area, h):
    """A user's .geo or .msh meshed and scaled to ``area`` (m^2), in a
    child process.

    gmsh aborts its process on some malformed files (an open curve loop
    throws a C++ string that nothing catches), so a user's file is read by
    ``python -m softpack.scene.user_shapes`` (:func:`main`) and a crash becomes a
    :class:`MeshingError`.
    """
    import os
    import subprocess
    import sys
    import tempfile

    package = str(Path(__file__).resolve().parents[2])
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        p for p in (package, env.get("PYTHONPATH")) if p)
    with tempfile.TemporaryDirectory(prefix="softpack-shape-") as tmp:
        out = Path(tmp) / "mesh.npz"
        proc = subprocess.run(
            [sys.executable, "-m", "softpack.scene.user_shapes", shape, str(path),
             repr(float(area)), repr(float(h)), str(out)],
            capture_output=True, text=True, env=env)
        if proc.returncode == 0:
            with np.load(out) as data:
                return data["points"], data["triangles"]
    said = [line for line in proc.stderr.splitlines() if line.strip()]
    if proc.returncode == CHILD_REFUSED and said:
        raise MeshingError(said[-1])
    # gmsh's own messages (General.Terminal = 1 in the child) say why
    crash = [line.strip() for line in (proc.stdout + proc.stderr).splitlines()
             if "Error" in line]
    raise MeshingError(f"gmsh crashed reading it (exit status"
                       f" {proc.returncode}): " + "; ".join(crash[-3:]))


#: Exit status of :func:`main` when gmsh refused the file cleanly.
CHILD_REFUSED = 3


def main(argv=None) -> int:
    """``python -m softpack.scene.user_shapes geo|msh FILE AREA H OUT.npz``:
    the child process of :func:`user_mesh`."""
    import sys

    import gmsh

    shape, path, area, h, out = argv or sys.argv[1:]
    initialize_gmsh(gmsh)
    gmsh.option.setNumber("General.Terminal", 1)  # its errors, if it aborts
    gmsh.logger.start()
    try:
        points, triangles = (_scaled_geo if shape == "geo" else _scaled_msh)(
            gmsh, Path(path), float(area), float(h))
    except MeshingError as err:
        print(err, file=sys.stderr)
        return CHILD_REFUSED
    finally:
        gmsh.finalize()
    np.savez(out, points=points, triangles=triangles)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
