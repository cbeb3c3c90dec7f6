"""3D bodies: linear tetrahedra of a sphere or a finite cylinder (gmsh).

The 3D counterpart of the 2D shapes (:mod:`softpack.scene.shapes`): one
solid meshed by gmsh's OpenCASCADE kernel at one absolute element size,
centred on the origin, every tetrahedron positively oriented. A cylinder
(axis along z, end faces at z = -height/2 and +height/2) is its end disk
meshed and extruded in layers of about the element size, each prism cut
into tetrahedra: its lateral faces are vertical (the meshed solid is a
prism on the meshed disk, as a standing cylinder's bottom face is). It is
written in the layout of the 2D mesh (:mod:`softpack.scene.mesh`: the mesh
named ``"mesh"``, the cell tags ``"bodies"``) with tetrahedral topology,
which the driver reads (``driver/bodies/body_mesh.h``)::

    python3 -m softpack.scene.solids sphere --diameter 0.02 \\
        --element-size 0.004 --out sphere.xdmf

``symmetry_planes`` makes a cylinder's mesh conform to the planes x = 0
and y = 0 (its disk is cut into four quarters that share their edges'
nodes): nodes lie on both planes, where roller conditions of a test hold
the solid without a rigid motion.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from softpack.scene.triangulation import MeshingError, initialize_gmsh

SHAPES = ("sphere", "cylinder", "ellipsoid")
#: A tetrahedron whose |volume| is at most this fraction of the largest
#: one's is degenerate (flat).
DEGENERATE = 1e-12


def signed_volumes(points, tets) -> np.ndarray:
    """Signed volumes of tetrahedra; positive when (b-a) x (c-a) . (d-a) > 0."""
    p = np.asarray(points)[np.asarray(tets)]
    e = p[:, 1:] - p[:, :1]
    return np.einsum("ij,ij->i", np.cross(e[:, 0], e[:, 1]), e[:, 2]) / 6


def spheroid_axes(aspect_ratio, diameter) -> tuple[float, float]:
    """Semi-axes (a along x, b the two others) of the spheroid of axis
    ratio a/b = ``aspect_ratio`` and the volume of the sphere of diameter
    D: a b^2 = (D/2)^3."""
    r = diameter / 2
    return r * aspect_ratio ** (2 / 3), r * aspect_ratio ** (-1 / 3)


def _solid(gmsh, shape, diameter, height, element_size,
           symmetry_planes) -> None:
    """The OCC volume(s) of one solid (``height``: a cylinder's height or an
    ellipsoid's aspect ratio)."""
    occ, r = gmsh.model.occ, diameter / 2
    if shape in ("sphere", "ellipsoid"):
        if symmetry_planes:
            raise ValueError("symmetry_planes: cylinders only")
        tag = occ.addSphere(0, 0, 0, r)
        if shape == "ellipsoid":
            a, b = spheroid_axes(height, diameter)
            occ.dilate([(3, tag)], 0, 0, 0, a / r, b / r, b / r)
        occ.synchronize()
        return
    disk = [(2, occ.addDisk(0, 0, -height / 2, r, r))]
    if symmetry_planes:
        # Split along x = 0 and y = 0: the quarters share those edges' nodes
        lines = [(1, occ.addLine(occ.addPoint(*a, -height / 2),
                                 occ.addPoint(*b, -height / 2)))
                 for a, b in (((-r, 0), (r, 0)), ((0, -r), (0, r)))]
        disk = [e for e in occ.fragment(disk, lines)[0] if e[0] == 2]
    occ.extrude(disk, 0, 0, height,
                numElements=[max(1, round(height / element_size))],
                recombine=False)
    occ.synchronize()


def solid_tetrahedra(shape, element_size, diameter, height=None,
                     symmetry_planes=False):
    """Nodes (n, 3) and positively oriented tetrahedra (m, 4) of one solid.

    Parameters
    ----------
    shape : str
        ``"sphere"``, ``"cylinder"`` or ``"ellipsoid"``.
    element_size : float
        gmsh's element size (absolute, m).
    diameter, height : float
        The solid's diameter (an ellipsoid's: of the sphere of equal
        volume), and a cylinder's height or an ellipsoid's aspect ratio
        (its axis along x over the two others, >= 1).
    symmetry_planes : bool
        Conform the mesh to the planes x = 0 and y = 0 (cylinders).
    """
    if shape not in SHAPES:
        raise ValueError(f"shape {shape!r}: allowed {', '.join(SHAPES)}")
    if not (diameter > 0 and element_size > 0):
        raise ValueError("diameter and element_size must be positive")
    if shape == "cylinder" and not (height and height > 0):
        raise ValueError("a cylinder needs a positive height")
    if shape == "ellipsoid" and not (height and height >= 1):
        raise ValueError("an ellipsoid needs an aspect ratio >= 1")
    import gmsh

    initialize_gmsh(gmsh)
    try:
        gmsh.model.add(shape)
        _solid(gmsh, shape, diameter, height, element_size,
               symmetry_planes)
        for name, value in (("Mesh.MeshSizeMin", element_size),
                            ("Mesh.MeshSizeMax", element_size),
                            ("Mesh.MeshSizeFromCurvature", 0),
                            # MeshAdapt surfaces: Frontal-Delaunay (gmsh
                            # 4.8's default) left a 10 mm edge on a 20 mm
                            # sphere meshed at 4 mm
                            ("Mesh.Algorithm", 1),
                            ("Mesh.ElementOrder", 1)):
            gmsh.option.setNumber(name, value)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        types, _, nodes = gmsh.model.mesh.getElements(3)
    finally:
        gmsh.finalize()
    if list(types) != [4]:  # gmsh type 4: 4-node tetrahedron
        raise MeshingError(f"element types {list(types)}, expected only"
                           " 4-node tetrahedra")
    return _compact(tags, coords.reshape(-1, 3), nodes[0])


def _compact(tags, points, element_nodes):
    """The nodes the tetrahedra use, numbered from 0; positive orientation."""
    tags = np.asarray(tags, dtype=np.int64)
    local = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    local[tags] = np.arange(len(tags))
    tets = local[np.asarray(element_nodes, dtype=np.int64)].reshape(-1, 4)
    used, tets = np.unique(tets, return_inverse=True)
    points, tets = points[used], tets.reshape(-1, 4)
    volumes = signed_volumes(points, tets)
    if np.any(np.abs(volumes) <= DEGENERATE * np.abs(volumes).max()):
        raise MeshingError("degenerate tetrahedra (zero volume)")
    flip = volumes < 0
    tets[flip] = tets[flip][:, [0, 1, 3, 2]]
    return points, tets


def checked_tetrahedra(points, tets):
    """A user's tetrahedra, refused when some are degenerate (|volume| <=
    ``DEGENERATE`` of the largest) or inverted (oriented against the
    others: a tangled mesh); a mesh oriented negatively throughout (a
    writer's convention) is turned over.

    Raises
    ------
    MeshingError
        Saying how many tetrahedra are degenerate or inverted, and the
        first one's index.
    """
    points = np.asarray(points, dtype=float)
    tets = np.array(tets, dtype=np.int64).reshape(-1, 4)
    if not len(tets):
        raise MeshingError("no tetrahedra (a 3D solid needs 4-node"
                           " tetrahedra)")
    volumes = signed_volumes(points, tets)
    flat = np.flatnonzero(np.abs(volumes) <= DEGENERATE
                          * np.abs(volumes).max())
    if len(flat):
        raise MeshingError(f"{len(flat)} of {len(tets)} tetrahedra are"
                           f" degenerate (zero volume; the first: tetrahedron"
                           f" {flat[0]})")
    sign = 1.0 if np.sum(volumes > 0) >= np.sum(volumes < 0) else -1.0
    inverted = np.flatnonzero(sign * volumes < 0)
    if len(inverted):
        raise MeshingError(f"{len(inverted)} of {len(tets)} tetrahedra are"
                           f" inverted (oriented against the others: a"
                           f" tangled mesh; the first: tetrahedron"
                           f" {inverted[0]})")
    if sign < 0:
        tets = tets[:, [0, 1, 3, 2]]
    return points, tets


def read_solid(path):
    """The nodes and tetrahedra of a user's gmsh mesh of one solid (meshio
    reads it; only its 4-node tetrahedra are kept, the nodes they use
    numbered from 0), checked by :func:`checked_tetrahedra`.

    Raises
    ------
    MeshingError
        Unreadable, no tetrahedra, degenerate or inverted ones.
    """
    import meshio

    try:
        mesh = meshio.read(str(path))
    except Exception as err:  # meshio raises many kinds on a bad file
        raise MeshingError(f"cannot read it: {err}") from None
    blocks = [c.data for c in mesh.cells if c.type == "tetra"]
    if not blocks:
        raise MeshingError("no tetrahedra (a 3D solid needs 4-node"
                           " tetrahedra)")
    tets = np.vstack(blocks).astype(np.int64)
    used, tets = np.unique(tets, return_inverse=True)
    points = np.asarray(mesh.points, dtype=float)[used]
    if points.shape[1] != 3:
        raise MeshingError("its nodes have 2 coordinates, not 3")
    return checked_tetrahedra(points, tets.reshape(-1, 4))


def write_solids(xdmf, points, tets, body=None) -> None:
    """Write tetrahedra and their body ids (default: one body) as the
    driver reads them (``softpack.scene.mesh``'s layout)."""
    from softpack.scene.mesh import write_xdmf

    body = np.zeros(len(tets), dtype=np.int32) if body is None else body
    write_xdmf(Path(xdmf), points, tets, body)


def main(argv=None) -> int:
    """Mesh one solid into an XDMF file (exit 1 naming what is wrong)."""
    parser = argparse.ArgumentParser(prog="softpack.scene.solids",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("shape", choices=SHAPES)
    parser.add_argument("--diameter", type=float, required=True)
    parser.add_argument("--height", type=float,
                        help="a cylinder's height; an ellipsoid's aspect"
                        " ratio")
    parser.add_argument("--element-size", type=float, required=True)
    parser.add_argument("--symmetry-planes", action="store_true")
    parser.add_argument("--out", type=Path, required=True,
                        help="the XDMF file (its .h5 beside it)")
    args = parser.parse_args(argv)
    try:
        points, tets = solid_tetrahedra(args.shape, args.element_size,
                                        args.diameter, args.height,
                                        args.symmetry_planes)
    except (ValueError, MeshingError) as err:
        print(f"softpack.scene.solids: {err}", file=sys.stderr)
        return 1
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_solids(args.out, points, tets)
    print(f"{args.out}: {len(points)} nodes, {len(tets)} tetrahedra,"
          f" volume {signed_volumes(points, tets).sum():.9g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
