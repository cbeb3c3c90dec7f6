"""Meshes of particles with gmsh, written as one dolfinx mesh for the driver.

Every disk is meshed with linear (3-node) triangles of one absolute element
size h (the paper: h = 1.065 mm for both D1 = 20 mm and D2 = 30 mm, about 670
and 1506 triangles).  All disks form one dolfinx mesh of disconnected
components; a cell tag gives each triangle's body id.

Output of :func:`mesh_disks` for a stem ``NAME`` (SI units, metres):

``NAME.xdmf`` + ``NAME.h5``
    in the layout of ``dolfinx.io.XDMFFile`` (which reads them): the mesh
    named ``"mesh"`` and the cell meshtags named ``"bodies"`` whose value is the body id
    ``0..n-1`` in the order the disks were given.
``NAME.bodies.csv``
    header ``body,x,y,radius,reference_area,angle``, one row per body; the
    radius is the bounding radius (a disk's radius), the reference area
    the area of the meshed polygon (m^2), the angle the body's rotation
    (rad; see :func:`mesh_particles`, which meshes any shape of
    :mod:`softpack.scene.shapes`).

The files are written in a temporary directory next to them and renamed into
place, ``NAME.bodies.csv`` last (a stale one is removed first), so a present
``NAME.bodies.csv`` means the three files are complete.

Disks of equal radius share one gmsh mesh translated to each centre, so the
boundary nodes lie on each circle up to rounding.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.contract.schema import load_schema
from softpack.contract.tables import read_table
from softpack.scene.packing import (DEFAULT_GAP, PAPER_COUNTS,
                                    PAPER_DIAMETERS, PAPER_LENGTH,
                                    PAPER_WIDTH, Packing, PackingError,
                                    random_packing)
from softpack.scene.shapes import (MIN_BOUNDARY_ELEMENTS, Template, rotated,
                                   shape_file)
from softpack.scene.triangulation import (initialize_gmsh, mesh_geometry,
                                          signed_areas)

#: The paper's element size (m): kappa = h / (D2 / 2) = 0.071 (the
#: schema's default).
PAPER_ELEMENT_SIZE = load_schema()["mesh"].parameters["element_size"].default
BODIES_COLUMNS = "body,x,y,radius,reference_area,angle"


@dataclass(frozen=True)
class MeshInfo:
    """What :func:`mesh_disks` wrote.

    Attributes
    ----------
    xdmf, h5, bodies_csv : Path
        The three output files.
    triangles_per_body, nodes_per_body : tuple of int
        Mesh size of each body, in body-id order.
    reference_areas : tuple of float
        Area of each body's meshed polygon (m^2).
    """

    xdmf: Path
    h5: Path
    bodies_csv: Path
    triangles_per_body: tuple
    nodes_per_body: tuple
    reference_areas: tuple

    @property
    def n_triangles(self) -> int:
        """Total number of triangles."""
        return int(sum(self.triangles_per_body))


def output_paths(out_stem) -> tuple[Path, Path, Path]:
    """The ``(xdmf, h5, bodies_csv)`` paths of a stem.

    A trailing ``.xdmf`` on the stem is dropped.
    """
    stem = Path(out_stem)
    if stem.suffix == ".xdmf":
        stem = stem.with_suffix("")
    return (stem.with_name(stem.name + ".xdmf"),
            stem.with_name(stem.name + ".h5"),
            stem.with_name(stem.name + ".bodies.csv"))


def check_disks(centres, radii, element_size) -> tuple[np.ndarray, np.ndarray]:
    """Validate disk data; return centres ``(n, 2)`` and radii ``(n,)``.

    Raises
    ------
    ValueError
        On shapes that do not match, non-finite or non-positive values, or an
        element size giving fewer than ``MIN_BOUNDARY_ELEMENTS`` elements
        around the smallest disk.
    """
    centres = np.asarray(centres, dtype=float)
    radii = np.atleast_1d(np.asarray(radii, dtype=float))
    if centres.ndim == 1 and centres.size == 2:
        centres = centres.reshape(1, 2)
    if centres.ndim != 2 or centres.shape[1] != 2:
        raise ValueError(f"centres must have shape (n, 2), got {centres.shape}")
    if radii.ndim != 1 or len(radii) != len(centres) or not len(radii):
        raise ValueError(f"need one radius per centre: {len(centres)} centres,"
                         f" radii of shape {radii.shape}")
    if not (np.all(np.isfinite(centres)) and np.all(np.isfinite(radii))):
        raise ValueError("centres and radii must be finite")
    if np.any(radii <= 0):
        raise ValueError(f"radii must be positive, got min {radii.min()}")
    h = float(element_size)
    if not np.isfinite(h) or h <= 0:
        raise ValueError(f"element size must be positive, got {element_size}")
    if 2 * np.pi * radii.min() / h < MIN_BOUNDARY_ELEMENTS:
        raise ValueError(
            f"element size {h} m is too large for a disk of radius"
            f" {radii.min()} m (fewer than {MIN_BOUNDARY_ELEMENTS} elements"
            " around it)")
    return centres, radii


def disk_triangulation(radii, element_size, shape="disk") -> dict:
    """Mesh particles centred at the origin, one per distinct radius.

    Parameters
    ----------
    radii : iterable of float
        Radii (m); each distinct value is meshed once.
    element_size : float
        Target edge length h (m), the same everywhere.
    shape : str
        The geometry ``meshes/SHAPE.geo`` (:func:`shape_file`), opened with
        its ONELAB parameter ``Parameters/radius`` set to each radius.

    Returns
    -------
    dict
        ``radius -> (points, triangles)``: node coordinates ``(m, 2)`` and
        counter-clockwise 3-node triangles ``(k, 3)`` indexing them.

    Notes
    -----
    Owns the gmsh session: initialises gmsh and finalises it on return.
    """
    import gmsh

    geometry = shape_file(shape)
    initialize_gmsh(gmsh)
    try:
        return {float(r): mesh_geometry(gmsh, geometry, {"radius": float(r)},
                                        float(element_size))
                for r in sorted(set(np.asarray(radii, dtype=float).tolist()))}
    finally:
        gmsh.finalize()


def mesh_disks(centres, radii, element_size, out_stem) -> MeshInfo:
    """Mesh disks and write them as one dolfinx mesh with body tags.

    Parameters
    ----------
    centres : array_like, shape (n, 2)
        Disk centres (m); body ``i`` is the disk ``centres[i], radii[i]``.
    radii : array_like, shape (n,)
        Disk radii (m).
    element_size : float
        One absolute element size h for all disks (m).
    out_stem : str or Path
        Output stem ``NAME``: writes ``NAME.xdmf``, ``NAME.h5`` and
        ``NAME.bodies.csv`` (parent directories are created).

    Returns
    -------
    MeshInfo
    """
    centres, radii = check_disks(centres, radii, element_size)
    meshes = disk_triangulation(radii, element_size)
    templates = {r: Template(points=p, triangles=t,
                             area=float(signed_areas(p, t).sum()),
                             bounding_radius=r)
                 for r, (p, t) in meshes.items()}
    return mesh_particles([templates[float(r)] for r in radii], centres,
                          np.zeros(len(radii)), out_stem)


def mesh_particles(bodies, centres, angles, out_stem) -> MeshInfo:
    """Copy each body's template to its place; write the one mesh.

    Parameters
    ----------
    bodies : list of softpack.scene.shapes.Template
        Body ``i``'s shape and size, centred at the origin (the same object
        for bodies that share a mesh).
    centres : array_like, shape (n, 2)
        Where each template's origin goes (m).
    angles : array_like, shape (n,)
        Counter-clockwise rotation of each body about its centre (rad).
    out_stem : str or Path
        As :func:`mesh_disks`; ``NAME.bodies.csv``'s ``radius`` is each
        body's bounding radius and ``angle`` its rotation.

    Returns
    -------
    MeshInfo
    """
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    angles = np.asarray(angles, dtype=float).reshape(-1)
    xdmf, h5, bodies_csv = output_paths(out_stem)
    points, cells, body = placed_copies(bodies, centres, angles,
                                        [t.triangles for t in bodies],
                                        rotated)
    _check_cells(points, cells)
    rows = [f"{i},{c[0]!r},{c[1]!r},{t.bounding_radius!r},{t.area!r},{a!r}"
            for i, (t, c, a) in enumerate(zip(bodies, centres, angles))]
    _write_outputs(xdmf, (points, cells, body), bodies_csv, rows)
    return MeshInfo(
        xdmf=xdmf, h5=h5, bodies_csv=bodies_csv,
        triangles_per_body=tuple(len(t.triangles) for t in bodies),
        nodes_per_body=tuple(len(t.points) for t in bodies),
        reference_areas=tuple(float(t.area) for t in bodies))


def placed_copies(templates, centres, angles, template_cells, rotate):
    """Each template's points rotated by its angle (``rotate(points,
    angle)``) and moved to its centre, its cells renumbered into the one
    mesh: (points, cells, the body of each cell)."""
    points, cells, body = [], [], []
    offset = 0
    for i, (t, own, c, a) in enumerate(zip(templates, template_cells,
                                            centres, angles)):
        points.append((rotate(t.points, a) if a else t.points) + c)
        cells.append(own + offset)
        body.append(np.full(len(own), i, dtype=np.int32))
        offset += len(t.points)
    return np.vstack(points), np.vstack(cells), np.concatenate(body)


def _check_cells(points, cells) -> None:
    """Every triangle counter-clockwise (the templates are; a rotation
    keeps them so)."""
    if np.any(signed_areas(points, cells) <= 0):
        raise RuntimeError("mesh has non-positively oriented cells")


#: The XDMF of the mesh and its "bodies" cell tags, as dolfinx writes them
#: (dolfinx.io.XDMFFile.write_mesh + write_meshtags) and reads them back.
XDMF_TEMPLATE = """<?xml version="1.0"?>
<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>
<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">
  <Domain>
    <Grid Name="mesh" GridType="Uniform">
      <Topology TopologyType="{topology}" NumberOfElements="{cells}" \
NodesPerElement="{per_cell}">
        <DataItem Dimensions="{cells} {per_cell}" NumberType="Int" \
Format="HDF">{h5}:/Mesh/mesh/topology</DataItem>
      </Topology>
      <Geometry GeometryType="{geometry}">
        <DataItem Dimensions="{nodes} {dim}" Format="HDF">\
{h5}:/Mesh/mesh/geometry</DataItem>
      </Geometry>
    </Grid>
    <Grid Name="bodies" GridType="Uniform">
      <xi:include xpointer="xpointer(/Xdmf/Domain/Grid/Geometry)" />
      <Topology TopologyType="{topology}" NumberOfElements="{cells}" \
NodesPerElement="{per_cell}">
        <DataItem Dimensions="{cells} {per_cell}" NumberType="Int" \
Format="HDF">{h5}:/MeshTags/bodies/topology</DataItem>
      </Topology>
      <Attribute Name="bodies" AttributeType="Scalar" Center="Cell">
        <DataItem Dimensions="{cells} 1" Format="HDF">\
{h5}:/MeshTags/bodies/Values</DataItem>
      </Attribute>
    </Grid>
  </Domain>
</Xdmf>
"""


def write_xdmf(xdmf, points, cells, body) -> None:
    """The mesh (triangles in 2D, tetrahedra in 3D: the points' number of
    coordinates) and its cell tags in dolfinx's XDMF layout, written with
    h5py: dolfinx's own writer first builds a distributed mesh, whose cell
    reordering takes most of the time for a thousand particles (12 s of
    16 s); the driver's reader (and tests/python/test_mesh.py) reads this
    file as it reads dolfinx's."""
    import h5py

    h5 = xdmf.with_suffix(".h5")
    with h5py.File(h5, "w") as f:
        f["Mesh/mesh/geometry"] = np.asarray(points, dtype=np.float64)
        f["Mesh/mesh/topology"] = np.asarray(cells, dtype=np.int64)
        f["MeshTags/bodies/topology"] = np.asarray(cells, dtype=np.int64)
        f["MeshTags/bodies/Values"] = np.asarray(
            body, dtype=np.int32).reshape(-1, 1)
    dim = np.shape(points)[1]
    xdmf.write_text(XDMF_TEMPLATE.format(
        cells=len(cells), nodes=len(points), h5=h5.name, dim=dim,
        per_cell=dim + 1, topology="Triangle" if dim == 2 else "Tetrahedron",
        geometry="XY" if dim == 2 else "XYZ"))


#: The 2D meshes' writer (tests replace it)
_write_xdmf = write_xdmf


def _write_outputs(xdmf, mesh, bodies_csv, rows,
                   columns=BODIES_COLUMNS) -> None:
    """Write mesh (``(points, cells, body)``), tags and body table (its
    header ``columns``) into place atomically (see module)."""
    xdmf.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{xdmf.stem}.tmp-", dir=xdmf.parent))
    try:
        _write_xdmf(tmp / xdmf.name, *mesh)
        (tmp / bodies_csv.name).write_text(
            "\n".join([columns, *rows]) + "\n")
        bodies_csv.unlink(missing_ok=True)
        h5_name = xdmf.with_suffix(".h5").name
        os.replace(tmp / h5_name, xdmf.with_name(h5_name))
        os.replace(tmp / xdmf.name, xdmf)
        os.replace(tmp / bodies_csv.name, bodies_csv)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def read_bodies(path) -> dict:
    """Read ``NAME.bodies.csv``: a dict of arrays keyed by column name."""
    table = read_table(path)
    table["body"] = table["body"].astype(int)
    return table


def _positive(text) -> float:
    """argparse type: a positive finite float."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}")
    if not np.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {text!r}")
    return value


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack mesh``."""
    parser = argparse.ArgumentParser(
        prog="softpack mesh",
        description="Mesh disks with gmsh (linear triangles, one element "
        "size) into NAME.xdmf/.h5 with 'bodies' cell tags and "
        "NAME.bodies.csv. All lengths in metres.")
    sub = parser.add_subparsers(dest="what", required=True)
    disk = sub.add_parser("disk", help="one disk")
    disk.add_argument("--diameter", type=_positive, required=True,
                      help="disk diameter D (m), e.g. 0.02")
    disk.add_argument("--centre", type=float, nargs=2, default=(0.0, 0.0),
                      metavar=("X", "Y"), help="centre (m), default 0 0")
    packing = sub.add_parser(
        "packing", help="a random packing (the paper's by default); also "
        "writes NAME.packing.csv")
    source = packing.add_mutually_exclusive_group(required=True)
    source.add_argument("--seed", type=int, help="seed of a new packing")
    source.add_argument("--packing", type=Path, metavar="CSV",
                        help="mesh an existing NAME.packing.csv instead")
    packing.add_argument("--counts", type=int, nargs="+",
                         default=list(PAPER_COUNTS),
                         help="disks per species (default 70 30)")
    packing.add_argument("--diameters", type=_positive, nargs="+",
                         default=list(PAPER_DIAMETERS),
                         help="diameter per species (m, default 0.02 0.03)")
    packing.add_argument("--length", type=_positive, default=PAPER_LENGTH,
                         help="box length L along x (m, default 0.286)")
    packing.add_argument("--width", type=_positive, default=PAPER_WIDTH,
                         help="box width W along y (m, default 0.202)")
    packing.add_argument("--gap", type=float, default=DEFAULT_GAP,
                         help="minimum clearance (m, default 1e-4)")
    for p in (disk, packing):
        p.add_argument("--element-size", type=_positive,
                       default=PAPER_ELEMENT_SIZE,
                       help="element size h (m, default 1.065e-3)")
        p.add_argument("--out", type=Path, required=True, metavar="STEM",
                       help="output stem: writes STEM.xdmf, STEM.h5, "
                       "STEM.bodies.csv")
    return parser


def main(argv=None) -> int:
    """``./softpack mesh disk|packing ...``; returns the exit status."""
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        if args.what == "disk":
            packing = None
            centres, radii = [args.centre], [args.diameter / 2]
        elif args.packing is not None:
            packing = Packing.from_csv(args.packing)
        else:
            if len(args.counts) != len(args.diameters):
                parser.error("--counts and --diameters need the same number"
                             " of values")
            packing = random_packing(
                args.seed, counts=args.counts, diameters=args.diameters,
                length=args.length, width=args.width, gap=args.gap)
        if packing is not None:
            centres, radii = packing.centres, packing.radii
        check_disks(centres, radii, args.element_size)
    except (ValueError, OSError) as err:
        parser.error(str(err))
    except PackingError as err:
        print(f"softpack mesh: {err}", file=sys.stderr)
        return 1
    info = mesh_disks(centres, radii, args.element_size, args.out)
    if packing is not None:
        stem = info.xdmf.with_suffix("")
        packing.to_csv(stem.with_name(stem.name + ".packing.csv"))
    print(f"{info.xdmf}: {len(radii)} bodies, {info.n_triangles} triangles"
          f" (h = {args.element_size:g} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
