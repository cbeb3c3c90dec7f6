"""Tetrahedral sphere meshes for the 3D time-step tests (gmsh, OpenCASCADE).

    sphere_meshes.py pair OUT.xdmf --diameter D --element-size H --gap G [--offset Y]
        two spheres of diameter D, centred at (-(D + G) / 2, -Y / 2, 0) and
        ((D + G) / 2, Y / 2, 0): bodies 0 and 1
    sphere_meshes.py graded OUT.xdmf --diameter D --element-size H --pole-size P
        one sphere at the origin, element size P at the poles (0, 0, +-D/2)
        growing by G (default 0.5) per unit distance from the plane of each
        pole, up to H
    sphere_meshes.py brick OUT.xdmf --diameter D --element-size H
        one box of D x 0.7 D x 0.4 D centred at the origin (three distinct
        principal moments of inertia: an asymmetric top)

The file is the driver's XDMF layout (softpack.scene.mesh.write_xdmf).
"""
import argparse
from pathlib import Path

import numpy as np

from softpack.scene.solids import _compact, initialize_gmsh, write_solids


def tetrahedra(name, geometry):
    """Nodes and positively oriented tetrahedra of the gmsh model that
    geometry(gmsh) builds and sets the options of."""
    import gmsh

    initialize_gmsh(gmsh)
    try:
        gmsh.model.add(name)
        geometry(gmsh)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, _, nodes = gmsh.model.mesh.getElements(3)
    finally:
        gmsh.finalize()
    return _compact(tags, coords.reshape(-1, 3), nodes[0])


def sphere(diameter, element_size, pole_size=None, growth=0.5, octant=False):
    """Nodes and positively oriented tetrahedra of a sphere at the origin
    (or of its octant x, y, z >= 0)."""
    def geometry(gmsh):
        r = diameter / 2
        ball = gmsh.model.occ.addSphere(0, 0, 0, r)
        if octant:
            box = gmsh.model.occ.addBox(0, 0, 0, 2 * r, 2 * r, 2 * r)
            gmsh.model.occ.intersect([(3, ball)], [(3, box)])
        gmsh.model.occ.synchronize()
        options = [("Mesh.MeshSizeFromCurvature", 0), ("Mesh.Algorithm", 1),
                   ("Mesh.ElementOrder", 1), ("Mesh.MeshSizeMax", element_size)]
        if pole_size is None:
            options.append(("Mesh.MeshSizeMin", element_size))
        else:
            field = gmsh.model.mesh.field
            f = field.add("MathEval")
            field.setString(f, "F", f"min({element_size}, {pole_size} + "
                                    f"{growth} * ({r} - abs(z)))")
            field.setAsBackgroundMesh(f)
            options += [("Mesh.MeshSizeExtendFromBoundary", 0),
                        ("Mesh.MeshSizeFromPoints", 0)]
        for name, value in options:
            gmsh.option.setNumber(name, value)

    return tetrahedra("sphere", geometry)


def brick(diameter, element_size):
    """Nodes and positively oriented tetrahedra of the box D x 0.7 D x 0.4 D
    centred at the origin."""
    def geometry(gmsh):
        size = np.array([1.0, 0.7, 0.4]) * diameter
        gmsh.model.occ.addBox(*(-size / 2), *size)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", element_size)
        gmsh.option.setNumber("Mesh.ElementOrder", 1)

    return tetrahedra("brick", geometry)


def mirrored(points, tets):
    """The octant's eight mirror images, the nodes of the planes shared."""
    parts, cells, offset = [], [], 0
    for signs in np.ndindex(2, 2, 2):
        factor = np.where(np.array(signs) == 1, -1.0, 1.0)
        parts.append(points * factor)
        t = tets + offset
        cells.append(t[:, [0, 1, 3, 2]] if np.prod(factor) < 0 else t)
        offset += len(points)
    allpts = np.vstack(parts)
    key = np.round(allpts / (1e-9 * np.abs(points).max())).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True,
                                  return_inverse=True)
    return allpts[first], inverse.reshape(-1)[np.vstack(cells)]


def main(argv=None):
    p = argparse.ArgumentParser()
    p.add_argument("kind", choices=("pair", "graded", "octant", "mirrored",
                                     "brick"))
    p.add_argument("out", type=Path)
    p.add_argument("--diameter", type=float, required=True)
    p.add_argument("--element-size", type=float, required=True)
    p.add_argument("--gap", type=float, default=0.0)
    p.add_argument("--offset", type=float, default=0.0)
    p.add_argument("--pole-size", type=float)
    p.add_argument("--growth", type=float, default=0.5)
    a = p.parse_args(argv)
    a.out.parent.mkdir(parents=True, exist_ok=True)
    if a.kind == "brick":
        write_solids(a.out, *brick(a.diameter, a.element_size))
        return 0
    if a.kind in ("graded", "octant", "mirrored"):
        points, tets = sphere(a.diameter, a.element_size, a.pole_size,
                              a.growth, a.kind != "graded")
        if a.kind == "mirrored":
            points, tets = mirrored(points, tets)
        write_solids(a.out, points, tets)
        return 0
    points, tets = sphere(a.diameter, a.element_size)
    shift = np.array([(a.diameter + a.gap) / 2, a.offset / 2, 0.0])
    both = np.vstack([points - shift, points + shift])
    cells = np.vstack([tets, tets + len(points)])
    body = np.repeat(np.arange(2, dtype=np.int32), len(tets))
    write_solids(a.out, both, cells, body)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
