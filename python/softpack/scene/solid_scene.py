"""3D scenes: tetrahedral solids placed in a box of three edges (issue 40).

The 3D counterpart of :func:`softpack.scene.build.build_scene`, for
``[model] dimension = 3``. Each distinct (shape, size) is meshed once by
:mod:`softpack.scene.solids` (sphere, cylinder, ellipsoid) or read from a
user's gmsh file (msh: its tetrahedra, scaled to the species' size and
centred on their volume centroid), then copied to every particle:

- cylinders stand on the base z = 0 (their bottom faces on it, axes along
  z, height ``[model] thickness``, the experiment's geometry): their end
  disks are placed in the box's plan (length x width) by the 2D placement
  with radius D/2, exactly as the disks of the same species, box and seed
  are in 2D (:func:`softpack.scene.packing.scene_packing`): the 2D and 3D
  runs start from the same packing;
- every other solid is placed through its bounding sphere in the box
  (length x width x height, :func:`softpack.scene.placement.place` with
  three edges).

The bodies are rotated about z by the species' orientation rule (never a
sphere or a cylinder) and written as one mesh of tetrahedra in the 2D
mesh's layout (``STEM.xdmf`` + ``.h5``, cell tags "bodies",
``STEM.bodies.csv`` with the columns :data:`BODIES_COLUMNS`), which the
driver reads into a BodySet of dimension 3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from softpack.scene import mesh as mesh_files
from softpack.scene import solids
from softpack.scene.packing import PackingError, scene_packing
from softpack.scene.ball_fraction import ball_fraction
from softpack.scene.placement import _padded, place
from softpack.scene.shapes import ShapeError, user_file
from softpack.scene.species import orientations, particle_table
from softpack.scene.triangulation import MeshingError

#: The columns of a 3D scene's ``STEM.bodies.csv``.
BODIES_COLUMNS = "body,x,y,z,radius,reference_volume,angle"
#: Placement fails beyond random close packing; refuse bounding spheres
#: filling more than this of the box (Torquato's RCP of spheres, 0.64).
SPHERE_FILL_LIMIT = 0.64
#: Fewest tetrahedra of one body's mesh.
MIN_TETRAHEDRA = 4


@dataclass(frozen=True)
class SolidTemplate:
    """One solid centred on its volume centroid (a cylinder: its axis on
    z, its end faces at z = -H/2 and H/2)."""

    points: np.ndarray
    tets: np.ndarray
    volume: float
    bounding_radius: float


@dataclass(frozen=True)
class SolidPacking:
    """Where the bodies are: centres (n, 3) in the box ``extent`` (its
    three edges, m) and each body's meshed volume (m^3). The bottom faces'
    area fraction is an observable
    (:func:`softpack.analysis.solids.scene_fractions`)."""

    centres: np.ndarray
    extent: tuple
    volumes: np.ndarray
    seed: int

    @property
    def n_particles(self) -> int:
        return len(self.centres)

    @property
    def packing_fraction(self) -> float:
        """The volume fraction of the box."""
        return float(self.volumes.sum() / np.prod(self.extent))


def solid_key(spec, diameter) -> tuple:
    """What makes two particles' meshes the same."""
    extra = {"ellipsoid": ("aspect_ratio",), "msh": ("file",)}
    return (spec["shape"], *(spec[k] for k in extra.get(spec["shape"], ())),
            float(diameter))


def solid_template(spec, s, diameter, config, base=None) -> SolidTemplate:
    """One species' solid at one size (:class:`SolidTemplate`).

    Raises
    ------
    ShapeError
        Naming ``[species.s]`` (and its file) and why.
    """
    where = f"[species.{s}] (species {spec['name']!r}, D = {diameter:g} m)"
    h, shape = config["mesh"]["element_size"], spec["shape"]
    try:
        if shape == "msh":
            path = user_file(spec, where, base)
            where = f"{where} file = {str(path)!r}"
            points, tets = solids.read_solid(path)
            scale = (math.pi * diameter**3 / 6
                     / solids.signed_volumes(points, tets).sum())
            points = points * scale ** (1 / 3)
        else:
            extra = {"cylinder": config["model"]["thickness"],
                     "ellipsoid": spec["aspect_ratio"]}.get(shape)
            points, tets = solids.solid_tetrahedra(shape, h, diameter, extra)
    except MeshingError as err:
        raise ShapeError(f"{where}: {err}") from None
    if len(tets) < MIN_TETRAHEDRA:
        raise ShapeError(f"{where}: {len(tets)} tetrahedra, fewer than"
                         f" {MIN_TETRAHEDRA}; a smaller [mesh] element_size")
    volumes = solids.signed_volumes(points, tets)
    centroid = (volumes[:, None] * points[tets].mean(axis=1)).sum(0) \
        / volumes.sum()
    if shape == "cylinder":  # its axis on z (gmsh's), end faces at -+H/2:
        # its nodes on the circle of the placement's radius D/2
        centroid = np.array([0.0, 0.0, 0.5 * (points[:, 2].min()
                                              + points[:, 2].max())])
    points = points - centroid
    return SolidTemplate(points=points, tets=tets, volume=volumes.sum(),
                         bounding_radius=float(np.linalg.norm(
                             points, axis=1).max()))


def solid_templates(config, diameters, index, base=None,
                    known=None) -> dict:
    """Every distinct (shape, size) of a 3D scene, meshed once."""
    species = config["species"]
    made = dict(known or {})
    for d, s in zip(np.asarray(diameters, float).tolist(),
                    np.asarray(index).tolist()):
        key = solid_key(species[s], d)
        if key not in made:
            made[key] = solid_template(species[s], s, d, config, base)
    return made


def place_solids(config, bodies, diameters, index) -> np.ndarray:
    """The bodies' centres (n, 3) in the box (see the module doc).

    Raises
    ------
    PackingError
        A body larger than the box, a box too full, or a failed placement;
        naming the keys.
    """
    box, gap = config["box"], config["packing"]["gap"]
    extent = (box["length"], box["width"], box["height"])
    species = config["species"]
    if all(species[s]["shape"] == "cylinder" for s in set(index.tolist())):
        height = config["model"]["thickness"]
        plan = scene_packing(config, np.asarray(diameters) / 2)
        return np.column_stack([plan.centres,
                                np.full(len(diameters), height / 2)])
    radii = np.array([b.bounding_radius for b in bodies])
    keys = ("([[species]] count, diameter and shape, [box] length, width and"
            " height, [packing] gap)")
    if radii.max() + _padded(gap) >= min(extent) / 2:
        k = int(index[np.argmax(radii)])
        raise PackingError(
            f"[species.{k}] (species {species[k]['name']!r}): a body of"
            f" bounding diameter {2 * radii.max():g} m does not fit in the"
            f" {' x '.join(f'{e:g}' for e in extent)} m box {keys}")
    phi = ball_fraction(radii, extent)
    if phi >= SPHERE_FILL_LIMIT:
        raise PackingError(
            f"the bodies' bounding spheres would fill {phi:.3f} of the box,"
            f" more than random close packing ({SPHERE_FILL_LIMIT}) {keys}")
    try:
        return place(radii, extent, gap,
                     np.random.default_rng(config["packing"]["seed"]))
    except PackingError as err:
        raise PackingError(f"{err} {keys}") from None


def rotated_about_z(points, angle) -> np.ndarray:
    """Points rotated counter-clockwise about the z axis."""
    c, s = math.cos(angle), math.sin(angle)
    out = np.array(points, dtype=float)
    out[:, 0] = c * points[:, 0] - s * points[:, 1]
    out[:, 1] = s * points[:, 0] + c * points[:, 1]
    return out


def write_solids(bodies, centres, angles, out_stem) -> mesh_files.MeshInfo:
    """Copy each template to its place and write the one mesh."""
    xdmf, h5, bodies_csv = mesh_files.output_paths(out_stem)
    points, cells, tags = mesh_files.placed_copies(
        bodies, centres, angles, [t.tets for t in bodies], rotated_about_z)
    if np.any(solids.signed_volumes(points, cells) <= 0):
        raise RuntimeError("mesh has non-positively oriented tetrahedra")
    rows = [f"{i},{c[0]!r},{c[1]!r},{c[2]!r},{t.bounding_radius!r},"
            f"{t.volume!r},{a!r}"
            for i, (t, c, a) in enumerate(zip(bodies, centres, angles))]
    mesh_files._write_outputs(xdmf, (points, cells, tags),
                              bodies_csv, rows, BODIES_COLUMNS)
    return mesh_files.MeshInfo(
        xdmf=xdmf, h5=h5, bodies_csv=bodies_csv,
        triangles_per_body=tuple(len(t.tets) for t in bodies),
        nodes_per_body=tuple(len(t.points) for t in bodies),
        reference_areas=tuple(float(t.volume) for t in bodies))


def build_solids(config, mesh_stem, known=None, base=None):
    """Mesh, place and write a 3D configuration's bodies.

    Returns
    -------
    packing : SolidPacking
    mesh : softpack.scene.mesh.MeshInfo
        Its ``triangles_per_body`` are tetrahedra, its ``reference_areas``
        volumes.
    index : ndarray of int
        Each body's species.

    Raises
    ------
    PackingError
        The bodies cannot be placed, or (:class:`ShapeError`) a solid
        cannot be meshed or read; nothing is written then.
    """
    species, seed = config["species"], config["packing"]["seed"]
    diameters, index = particle_table(species, seed)
    made = solid_templates(config, diameters, index, base, known)
    bodies = [made[solid_key(species[s], d)]
              for d, s in zip(diameters, index)]
    centres = place_solids(config, bodies, diameters, index)
    info = write_solids(bodies, centres,
                        orientations(species, index, seed), mesh_stem)
    box = config["box"]
    packing = SolidPacking(
        centres=centres, extent=(box["length"], box["width"], box["height"]),
        volumes=np.array(info.reference_areas), seed=seed)
    return packing, info, index
