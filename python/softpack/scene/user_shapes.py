"""A user's particle shape: a gmsh geometry (.geo) or mesh (.msh) file.

``shape = "geo"``: any gmsh geometry of one plane surface, in any units; it
is meshed in its own units at element size h / s and scaled by s so that its
meshed area is pi D^2 / 4 (D the species' equal-area diameter), then centred
on its area centroid. ``shape = "msh"``: an existing gmsh mesh of one
particle, its triangles scaled and centred the same way.

gmsh aborts its process on some malformed files (an open curve loop throws
a C++ string that nothing catches), so the file is read in a child process
(``python -m softpack.scene.user_shapes``); its failure is a
:class:`~softpack.scene.shapes.MeshingError` carrying gmsh's own message.
The checks every template passes are :mod:`softpack.scene.shapes`'.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from softpack.paths import MESHES
from softpack.scene.shapes import (MeshingError, ShapeError, _centred,
                                   _gmsh_errors, _oriented, _polygon_area,
                                   _surface_mesh, exact_area, mesh_geometry)

#: Element size of the first pass that measures a .geo shape's area, as a
#: fraction of its bounding box diagonal.
PROBE_SIZE = 1.0 / 60


def user_file(spec, where, base=None) -> Path:
    """The ``file`` of a geo/msh species: as given, next to the TOML file
    (``base``), then in ``meshes/``.

    Raises
    ------
    ShapeError
        When it is not found or has the wrong suffix.
    """
    name = spec["file"]
    suffix = "." + spec["shape"]
    if not name:
        raise ShapeError(f"{where} file: missing; shape = {spec['shape']!r}"
                         f" needs a gmsh {suffix} file")
    path = Path(name).expanduser()
    tried = [path] if path.is_absolute() else [
        *([Path(base) / path] if base is not None else []), path,
        MESHES / path]
    for candidate in tried:
        if candidate.is_file():
            if candidate.suffix.lower() != suffix:
                raise ShapeError(f"{where} file = {name!r}: shape ="
                                 f" {spec['shape']!r} needs a {suffix} file")
            return candidate.resolve()
    raise ShapeError(f"{where} file = {name!r}: not found (looked in: "
                     + ", ".join(str(p) for p in tried) + ")")


def _scaled_geo(gmsh, path, diameter, h):
    """A user's .geo meshed so that, scaled by s, its area is pi D^2 / 4."""
    try:
        gmsh.open(str(path))
    except Exception as err:
        raise MeshingError(_gmsh_errors(gmsh, err)) from None
    try:
        box = np.array(gmsh.model.getBoundingBox(-1, -1))
    finally:
        gmsh.model.remove()
    diagonal = float(np.linalg.norm(box[3:5] - box[0:2]))
    if not np.isfinite(diagonal) or diagonal <= 0:
        raise MeshingError("the geometry is empty")
    probe = mesh_geometry(gmsh, path, {}, PROBE_SIZE * diagonal)
    scale = math.sqrt(exact_area(diameter) / _polygon_area(*probe))
    points, triangles = mesh_geometry(gmsh, path, {}, h / scale)
    scale = math.sqrt(exact_area(diameter) / _polygon_area(points, triangles))
    return _centred(points * scale, triangles), triangles


def _scaled_msh(gmsh, path, diameter, h):
    """A user's .msh: its triangles, scaled to area pi D^2 / 4."""
    try:
        gmsh.open(str(path))
        points, triangles = _surface_mesh(gmsh, -1)
    except MeshingError:
        raise
    except Exception as err:
        raise MeshingError(_gmsh_errors(gmsh, err)) from None
    finally:
        gmsh.model.remove()
    points, triangles = _oriented(points, triangles)
    scale = math.sqrt(exact_area(diameter) / _polygon_area(points, triangles))
    return _centred(points * scale, triangles), triangles


def user_mesh(shape, path, diameter, h):
    """A user's .geo or .msh meshed and scaled, in a child process.

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
             repr(float(diameter)), repr(float(h)), str(out)],
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
    """``python -m softpack.scene.user_shapes geo|msh FILE D H OUT.npz``: the
    child process of :func:`user_mesh`."""
    import sys

    import gmsh

    from softpack.scene.mesh import initialize_gmsh

    shape, path, diameter, h, out = argv or sys.argv[1:]
    initialize_gmsh(gmsh)
    gmsh.option.setNumber("General.Terminal", 1)  # its errors, if it aborts
    gmsh.logger.start()
    try:
        points, triangles = (_scaled_geo if shape == "geo" else _scaled_msh)(
            gmsh, Path(path), float(diameter), float(h))
    except MeshingError as err:
        print(err, file=sys.stderr)
        return CHILD_REFUSED
    finally:
        gmsh.finalize()
    np.savez(out, points=points, triangles=triangles)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
