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
    the species' ``angle``. Disks are never rotated (0).
    """
    index = np.asarray(index)
    out = np.zeros(len(index))
    for k, s in enumerate(species):
        mine = index == k
        if s.get("shape", "disk") == "disk":
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


def total_area(species) -> float:
    """Area of all the particles (m^2): every shape's area is pi D^2 / 4
    of its equal-area diameter; the expected area for a random
    distribution."""
    return sum(int(s["count"]) * math.pi / 4
               * distributions.mean_square(_sized(s)) for s in species)


def present(species) -> list:
    """The species with at least one particle."""
    return [s for s in species if int(s["count"]) > 0]


def _sized(spec) -> dict:
    """A species with the size keys' defaults (tables written by hand, in
    tests, may give only diameter and count)."""
    return {"distribution": "fixed", "diameter_min": 0.0,
            "diameter_max": 0.0, "sigma": 0.0, "diameters": [], **spec}
