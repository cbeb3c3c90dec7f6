"""Checks and derivations that involve several keys of a configuration.

:func:`derive` fills the schema's derived keys that the user left out (the
rule is the schema's ``derived`` text); :func:`check` refuses values that
are each in range but do not fit together. Both work on the sections of a
:class:`softpack.scene.config.Config` being built and raise
:class:`Inconsistent` with a message naming the keys; the config stage
prefixes the file name.
"""

from __future__ import annotations

import math

from softpack.scene.mesh import MIN_BOUNDARY_ELEMENTS
from softpack.scene.packing import HEXAGONAL_FRACTION, PackingError, \
    cell_sides
from softpack.scene import species as species_sizes
from softpack.scene.species import present, total_area, total_mass
from softpack.scene import cell_control
from softpack.scene.walls import (scene_walls, fastest, check_controls,
                                  derive_masses)
#: The Newton tolerance over the contact solver's: at least this.
NEWTON_OVER_NLGS = 10.0
#: ``contact.max_penetration`` over ``mesh.element_size``: at least this.
#: A detection deeper than max_penetration is taken as wrong-side and
#: ignored, so a smaller value lets bodies pass through each other unseen
#: (issue 16: 1e-9 m let 5 % of the disk area overlap while reporting
#: 1.6e-12 m); the examples use about h/2, the single-disk reference h/4.
MIN_PENETRATION_OVER_ELEMENT = 0.1


class Inconsistent(ValueError):
    """Values that do not fit together; the message names the keys."""


def derive(sections) -> None:
    """Fill ``stop.max_time``, ``contact.delassus_drop_tolerance`` and the
    walls' ``mass`` (the particles' total mass per unit length)."""
    contact = sections["contact"]
    if contact["delassus_drop_tolerance"] is None:
        contact["delassus_drop_tolerance"] = 1e-3 * contact["nlgs_tolerance"]
    derive_masses(sections["walls"], total_mass(sections))
    cell_control.derive_mass(sections["cell"], total_mass(sections))
    stop = sections["stop"]
    if stop["max_time"] is None:
        wall = fastest(scene_walls(sections))
        stop["max_time"] = half_box_time(
            "[stop] max_time", sections["box"], wall.speed if wall else 0.0,
            "the fastest wall speed", "wall")


def half_box_time(key, box, speed, fastest, wall) -> float:
    """The derived time bound: [box] length / (2 x ``speed``), the time a
    wall at that speed takes to cross half the box.

    Parameters
    ----------
    key : str
        The bound's key, for the message (``"[stop] max_time"``).
    box : dict
        The [box] section.
    speed : float
        The fastest wall speed (0: none moves).
    fastest, wall : str
        What the message calls that speed and the moving wall.

    Raises
    ------
    Inconsistent
        Without a box or a moving wall: the bound must be given.
    """
    if not box["enabled"] or not speed > 0:
        raise Inconsistent(
            f"{key} missing: it is derived as [box] length / (2 x {fastest})"
            f" only with a box and a moving {wall}; give it")
    return box["length"] / (2.0 * speed)


def initial_packing_fraction(sections) -> float:
    """Area of the rigid particles over the box's or the periodic cell's
    (0 with neither)."""
    box, cell = sections["box"], sections["cell"]
    if cell["enabled"]:
        (a1x, a1y), (a2x, a2y) = cell["a1"], cell["a2"]
        return total_area(sections["species"]) / abs(a1x * a2y - a1y * a2x)
    if not box["enabled"]:
        return 0.0
    return total_area(sections["species"]) / (box["length"] * box["width"])


def check(sections) -> None:
    """Refuse what does not fit together (see the module doc)."""
    _check_particles(sections)
    try:
        cell_control.check(sections["cell"])
    except cell_control.CellControlError as err:
        raise Inconsistent(str(err)) from None
    if sections["cell"]["enabled"]:
        _check_cell(sections)
    elif sections["model"]["dimension"] == 2:
        _check_box(sections)  # 3D: dimension.check
    try:
        check_controls(sections["walls"], sections["box"]["enabled"])
    except ValueError as err:
        raise Inconsistent(str(err)) from None
    _check_solvers(sections)


def _check_particles(sections) -> None:
    """At least one particle; elements small enough for the smallest."""
    used = present(sections["species"])
    if not used:
        raise Inconsistent("[[species]] count: there must be at least one"
                           " particle")
    try:
        species_sizes.check(sections["species"])
    except ValueError as err:
        raise Inconsistent(str(err)) from None
    k = _extreme(sections["species"], 0)
    smallest = sections["species"][k]
    d_min = species_sizes.size_bounds(smallest)[0]
    h = sections["mesh"]["element_size"]
    h_max = math.pi * d_min / MIN_BOUNDARY_ELEMENTS
    if h > h_max:
        raise Inconsistent(
            f"[mesh] element_size = {h!r}: must be <= {h_max:.4g} m (at least"
            f" {MIN_BOUNDARY_ELEMENTS} elements around the smallest particle,"
            f" species {smallest['name']}, D = {d_min:g} m from [species.{k}]"
            f" {species_sizes.size_bound_keys(smallest, 'min')})")


def _extreme(species, end) -> int:
    """The index of the present species with the smallest (``end`` 0) or
    largest (1) diameter bound."""
    used = [k for k, s in enumerate(species) if int(s["count"]) > 0]
    pick = min if end == 0 else max
    return pick(used, key=lambda k: species_sizes.size_bounds(species[k])[end])


def _check_box(sections) -> None:
    """Particles fit in the box; Phi0 below the target; no box, no Phi."""
    box, stop = sections["box"], sections["stop"]
    target = stop["packing_fraction"]
    if not box["enabled"]:
        if target > 0:
            raise Inconsistent(
                f"[stop] packing_fraction = {target!r}: must be 0 with [box]"
                " enabled = false (Phi is measured inside the box)")
        if sum(s["count"] for s in sections["species"]) != 1:
            raise Inconsistent(
                "[[species]] count: without a box the scene holds one"
                " particle, at the origin (the random packing needs a box)")
        return
    k = _extreme(sections["species"], 1)
    largest = sections["species"][k]
    d_max = species_sizes.size_bounds(largest)[1]
    room = min(box["length"], box["width"]) - 2 * sections["packing"]["gap"]
    if d_max >= room:
        raise Inconsistent(
            f"[species.{k}] (species {largest['name']!r})"
            f" {species_sizes.size_bound_keys(largest, 'max')}: must be <"
            f" {room:g} m (the box's shorter side minus twice [packing] gap)")
    _check_fill("box", initial_packing_fraction(sections), target)


def _check_fill(where, phi0, target) -> None:
    """The particles must fill less of the box (cell) than the Phi target
    and than a hexagonal packing."""
    limit = min(target, HEXAGONAL_FRACTION) if target > 0 \
        else HEXAGONAL_FRACTION
    if phi0 >= limit:
        raise Inconsistent(
            f"[{where}] the particles fill {phi0:.3f} of the {where}: must be"
            f" < [stop] packing_fraction = {target:g} and <"
            f" {HEXAGONAL_FRACTION:.4f} (hexagonal packing)")


def _check_cell(sections) -> None:
    """A periodic cell: no box or walls; every particle smaller
    than half the cell; its edges move less than the alert distance in a
    step; Phi0 below the target."""
    cell = sections["cell"]
    if sections["box"]["enabled"]:
        raise Inconsistent(
            "[cell] enabled = true with [box] enabled = true: a periodic"
            " cell has no walls; set [box] enabled = false")
    if sections["walls"]:
        names = ", ".join(f"[walls.{name}]" for name in sections["walls"])
        raise Inconsistent(
            f"{names}: a periodic cell ([cell] enabled) has no walls, both"
            " directions are periodic")
    if any(sections["gravity"]["acceleration"]):
        raise Inconsistent(
            f"[gravity] acceleration = {sections['gravity']['acceleration']!r}"
            " with [cell] enabled: in a periodic cell nothing holds the"
            " weight (the whole assembly would fall); set it to [0.0, 0.0]")
    try:
        length, width = cell_sides(cell)
    except PackingError as err:
        raise Inconsistent(str(err)) from None
    k = _extreme(sections["species"], 1)
    largest = sections["species"][k]
    d_max = species_sizes.size_bounds(largest)[1]
    if not d_max < min(length, width) / 2:
        raise Inconsistent(
            f"[species.{k}] (species {largest['name']!r})"
            f" {species_sizes.size_bound_keys(largest, 'max')} m:"
            f" must be smaller than half the cell ([cell] a1 = {cell['a1']},"
            f" a2 = {cell['a2']}: half is {min(length, width) / 2:g} m), or a"
            " particle would touch two images of a neighbour")
    speed = cell_speed(cell)
    step, key = largest_time_step(sections)
    alert = sections["contact"]["alert_distance"]
    if speed * step > alert:
        raise Inconsistent(
            f"{key} = {step:.4g}: must be <= {alert / speed:.4g} s ([contact]"
            " alert_distance / the speed of the cell's edges, |L a1| and"
            " |L a2| from [cell]: no image may move more than the alert"
            " distance in one step)")
    penetration = sections["contact"]["max_penetration"]
    if speed * step > penetration:
        raise Inconsistent(
            f"[contact] max_penetration = {penetration!r}: must be >="
            f" {speed * step:.4g} m (the travel of the cell's images in one"
            f" step of {key}): a deeper detection is ignored as wrong-side")
    _check_fill("cell", total_area(sections["species"]) / (length * width),
                sections["stop"]["packing_fraction"])


def cell_speed(cell) -> float:
    """The speed of the cell's edges at t = 0: max(|L a1|, |L a2|)."""
    rows = (cell["velocity_gradient_x"], cell["velocity_gradient_y"])
    return max(math.hypot(*(r[0] * a[0] + r[1] * a[1] for r in rows))
               for a in (cell["a1"], cell["a2"]))


def largest_time_step(sections) -> tuple[float, str]:
    """The largest step the driver may take and the keys that set it:
    ``[time] time_step`` times ``max_step_factor``."""
    time = sections["time"]
    if time["max_step_factor"] > 1:
        return (time["time_step"] * time["max_step_factor"],
                "[time] time_step x max_step_factor")
    return time["time_step"], "[time] time_step"


def _check_solvers(sections) -> None:
    """NLGS below Newton; no wall moves past the alert distance per step."""
    newton = sections["time"]["newton_tolerance"]
    nlgs = sections["contact"]["nlgs_tolerance"]
    if nlgs > newton / NEWTON_OVER_NLGS:
        raise Inconsistent(
            f"[contact] nlgs_tolerance = {nlgs!r}: must be <="
            f" {newton / NEWTON_OVER_NLGS:.3g} (a tenth of [time]"
            " newton_tolerance: the Newton iterations cannot converge below"
            " the noise of the contact solve)")
    wall = fastest(scene_walls(sections))
    step, key = largest_time_step(sections)
    alert = sections["contact"]["alert_distance"]
    if wall is not None and wall.speed * step > alert:
        raise Inconsistent(
            f"{key} = {step:.4g}: must be <= {alert / wall.speed:.4g}"
            f" s ([contact] alert_distance / the speed of [walls.{wall.name}]"
            ": no wall may move more than the alert distance in one step)")
    _check_max_penetration(sections, wall)


def _check_max_penetration(sections, wall) -> None:
    """max_penetration above what one step can move and h / 10.

    One step may push a node up to a wall's travel (speed x time_step)
    past a boundary, and a discretised boundary overlaps another by up to
    a fraction of the element size h (a chord's sagitta): a legitimate
    penetration deeper than max_penetration would be ignored as wrong-side.
    """
    mp = sections["contact"]["max_penetration"]
    h = sections["mesh"]["element_size"]
    least = MIN_PENETRATION_OVER_ELEMENT * h
    why = (f"{MIN_PENETRATION_OVER_ELEMENT:g} x [mesh] element_size ="
           f" {h:g} m")
    if wall is not None:
        step, key = largest_time_step(sections)
        travel = wall.speed * step
        if travel > least:
            least, why = travel, (f"the travel of [walls.{wall.name}] in one"
                                  f" step of {key}")
    if mp < least * (1 - 1e-12):  # h / 10 itself, despite rounding
        raise Inconsistent(
            f"[contact] max_penetration = {mp!r}: must be >= {least:.4g} m"
            f" ({why}): a deeper detection is ignored as wrong-side, so"
            " bodies would pass through each other unseen")
