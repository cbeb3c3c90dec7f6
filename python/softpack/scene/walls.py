"""The scene's walls: the box's four and the free ones.

A wall is a line through ``point`` with the unit ``normal`` pointing to the
particles' side, translating at ``velocity`` (``control = "velocity"``) or,
a servo wall, pushed towards the particles by an imposed ``pressure`` (Pa:
force per unit length along z over the wall's current length, the distance
between its two box neighbours) or ``force`` (N/m); a servo wall's velocity
along its normal is an unknown of each time step (the driver's
``driver/dynamics/servo_walls.h``), and its ``mass`` (kg/m) is numerical. With ``[box] enabled`` the
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
    control: str = "velocity"
    pressure: float = 0.0
    force: float = 0.0
    mass: float = 1.0

    @property
    def servo(self) -> bool:
        """Its normal velocity is an unknown (pressure or force control)."""
        return self.control != "velocity"

    @property
    def speed(self) -> float:
        """The wall's speed |velocity| (m/s)."""
        return math.hypot(*self.velocity)

    def to_dict(self) -> dict:
        """``{"name", "point", "normal", "velocity", "control", "pressure",
        "force", "mass"}`` with lists."""
        return {"name": self.name, "point": [float(v) for v in self.point],
                "normal": [float(v) for v in self.normal],
                "velocity": [float(v) for v in self.velocity],
                "control": self.control, "pressure": float(self.pressure),
                "force": float(self.force), "mass": float(self.mass)}


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
                 tuple(w["velocity"]), w.get("control", "velocity"),
                 w.get("pressure", 0.0), w.get("force", 0.0),
                 w.get("mass") or 1.0)
            for name, w in config["walls"].items()]


def check_controls(walls: dict, boxed: bool) -> None:
    """Refuse a wall driven two ways, or by a pressure with no length.

    Parameters
    ----------
    walls : dict
        ``name -> values`` of the [walls.NAME] tables (validated keys).
    boxed : bool
        ``[box] enabled``: only box walls have a length for a pressure.

    Raises
    ------
    ValueError
        Naming the table and the key, e.g. ``[walls.right] velocity``.
    """
    imposed = {"velocity": ("pressure", "force"),
               "pressure": ("velocity", "force"),
               "force": ("velocity", "pressure")}
    for name, w in walls.items():
        control = w.get("control", "velocity")
        for key in imposed[control]:
            value = w.get(key, 0.0)
            if any(v != 0 for v in (value if isinstance(value, (list, tuple))
                                    else [value])):
                raise ValueError(
                    f"[walls.{name}] {key} = {value!r}: the wall is under"
                    f" control = \"{control}\"; a wall is driven by one of"
                    " velocity, pressure or force (set control, or remove"
                    f" {key})")
        if control == "pressure" and not (boxed and name in BOX_WALLS):
            raise ValueError(
                f"[walls.{name}] control = \"pressure\": only a box wall"
                " (left, right, bottom, top with [box] enabled) has a length"
                " to turn a pressure into a force; use control = \"force\"")


def derive_masses(walls: dict, mass: float) -> None:
    """Set every wall's ``mass`` left out (None) to ``mass`` (kg/m)."""
    for w in walls.values():
        if w.get("mass") is None:
            w["mass"] = float(mass)


def fastest(walls) -> Wall | None:
    """The fastest wall (None when there are none)."""
    return max(walls, key=lambda w: w.speed, default=None)
