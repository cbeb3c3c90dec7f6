"""Particle species -> the per-particle table of the scene.

``[[species]]`` gives each species a name, a shape, a diameter and a count.
Particles are numbered species by species in the file's order (the paper's
case: bodies 0-69 are the 20-mm disks, 70-99 the 30-mm ones); that order is
the body order of the packing, the mesh and the driver.
"""

from __future__ import annotations

import math

import numpy as np


def particle_table(species) -> tuple[np.ndarray, np.ndarray]:
    """Per-particle diameters (m) and species indices, in body order.

    Parameters
    ----------
    species : list of dict
        ``config["species"]``: each with ``diameter`` and ``count``.

    Returns
    -------
    diameters : ndarray of float, shape (n,)
    index : ndarray of int, shape (n,)
        The species (position in the list) of each particle.
    """
    counts = [int(s["count"]) for s in species]
    diameters = np.repeat([float(s["diameter"]) for s in species], counts)
    index = np.repeat(np.arange(len(species), dtype=int), counts)
    return diameters.astype(float), index


def total_area(species) -> float:
    """Area of all the particles (m^2)."""
    return sum(int(s["count"]) * math.pi * float(s["diameter"]) ** 2 / 4
               for s in species)


def present(species) -> list:
    """The species with at least one particle."""
    return [s for s in species if int(s["count"]) > 0]
