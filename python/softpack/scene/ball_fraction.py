"""The packing fraction of disks (spheres) in a box: one rule for the
placement, the growth protocol and the scenes (2D and 3D)."""

from __future__ import annotations

import numpy as np

#: Volume of the unit ball, per dimension.
UNIT_BALL = {2: np.pi, 3: 4.0 * np.pi / 3.0}


def ball_fraction(radii, extent) -> float:
    """Packing fraction of disks (spheres) of the given radii in the box
    of edges ``extent`` (2 or 3 of them)."""
    d = len(extent)
    return float(UNIT_BALL[d] * np.sum(np.asarray(radii) ** d)
                 / np.prod(extent))
