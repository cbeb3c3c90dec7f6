"""What the analysis knows about a run: ``raw/setup.json`` and the rules.

The driver writes ``DIR/raw/setup.json`` before its first step
(``docs/contract.md`` section 5): the scene, the material, the walls at
t = 0, the solver parameters and the bodies. :func:`read_setup` turns it into
a :class:`RunSetup`; the analysis never re-reads ``driver.json``, the mesh
or the user's TOML file. The observables' own rules (which a user may change
after a run and recompute) are the ``[observables]`` section of
``DIR/config.toml``, read by :func:`read_rules` (that section only).
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softpack.contract.run_directory import RunDirectory

SCHEMA_VERSION = 2
#: The walls that make a box, and which coordinate of their point locates it.
BOX_WALLS = ("left", "right", "bottom", "top")
#: The loaded box wall (the paper's piston).
PISTON = "right"


class SetupError(ValueError):
    """``raw/setup.json`` or the ``[observables]`` rules are unusable."""


@dataclass(frozen=True)
class Wall:
    """A rigid wall at t = 0: a point, its inward unit normal, a velocity."""

    name: str
    point: np.ndarray
    normal: np.ndarray
    velocity: np.ndarray


@dataclass(frozen=True)
class RunSetup:
    """The run identity and geometry the later stages need (SI units).

    Attributes
    ----------
    path : Path
        The ``setup.json`` read.
    thickness : float
        The 2D model's depth H (m).
    walls : dict of str -> Wall
        In the driver's order.
    length, width : float
        The initial box L0 (right - left) and W0 (top - bottom); NaN when
        the scene has no box (walls left/right/bottom/top).
    shear_modulus : float
        ``material.parameters.shear_modulus``, NaN when the law has none
        (see ``notes``).
    law : str
    friction : float
    seed : int
    species : list of dict
        ``scene.species`` (name, shape, diameter, count).
    body_species : ndarray of int, shape (n,)
    reference_area : ndarray, shape (n,)
        Each body's reference area (m^2).
    diameters : ndarray, shape (n,)
        Each body's species diameter (m).
    element_size : float
        ``[mesh] element_size`` of the run (m).
    body_rigid : ndarray of bool, shape (n,)
        Whether each body is rigid (its species' material is).
    stage_names : tuple of str
        The names of the loading program's stages (none without stages).
    stage_frictions : tuple of float
        Each stage's friction (``contact.friction``; the run's ``friction``
        for a stage recorded without one).
    stage_phis : tuple of float
        Each stage's ``stop.packing_fraction`` (0: no such criterion).
    body_density : ndarray, shape (n,)
        Each body's mass density (kg/m^3: its species' material's).
    gravity : ndarray, shape (2,) or (3,)
        ``[gravity] acceleration`` as given (m/s^2; zeros without gravity;
        z = 0 when a 3D run gives two components).
    cell : bool
        A periodic cell's run (``parameters.cell.enabled``;
        docs/periodic_cell.md): its edges are columns of ``raw/steps.csv``
        and each contact has its antagonist's image.
    dimension : int
        ``scene.model.dimension``: 2, or 3 for tetrahedral bodies in a box
        of six planes, whose ``walls`` are then the four of ``setup.json``
        with 3D points and normals (z = 0) and the ``base`` (z = 0, normal
        +z) and ``lid`` (z = ``scene.box.height``, normal -z), in the
        driver's order (docs/driver_io.md, "3D runs").
    notes : tuple of str
        What could not be read and why.
    """

    path: Path
    thickness: float
    walls: dict
    length: float
    width: float
    shear_modulus: float
    law: str
    friction: float
    seed: int
    species: list
    body_species: np.ndarray
    reference_area: np.ndarray
    diameters: np.ndarray
    element_size: float = math.nan
    body_rigid: np.ndarray = None
    stage_names: tuple = ()
    stage_frictions: tuple = ()
    stage_phis: tuple = ()
    body_density: np.ndarray = None
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    notes: tuple = field(default=())
    cell: bool = False
    dimension: int = 2

    @property
    def has_box(self) -> bool:
        """Whether the walls left/right/bottom/top exist."""
        return all(name in self.walls for name in BOX_WALLS)

    @property
    def body_weight(self) -> np.ndarray:
        """Each body's weight under [gravity], shape (n, dimension):
        density x reference area (3D: volume) x g (N/m in 2D, N in 3D;
        zeros without gravity)."""
        g = np.zeros(self.dimension)
        g[:len(self.gravity)] = self.gravity
        return np.outer(self.body_density * self.reference_area, g)

    @property
    def radii(self) -> np.ndarray:
        """Each body's species radius (m)."""
        return 0.5 * self.diameters

    @property
    def count(self) -> int:
        """Number of bodies."""
        return len(self.body_species)


@dataclass(frozen=True)
class Rules:
    """The observables' rules (``[observables]`` of ``config.toml``).

    Attributes
    ----------
    force_threshold : float
        ``contact_force_threshold``: a nodal normal force counts above this
        fraction of the output step's largest one.
    unbalanced_threshold : float
        ``unbalanced_threshold``: f_p* as a fraction of the piston force.
    rule : str
        ``two_node_rule``, one of
        :data:`softpack.analysis.connectivity.RULES`.
    unbalanced_reference, excluded_contacts : str
        The readings of the exclusion rule
        (:mod:`softpack.analysis.connectivity`); ``None``: the schema's
        default.
    tensile_contacts : str
        ``tensile_contacts``: whether a tensile normal force bears load
        (:mod:`softpack.analysis.connectivity`); ``None``: the schema's
        default.
    """

    force_threshold: float
    unbalanced_threshold: float
    rule: str
    unbalanced_reference: str = None
    excluded_contacts: str = None
    tensile_contacts: str = None

    def __post_init__(self):
        from softpack.contract.schema import load_schema

        spec = load_schema()["observables"].parameters
        for name in ("unbalanced_reference", "excluded_contacts",
                     "tensile_contacts"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, spec[name].default)


def read_setup(run_dir) -> RunSetup:
    """Read ``DIR/raw/setup.json`` (schema version 2).

    Raises
    ------
    SetupError
        When the file is missing, of another schema version, or lacks a key
        the analysis needs (the message names the file and the key).
    """
    path = RunDirectory(run_dir).raw.setup_json
    try:
        doc = json.loads(path.read_text())
    except FileNotFoundError:
        raise SetupError(f"{path} missing: the driver writes it before its"
                         " first step") from None
    version = doc.get("schema_version")
    if version != SCHEMA_VERSION:
        raise SetupError(f"{path}: schema_version {version!r}, this analysis"
                         f" reads {SCHEMA_VERSION}")
    try:
        return _from_document(path, doc)
    except KeyError as err:
        raise SetupError(f"{path}: missing key {err}") from None


def _from_document(path, doc) -> RunSetup:
    """The RunSetup of a parsed document (KeyError names a missing key)."""
    scene, material = doc["scene"], doc["material"]
    walls = {w["name"]: Wall(w["name"], *(np.asarray(w[k], dtype=float)
                                          for k in ("point", "normal",
                                                    "velocity")))
             for w in doc["walls"]}
    dimension = int(scene["model"].get("dimension", 2))
    if dimension == 3:
        walls = _box_3d(walls, float(scene["box"]["height"]))
    notes = []
    cell = bool(doc["parameters"].get("cell", {}).get("enabled", False))
    if all(name in walls for name in BOX_WALLS):
        length = float(walls["right"].point[0] - walls["left"].point[0])
        width = float(walls["top"].point[1] - walls["bottom"].point[1])
    elif cell:
        length = width = math.nan  # the cell's are in raw/steps.csv
    else:
        length = width = math.nan
        notes.append("no box (walls left/right/bottom/top): L0, W0, the"
                     " piston and the box's Phi are undefined")
    law_parameters = material["parameters"]
    if "shear_modulus" in law_parameters:
        mu = float(law_parameters["shear_modulus"])
    else:
        mu = math.nan
        notes.append(f"material law {material['law']!r} has no"
                     " shear_modulus: E/(W H L mu) and Psi/mu are undefined")
    bodies = doc["bodies"]
    species_of = np.asarray(bodies["species"], dtype=np.int64)
    species = list(scene["species"])
    diameters = np.array([float(species[s]["diameter"]) for s in species_of])
    reference_area = np.asarray(bodies["reference_area"], dtype=float)
    if not len(species_of) == len(reference_area) == int(bodies["count"]):
        raise SetupError(f"{path}: bodies.count {bodies['count']}, "
                         f"{len(species_of)} species, {len(reference_area)}"
                         " reference areas")
    rigid = {m["name"] for m in doc.get("materials", ()) if m.get("rigid")}
    density = {m["name"]: float(m["density"])
               for m in doc.get("materials", ())}
    species_density = np.array([density.get(s.get("material", ""),
                                            float(material["density"]))
                                for s in species] or [0.0])
    gravity = np.asarray(doc["parameters"].get("gravity", {}).get(
        "acceleration", (0.0, 0.0)), dtype=float)
    species_rigid = np.array([s.get("material", "") in rigid
                              for s in species] or [False])
    friction = float(doc["parameters"]["contact"]["friction"])
    stages = doc.get("stages", ())
    return RunSetup(
        path=path, thickness=float(scene["model"]["thickness"]), walls=walls,
        length=length, width=width, shear_modulus=mu, law=material["law"],
        friction=friction,
        seed=int(scene["packing"]["seed"]), species=species,
        body_species=species_of, reference_area=reference_area,
        diameters=diameters,
        element_size=float(scene.get("mesh", {}).get("element_size",
                                                      math.nan)),
        body_rigid=species_rigid[species_of],
        stage_names=tuple(s.get("name", "") for s in stages),
        stage_frictions=tuple(float(s.get("contact", {}).get("friction",
                                                             friction))
                              for s in stages),
        stage_phis=tuple(float(s["stop"].get("packing_fraction", 0.0))
                         for s in stages),
        body_density=species_density[species_of], gravity=gravity,
        notes=tuple(notes), cell=cell, dimension=dimension)


def _box_3d(walls: dict, height: float) -> dict:
    """A 3D box's six planes (``driver/simulation/box_3d.h``): the four
    vertical walls with z = 0 appended to their vectors, then the base and
    the lid, both fixed."""
    def padded(v):
        return np.append(v, 0.0)

    out = {name: Wall(name, padded(w.point), padded(w.normal),
                      padded(w.velocity)) for name, w in walls.items()}
    zero = np.zeros(3)
    out["base"] = Wall("base", zero, np.array([0.0, 0.0, 1.0]), zero)
    out["lid"] = Wall("lid", np.array([0.0, 0.0, height]),
                      np.array([0.0, 0.0, -1.0]), zero)
    return out


def read_rules(run_dir) -> Rules:
    """The ``[observables]`` section of ``DIR/config.toml``.

    ``config.toml`` is the resolved configuration (every key explicit), so
    a missing key is an error, not a default.

    Raises
    ------
    SetupError
    """
    path = RunDirectory(run_dir).config_toml
    try:
        with open(path, "rb") as f:
            section = tomllib.load(f)["observables"]
    except FileNotFoundError:
        raise SetupError(f"{path} missing") from None
    except KeyError:
        raise SetupError(f"{path}: no [observables] section") from None
    except tomllib.TOMLDecodeError as err:
        raise SetupError(f"{path}: {err}") from None
    names = {"contact_force_threshold": "force_threshold",
             "unbalanced_threshold": "unbalanced_threshold",
             "two_node_rule": "rule",
             "unbalanced_reference": "unbalanced_reference",
             "excluded_contacts": "excluded_contacts",
             "tensile_contacts": "tensile_contacts"}
    # runs older than these readings: the schema's default
    optional = {"unbalanced_reference", "excluded_contacts",
                "tensile_contacts"}
    unknown = set(section) - set(names)
    missing = set(names) - set(section) - optional
    if unknown or missing:
        raise SetupError(f"{path} [observables]: unknown keys"
                         f" {sorted(unknown)}, missing keys {sorted(missing)}")
    _check_against_schema(path, section)
    return Rules(**{names[k]: v for k, v in section.items()})


def _check_against_schema(path, section) -> None:
    """Types, ranges and choices of the rules, from schema/parameters.toml."""
    from softpack.contract.schema import load_schema

    for key, spec in load_schema()["observables"].parameters.items():
        if key not in section:
            continue  # an optional reading, checked as the default
        value = section[key]
        if spec.type == "str":
            ok = isinstance(value, str) and value in (spec.choices or (value,))
        else:
            ok = isinstance(value, (int, float)) and not isinstance(
                value, bool) and spec.in_range(value)
        if not ok:
            raise SetupError(f"{path} [observables] {key} = {value!r}:"
                             f" {spec.allowed()}")
