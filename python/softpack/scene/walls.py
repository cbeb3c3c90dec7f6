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

from softpack.contract.schema import load_schema

#: The box's walls, in driver.json order.
BOX_WALLS = ("left", "right", "bottom", "top")
#: The key of [walls] that says what drives a wall (schema ``_drive``).
CONTROL = "control"


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
                 tuple(w["velocity"]), w.get(CONTROL, "velocity"),
                 w.get("pressure", 0.0), w.get("force", 0.0),
                 w.get("mass") or 1.0)
            for name, w in config["walls"].items()]


def drive_keys() -> tuple:
    """The keys of a wall's drive: ``control`` and the value key that each
    of its choices names (schema [walls]: velocity, pressure, force); a
    stage's ``walls.NAME`` sets these only."""
    return (CONTROL, *load_schema()["walls"].parameters[CONTROL].choices)


def check_drive(prefix: str, wall: str, drive: dict, boxed: bool,
                scope: str = "", given=None) -> None:
    """Refuse a wall driven two ways, or by a pressure with no length.

    The one rule of a wall's drive, for [walls.NAME] and a stage's
    walls.NAME alike: only the value of its ``control`` is set, and only a
    box wall has the length that turns a pressure into a force.

    Parameters
    ----------
    prefix : str
        What the message names before the key: ``"[walls.right] "`` or
        ``"[stages.0] walls.right."``.
    wall : str
        The wall's name.
    drive : dict
        Its drive keys (``control`` set; a value key absent counts as 0).
    boxed : bool
        ``[box] enabled``.
    scope : str
        Said after the control in the message (``" in this stage"``).
    given : collection of str, optional
        The keys the user wrote (a stage's entry): a value key of another
        drive among them is refused, whatever its value. None (a [walls]
        table, written back with every key): such a value must be 0.

    Raises
    ------
    ValueError
        Naming the table and the key, e.g. ``[walls.right] velocity``.
    """
    control = drive[CONTROL]
    for key in drive_keys()[1:]:
        value = drive.get(key, 0.0)
        values = value if isinstance(value, (list, tuple)) else [value]
        is_set = key in given if given is not None else any(
            v != 0 for v in values)
        if key != control and is_set:
            raise ValueError(
                f"{prefix}{key} = {value!r}: the wall is under control ="
                f" \"{control}\"{scope}; a wall is driven by one of velocity,"
                f" pressure or force (remove {key}, or set control)")
    if control == "pressure" and not (boxed and wall in BOX_WALLS):
        raise ValueError(
            f"{prefix}control = \"pressure\": only a box wall (left, right,"
            " bottom, top with [box] enabled) has a length to turn a pressure"
            " into a force; use control = \"force\"")


def check_controls(walls: dict, boxed: bool) -> None:
    """:func:`check_drive` for every [walls.NAME] table (validated keys)."""
    for name, w in walls.items():
        check_drive(f"[walls.{name}] ", name, w, boxed)


def derive_masses(walls: dict, mass: float) -> None:
    """Set every wall's ``mass`` left out (None) to ``mass`` (kg/m)."""
    for w in walls.values():
        if w.get("mass") is None:
            w["mass"] = float(mass)


def fastest(walls) -> Wall | None:
    """The fastest wall (None when there are none)."""
    return max(walls, key=lambda w: w.speed, default=None)
