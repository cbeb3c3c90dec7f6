"""The scene's walls: the box's four and the free ones.

A wall is a line through ``point`` with the unit ``normal`` pointing to the
particles' side, translating at ``velocity``. With ``[box] enabled`` the
box ``[0, length] x [0, width]`` has the walls named in :data:`BOX_WALLS`,
whose point and inward normal come from the box (a ``[walls.NAME]`` table
only sets their velocity); every other wall is given in full. The order is
the contract's (docs/contract.md section 4): box walls first, then the
others in the order of the TOML file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: The box's walls, in driver.json order.
BOX_WALLS = ("left", "right", "bottom", "top")


@dataclass(frozen=True)
class Wall:
    """One rigid wall at t = 0 (SI units)."""

    name: str
    point: tuple
    normal: tuple
    velocity: tuple

    @property
    def speed(self) -> float:
        """The wall's speed |velocity| (m/s)."""
        return math.hypot(*self.velocity)

    def to_dict(self) -> dict:
        """``{"name", "point", "normal", "velocity"}`` with lists."""
        return {"name": self.name, "point": [float(v) for v in self.point],
                "normal": [float(v) for v in self.normal],
                "velocity": [float(v) for v in self.velocity]}


def box_geometry(length: float, width: float) -> dict:
    """``name -> (point, inward normal)`` of the box's four walls."""
    return {"left": ((0.0, 0.0), (1.0, 0.0)),
            "right": ((float(length), 0.0), (-1.0, 0.0)),
            "bottom": ((0.0, 0.0), (0.0, 1.0)),
            "top": ((0.0, float(width)), (0.0, -1.0))}


def unit(normal) -> tuple:
    """The normal scaled to length 1; ValueError for a zero vector."""
    norm = math.hypot(*normal)
    if not norm > 0:
        raise ValueError("a zero vector has no direction")
    return (normal[0] / norm, normal[1] / norm)


def scene_walls(config) -> list:
    """The configuration's walls as :class:`Wall`, in driver.json order.

    ``config["walls"]`` already holds every wall in that order with point
    and normal resolved (:func:`softpack.scene.config.validate`).
    """
    return [Wall(name, tuple(w["point"]), tuple(w["normal"]),
                 tuple(w["velocity"]))
            for name, w in config["walls"].items()]


def fastest(walls) -> Wall | None:
    """The fastest wall (None when there are none)."""
    return max(walls, key=lambda w: w.speed, default=None)
