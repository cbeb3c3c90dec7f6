"""The scene of a configuration: walls, particles, packing and mesh.

:func:`build_scene` turns a validated :class:`~softpack.scene.config.Config`
into a :class:`Scene`: the packing of its species (body order: species by
species, in the file's order), the mesh of every body (one dolfinx mesh,
cells tagged by body), each body's species index, and the walls in
driver.json order. :meth:`Scene.record` is the ``scene`` object of
driver.json (docs/contract.md section 4).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.scene import shapes
from softpack.scene.mesh import MeshInfo, mesh_particles
from softpack.scene.packing import Packing, scene_packing
from softpack.contract.schema import load_schema
from softpack.scene.species import orientations, particle_table
from softpack.scene.walls import scene_walls


@dataclass(frozen=True)
class Scene:
    """What the scene stage built (SI units).

    Attributes
    ----------
    config : Config
        The configuration it was built from.
    packing : Packing or SolidPacking
        Particle centres and radii in body order (3D: centres and volumes,
        :class:`softpack.scene.solid_scene.SolidPacking`).
    mesh : MeshInfo
        The mesh files and sizes per body.
    species : ndarray of int
        Each body's species index (position in ``config["species"]``).
    walls : list of Wall
        In driver.json order.
    """

    config: dict
    packing: Packing
    mesh: MeshInfo
    species: np.ndarray
    walls: list

    def record(self) -> dict:
        """driver.json's ``scene`` (:func:`scene_record`)."""
        return scene_record(self.config, self.mesh.xdmf)


def scene_record(config, mesh_xdmf) -> dict:
    """driver.json's ``scene``: the scene-stage sections and the bodies
    (the mesh, each body's species index in body order).

    Parameters
    ----------
    config : Config
    mesh_xdmf : path-like
        The bodies' mesh written for this configuration's scene.
    """
    out = {}
    for name, section in load_schema().items():
        if section.stage == "scene":
            out[name] = _plain(config[name])
    _, species = particle_table(config["species"],
                                config["packing"]["seed"])
    out["bodies"] = {"mesh": str(Path(mesh_xdmf).resolve()),
                     "species": [int(s) for s in species]}
    return out


def _plain(value):
    """A copy of a config value with plain lists and dicts (for JSON)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _base(config):
    """The directory of the run's TOML file (relative ``file`` keys)."""
    source = Path(getattr(config, "source", ""))
    return source.parent if source.is_file() else None


def check_user_shapes(config) -> dict:
    """Mesh once the shapes a user's file draws (species of shape geo or
    msh, at their particles' sizes), so that a missing, unreadable or
    unmeshable file is refused before a run writes anything; the templates
    (for :func:`build_scene`'s ``known``: each is meshed once).

    Raises
    ------
    softpack.scene.shapes.ShapeError
        Naming the species, the file and why.
    """
    species = config["species"]
    user = [k for k, s in enumerate(species) if s["shape"] in ("geo", "msh")]
    if not user:
        return {}
    diameters, index = particle_table(species, config["packing"]["seed"])
    keep = np.isin(index, user)
    if config["model"]["dimension"] == 3:
        from softpack.scene.solid_scene import solid_templates

        return solid_templates(config, diameters[keep], index[keep],
                               _base(config))
    return shapes.templates(species, diameters[keep], index[keep],
                            config["mesh"]["element_size"], _base(config))


def build_scene(config, mesh_stem, known=None) -> Scene:
    """Draw, mesh, place and write a configuration's particles (3D:
    :func:`softpack.scene.solid_scene.build_solids`).

    Each distinct (shape, size) is meshed once (:mod:`.shapes`); the
    packing places the particles' bounding circles (:mod:`.packing`); the
    templates are rotated and copied to their places (:mod:`.mesh`).

    Parameters
    ----------
    config : Config
        A validated configuration.
    mesh_stem : str or Path
        Writes ``STEM.xdmf``, ``STEM.h5``, ``STEM.bodies.csv`` and, with a
        box, ``STEM.packing.csv``.
    known : dict, optional
        Shape templates meshed already (:func:`check_user_shapes`).

    Raises
    ------
    softpack.scene.packing.PackingError
        When the particles cannot be placed, or (its subclass
        :class:`~softpack.scene.shapes.ShapeError`) a shape cannot be
        meshed; nothing is written then.
    """
    if config["model"]["dimension"] == 3:
        from softpack.scene.solid_scene import build_solids

        packing, info, index = build_solids(config, mesh_stem, known,
                                            _base(config))
        return Scene(config=config, packing=packing, mesh=info,
                     species=index, walls=scene_walls(config))
    species, seed = config["species"], config["packing"]["seed"]
    diameters, index = particle_table(species, seed)
    if not (config["box"]["enabled"] or config["cell"]["enabled"]):
        diameters, index = diameters[:1], index[:1]
    meshes = shapes.templates(species, diameters, index,
                              config["mesh"]["element_size"], _base(config),
                              known)
    bodies = [meshes[shapes.shape_key(species[s], d)]
              for d, s in zip(diameters, index)]
    radii = np.array([b.bounding_radius for b in bodies])
    disks = all(species[s]["shape"] == "disk" for s in set(index.tolist()))
    packing = scene_packing(config, radii,
                            None if disks else np.pi * diameters**2 / 4)
    info = mesh_particles(bodies, packing.centres,
                          orientations(species, index, seed), mesh_stem)
    if config["box"]["enabled"]:
        stem = info.xdmf.with_suffix("")
        packing.to_csv(stem.with_name(stem.name + ".packing.csv"))
    return Scene(config=config, packing=packing, mesh=info, species=index,
                 walls=scene_walls(config))
