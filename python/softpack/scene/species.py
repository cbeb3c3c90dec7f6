"""Particle species -> the per-particle table of the scene.

``[[species]]`` gives each species a name, a shape (:mod:`.shapes`), a size
distribution (:mod:`.distributions`), an orientation rule and a count.
Particles are numbered species by species in the file's order (the paper's
case: bodies 0-69 are the 20-mm disks, 70-99 the 30-mm ones); that order is
the body order of the packing, the mesh and the driver.

Random draws are seeded by ``[packing] seed`` through separate streams of one
seed sequence (sizes: :data:`.distributions.SIZE_STREAM`, orientations:
:data:`ORIENTATION_STREAM`), species by species, so that each species' draws
do not depend on the others'.
"""

from __future__ import annotations

import math

import numpy as np

from softpack.scene import distributions

#: The seed-sequence stream of the orientations.
ORIENTATION_STREAM = 2
#: The shapes a rotation about their centre (about z in 3D) leaves alone.
ROUND = ("disk", "sphere", "cylinder")


def particle_table(species, seed=0) -> tuple[np.ndarray, np.ndarray]:
    """Per-particle diameters (m) and species indices, in body order.

    Parameters
    ----------
    species : list of dict
        ``config["species"]`` (every key, as the config has them).
    seed : int
        ``[packing] seed`` (draws of the size distributions).

    Returns
    -------
    diameters : ndarray of float, shape (n,)
    index : ndarray of int, shape (n,)
        The species (position in the list) of each particle.
    """
    counts = [int(s["count"]) for s in species]
    diameters = np.concatenate(
        [distributions.draw(_sized(s), seed, k) for k, s in enumerate(species)]
        or [np.empty(0)])
    index = np.repeat(np.arange(len(species), dtype=int), counts)
    return diameters.astype(float), index


def orientations(species, index, seed=0) -> np.ndarray:
    """Each particle's rotation about its centre (rad), in body order.

    ``orientation = "random"``: uniform in [0, 2 pi), seeded; ``"fixed"``:
    the species' ``angle`` (3D: about the z axis). Disks, spheres and
    cylinders are never rotated (0).
    """
    index = np.asarray(index)
    out = np.zeros(len(index))
    for k, s in enumerate(species):
        mine = index == k
        if s.get("shape", "disk") in ROUND:
            continue
        if s.get("orientation", "random") == "random":
            rng = np.random.default_rng([int(seed), ORIENTATION_STREAM, k])
            out[mine] = rng.uniform(0.0, 2 * math.pi, int(mine.sum()))
        else:
            out[mine] = float(s.get("angle", 0.0))
    return out


def check(species) -> None:
    """Refuse size keys that do not fit each species' distribution.

    Raises
    ------
    softpack.scene.distributions.DistributionError
        Naming ``[species.I]`` and the keys.
    """
    for k, s in enumerate(species):
        distributions.check(_sized(s), f"[species.{k}]")


def size_bounds(spec) -> tuple[float, float]:
    """Smallest and largest diameter of a species' particles (m)."""
    return distributions.bounds(_sized(spec))


def size_bound_keys(spec, end) -> str:
    """The keys behind :func:`size_bounds` (``end`` "min" or "max"), for
    messages (:func:`.distributions.bound_keys`)."""
    return distributions.bound_keys(_sized(spec), end)


def total_area(species) -> float:
    """Area of all the particles (m^2): every shape's area is pi D^2 / 4
    of its equal-area diameter; the expected area for a random
    distribution."""
    return sum(int(s["count"]) * math.pi / 4
               * distributions.mean_square(_sized(s)) for s in species)


def total_mass(sections) -> float:
    """The particles' mass per unit length (kg/m): each species' area
    (:func:`total_area`) times the density of its material, the
    ``[materials.NAME]`` it names or else ``[material]``. In 3D ([model]
    dimension = 3) their mass (kg): each species' volume
    (:func:`total_volume_3d`) times that density."""
    if sections["model"].get("dimension", 2) == 3:
        height = sections["model"]["thickness"]
        return sum(material_of(s, sections)["density"]
                   * total_volume_3d([s], height)
                   for s in sections["species"])
    return sum(material_of(s, sections)["density"] * total_area([s])
               for s in sections["species"])


def total_volume_3d(species, height) -> float:
    """Volume of all the solids of a 3D scene (m^3): a cylinder's pi D^2 /
    4 x ``height`` ([model] thickness), another solid's pi D^3 / 6 of its
    equal-volume diameter, D^3 taken as <D^2>^(3/2) (exact for one
    size)."""
    total = 0.0
    for s in species:
        d2 = distributions.mean_square(_sized(s))
        one = (math.pi / 4 * d2 * height if s["shape"] == "cylinder"
               else math.pi / 6 * d2 ** 1.5)
        total += int(s["count"]) * one
    return total


def material_of(spec, sections) -> dict:
    """A species' material table: ``[materials.NAME]`` for ``material =
    "NAME"``, ``[material]`` when it names none (checked by
    :func:`check_materials`)."""
    name = spec.get("material", "")
    return sections["materials"][name] if name else sections["material"]


def present(species) -> list:
    """The species with at least one particle."""
    return [s for s in species if int(s["count"]) > 0]


class SpeciesError(ValueError):
    """A species' material or a [[friction]] table that names what does
    not exist; the config stage prefixes the file name."""


#: The planes a 3D box adds to its four walls (the driver's wall names,
#: driver/simulation/box_3d.h), which [[friction]] may name.
BOX_PLANES_3D = ["base", "lid"]

#: The word of [[friction]] ``against`` that means every wall.
EVERY_WALL = "walls"


def check_materials(sections) -> None:
    """Refuse a species whose ``material`` names no [materials.NAME].

    Raises
    ------
    SpeciesError
        Naming ``[species.I] material`` and the names allowed.
    """
    named = sections["materials"]
    for k, s in enumerate(sections["species"]):
        if s["material"] and s["material"] not in named:
            allowed = ", ".join(repr(n) for n in named) or "none given"
            raise SpeciesError(
                f"[species.{k}] material = {s['material']!r}: no"
                f" [materials.{s['material']}] table (named materials:"
                f" {allowed}; empty: [material])")


#: Each law's own keys: a pair of another law leaves them at 0
LAW_KEYS = {"coulomb": (),
            "cohesive": ("cohesion", "cohesive_distance"),
            "bonded": ("tensile_strength", "shear_strength",
                       "bonding_distance")}
#: Each law's keys that must be > 0, and its distance (at most [contact]
#: alert_distance)
_LAW_POSITIVE = {"cohesive": ("cohesion",),
                 "bonded": ("tensile_strength", "shear_strength")}
_LAW_DISTANCE = {"cohesive": "cohesive_distance",
                 "bonded": "bonding_distance"}


def check_law(entry, title, contact) -> None:
    """Refuse a [[friction]] table whose law and law keys disagree.

    A ``cohesive`` pair needs ``cohesion > 0``, a ``bonded`` pair
    ``tensile_strength > 0`` and ``shear_strength > 0``; the distance of
    either (``cohesive_distance``, ``bonding_distance``) is at most
    ``[contact] alert_distance`` (farther pairs are no contact candidates,
    so a longer reach would not act); a pair has no key of another law
    (docs/contact_laws.md).

    Raises
    ------
    SpeciesError
        Naming the table, the key and what is allowed.
    """
    law = entry["law"]
    for other, keys in LAW_KEYS.items():
        for key in keys:
            if other != law and entry[key] != 0:
                raise SpeciesError(
                    f"[{title}] {key} = {entry[key]!r}: only law ="
                    f" \"{other}\" has a {key} (this pair's law is"
                    f" \"{law}\"; allowed: 0, or law = \"{other}\")")
    for key in _LAW_POSITIVE.get(law, ()):
        if not entry[key] > 0:
            raise SpeciesError(
                f"[{title}] {key} = {entry[key]!r}: law = \"{law}\" needs"
                f" a {key} > 0 (Pa; law = \"coulomb\" for none)")
    distance = _LAW_DISTANCE.get(law)
    if distance and entry[distance] > contact["alert_distance"]:
        raise SpeciesError(
            f"[{title}] {distance} = {entry[distance]!r}:"
            " must be <= [contact] alert_distance ="
            f" {contact['alert_distance']!r} (farther pairs are not contact"
            " candidates)")


def validate_friction(checker, section, items, sections) -> list:
    """Check the [[friction]] tables; return them complete.

    Each names a pair: ``species`` (a species name) and ``against`` (a
    species name, a wall name or ``"walls"``: every wall), and its law
    (:func:`check_law`). A pair may be named once (in either order); a wall
    named both by itself and through ``"walls"`` for the same species is
    refused too.

    Parameters
    ----------
    checker : softpack.scene.config._Checker
        Checks each table's keys and values against the schema.
    section : softpack.contract.schema.Section
        The schema's [friction].
    items : list
        The TOML's [[friction]] tables.
    sections : dict
        The validated sections (species, walls).

    Raises
    ------
    SpeciesError
        For a name that is neither a species nor a wall, a name that is both,
        or a pair named twice.
    """
    if not isinstance(items, (list, dict)):
        raise SpeciesError(
            f"key {section.name} outside a section: [[{section.name}]] is a"
            " list of pair tables; the default coefficient is [contact]"
            f" {section.name}")
    if not isinstance(items, list) or not all(isinstance(i, dict)
                                              for i in items):
        raise SpeciesError(f"[[{section.name}]] must be a list of tables")
    species = [s["name"] for s in sections["species"]]
    walls = list(sections["walls"])
    if sections.get("model", {}).get("dimension", 2) == 3:
        walls += BOX_PLANES_3D  # the base and lid of a 3D box are walls
    both = sorted(set(species) & set(walls + [EVERY_WALL]))
    out, seen = [], {}
    for i, item in enumerate(items):
        title = f"{section.name}.{i}"
        for key in ("species", "against"):
            if key not in item:
                raise SpeciesError(f"[{title}] {key} missing")
        entry = checker.table(section, item, title, [section.name, i])
        check_law(entry, title, sections["contact"])
        if entry["species"] not in species:
            raise SpeciesError(
                f"[{title}] species = {entry['species']!r}: not a species"
                f" (species: {', '.join(species)})")
        if entry["against"] not in species + walls + [EVERY_WALL]:
            raise SpeciesError(
                f"[{title}] against = {entry['against']!r}: not a species,"
                f" a wall or {EVERY_WALL!r} (species: {', '.join(species)};"
                f" walls: {', '.join(walls)})")
        if entry["against"] in both or entry["species"] in both:
            raise SpeciesError(
                f"[{title}]: {both[0]!r} names both a species and a wall"
                " (or the word 'walls'): rename the species")
        against = (walls if entry["against"] == EVERY_WALL
                   else [entry["against"]])
        for other in against:
            pair = frozenset((entry["species"], other))
            if pair in seen:
                raise SpeciesError(
                    f"[{title}] species = {entry['species']!r}, against ="
                    f" {entry['against']!r}: the pair"
                    f" ({entry['species']}, {other}) is already given by"
                    f" [{section.name}.{seen[pair]}]")
            seen[pair] = i
        out.append(entry)
    return out


def _sized(spec) -> dict:
    """A species with the size keys' defaults (tables written by hand, in
    tests, may give only diameter and count)."""
    return {"distribution": "fixed", "diameter_min": 0.0,
            "diameter_max": 0.0, "sigma": 0.0, "diameters": [], **spec}
