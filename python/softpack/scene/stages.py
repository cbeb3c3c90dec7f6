"""``[[stages]]``: a loading program, validated and completed.

A run is a sequence of stages (schema/parameters.toml, section
``[stages]``); each gives some walls a new drive and ends at its own stop
criterion. In the TOML file::

    [[stages]]
    name = "consolidate"
    walls.right = { control = "pressure", pressure = 1e4 }
    walls.top = { pressure = 1e4 }          # control "pressure" implied
    contact = { friction = 0.0 }            # from here on; else kept
    stop = { equilibrium = 1e-3, max_time = 0.5 }

or, in a periodic cell, a new drive of the cell (given whole: the keys it
leaves out take [cell]'s defaults)::

    cell = { velocity_gradient_x = [0.0, 2.0], control_yy = "stress",
             stress_yy = 2e3 }

A :class:`~softpack.scene.config.Config` holds every stage complete, as
driver.json takes it: ``{"name", "walls": {NAME: {"control", "velocity",
"pressure", "force"}}, "contact": {KEY: value}, "cell": {KEY: value},
"stop": {KEY: value}}`` with every contact, cell and stop key of the schema
(``contact.KEY``, ``cell.KEY``, ``stop.KEY``) set, the derived ``max_time``
and ``strain_wall`` computed. Walls a stage does not name keep the drive
they had, a contact key its value and the cell its drive; the first stage
starts from ``[walls]``, ``[contact]`` and ``[cell]``.

Errors name the file, the stage (``[stages.INDEX]``) and the key, like
the rest of the configuration's.
"""

from __future__ import annotations

import dataclasses
import math

from softpack.scene import cell_control
from softpack.scene.consistency import (Inconsistent, cell_speed,
                                        half_box_time, largest_time_step)
from softpack.contract.schema import load_schema
from softpack.scene.walls import CONTROL, check_drive, drive_keys

#: The keys of one stage.
STAGE_KEYS = ("name", "bond", "walls", "contact", "cell", "stop")
#: The prefix of the stop keys in the schema's [stages] section.
STOP = "stop."
#: The prefix of the contact keys in the schema's [stages] section.
CONTACT = "contact."
#: The prefix of the cell's drive keys in the schema's [stages] section.
CELL = "cell."
#: Normals whose dot product is below -1 + this face each other.
FACING_TOLERANCE = 1e-9


class StageError(ValueError):
    """An invalid stage; the config stage prefixes the file name."""


def stop_specs(section) -> dict:
    """``key -> Parameter`` of the stop keys (without ``stop.``)."""
    return _prefixed(section, STOP)


def _prefixed(section, prefix) -> dict:
    """``key -> Parameter`` of the keys ``PREFIX.KEY`` (without it)."""
    return {key[len(prefix):]: spec for key, spec in
            section.parameters.items() if key.startswith(prefix)}


def validate(checker, section, items, sections, given_stop) -> list:
    """Check the ``[[stages]]`` tables; return them complete.

    Parameters
    ----------
    checker : softpack.scene.config._Checker
        Checks values against their schema entries, naming file and key.
    section : softpack.contract.schema.Section
        The schema's [stages].
    items : list or None
        The file's ``stages`` (None: no stages).
    sections : dict
        The configuration's sections checked so far (box, walls, time,
        contact, stop); with stages, ``stop.packing_fraction`` is set to 0
        and ``stop.max_time`` derived as the sum of the stages' bounds.
    given_stop : dict
        The file's own [stop] table (what the user set).

    Raises
    ------
    StageError
    """
    if items is None or items == []:
        return []
    if not isinstance(items, list) or not all(isinstance(i, dict)
                                              for i in items):
        raise StageError("[[stages]] must be one or more tables")
    drives = {name: {k: w[k] for k in drive_keys()}
              for name, w in sections["walls"].items()}
    contact = {key: sections["contact"][key]
               for key in _prefixed(section, CONTACT)}
    cell = {key: sections["cell"][key] for key in _prefixed(section, CELL)}
    out = []
    for i, item in enumerate(items):
        title = f"stages.{i}"
        checker.keys(title, item, STAGE_KEYS)
        name = item.get("name", f"stage{i}")
        name = checker.value(title, ["stages", i, "name"],
                             section.parameters["name"], name) or f"stage{i}"
        drives = _apply_walls(checker, i, item.get("walls", {}), drives,
                              sections)
        contact = _contact(checker, section, i, item.get("contact", {}),
                           contact)
        cell = _cell(checker, section, i, item.get("cell"), cell, sections)
        stop = _stop(checker, section, i, item.get("stop", {}), drives,
                     sections)
        bond = checker.value(title, ["stages", i, "bond"],
                             section.parameters["bond"],
                             item.get("bond", False))
        if bond and not any(f["law"] == "bonded"
                            for f in sections.get("friction", [])):
            raise StageError(
                f"[{title}] bond = true: no [[friction]] pair has law ="
                " \"bonded\" (nothing to bond)")
        out.append({"name": name, "bond": bond,
                     "walls": {w: dict(d) for w, d in drives.items()
                               if w in item.get("walls", {})},
                     "contact": dict(contact), "cell": dict(cell),
                     "stop": stop})
    names = [s["name"] for s in out]
    if len(set(names)) != len(names):
        raise StageError(f"[[stages]] names {names!r}: must differ")
    _global_stop(sections["stop"], given_stop, out)
    return out


def _apply_walls(checker, index, entries, drives, sections) -> dict:
    """The walls' drives after a stage's ``walls`` entries."""
    title = f"stages.{index}"
    if not isinstance(entries, dict):
        raise StageError(f"[{title}] walls must be a table of walls.NAME ="
                         f" {{ {', '.join(drive_keys())} }}")
    walls_schema = load_schema()["walls"].parameters
    new = {name: dict(d) for name, d in drives.items()}
    for wall, entry in entries.items():
        where = f"[{title}] walls.{wall}"
        if wall not in drives:
            raise StageError(f"{where}: unknown wall (walls: "
                             f"{', '.join(drives)})")
        checker.keys(f"{title}.walls.{wall}", entry, drive_keys())
        values = {}
        for key, value in entry.items():
            spec = dataclasses.replace(walls_schema[key],
                                       key=f"walls.{wall}.{key}")
            values[key] = checker.value(title, ["stages", index, "walls",
                                                wall, key], spec, value)
        values[CONTROL] = _control(where, values)
        try:
            check_drive(f"{where}.", wall, values, sections["box"]["enabled"],
                        " in this stage", given=entry)
        except ValueError as err:
            raise StageError(str(err)) from None
        new[wall] = {CONTROL: values[CONTROL],
                     "velocity": list(values.get("velocity", [0.0, 0.0])),
                     "pressure": float(values.get("pressure", 0.0)),
                     "force": float(values.get("force", 0.0))}
        _check_speed(where, new[wall], sections)
    return new


def _control(where, values) -> str:
    """The entry's control: given, or the first drive whose value is given
    (:func:`~softpack.scene.walls.check_drive` then refuses the others)."""
    given = [k for k in drive_keys()[1:] if k in values]
    control = values.get(CONTROL)
    if control is None:
        if not given:
            raise StageError(f"{where}: give control or one of"
                             f" {', '.join(drive_keys()[1:])}")
        control = given[0]
    if control != "velocity" and control not in values:
        raise StageError(f"{where}.{control} missing: control ="
                         f" \"{control}\" needs its value")
    return control


def _check_speed(where, drive, sections) -> None:
    """No wall may move more than the alert distance (or the largest
    penetration taken as real) in one time step."""
    speed = math.hypot(*drive["velocity"])
    step, key = largest_time_step(sections)
    contact = sections["contact"]
    limit = min(contact["alert_distance"], contact["max_penetration"])
    if speed * step > limit:
        raise StageError(
            f"{where}.velocity = {drive['velocity']!r}: moves"
            f" {speed * step:.3g} m per step of {key}, more than [contact]"
            f" alert_distance or max_penetration ({limit:g} m)")


def _contact(checker, section, index, table, before) -> dict:
    """A stage's contact keys: given, else the stage before's (the first
    stage's: [contact]'s)."""
    title = f"stages.{index}"
    specs = _prefixed(section, CONTACT)
    if not isinstance(table, dict):
        raise StageError(f"[{title}] contact must be a table (keys:"
                         f" {', '.join(specs)})")
    checker.keys(f"{title}.contact", table, list(specs))
    return {key: checker.value(title, ["stages", index, "contact", key],
                               spec, table[key]) if key in table
            else before[key] for key, spec in specs.items()}


def _cell(checker, section, index, table, before, sections) -> dict:
    """A stage's cell drive: none given, the stage before's (the first
    stage's: [cell]'s); given, its keys with [cell]'s defaults for the ones
    it leaves out (a drive is given whole, as a wall's)."""
    title = f"stages.{index}"
    if table is None:
        return before
    specs = _prefixed(section, CELL)
    if not isinstance(table, dict):
        raise StageError(f"[{title}] cell must be a table (keys:"
                         f" {', '.join(specs)})")
    if not sections["cell"]["enabled"]:
        raise StageError(f"[{title}] cell: the run has no periodic cell"
                         " ([cell] enabled = false); a stage drives walls"
                         " with walls.NAME")
    checker.keys(f"{title}.cell", table, list(specs))
    drive = {key: checker.value(title, ["stages", index, "cell", key],
                                spec, table[key]) if key in table
             else spec.default for key, spec in specs.items()}
    try:
        cell_control.check(drive, True, f"[{title}] cell.")
    except cell_control.CellControlError as err:
        raise StageError(str(err)) from None
    speed = cell_speed({**sections["cell"], **drive})
    step, key = largest_time_step(sections)
    limit = min(sections["contact"]["alert_distance"],
                sections["contact"]["max_penetration"])
    if speed * step > limit:
        raise StageError(
            f"[{title}] cell.velocity_gradient_x, _y: the cell's edges move"
            f" {speed * step:.3g} m per step of {key} (at the initial cell),"
            " more than [contact] alert_distance or max_penetration"
            f" ({limit:g} m)")
    return drive


def _stop(checker, section, index, table, drives, sections) -> dict:
    """A stage's stop keys, checked, with max_time and strain_wall derived."""
    title = f"stages.{index}"
    specs = stop_specs(section)
    if not isinstance(table, dict):
        raise StageError(f"[{title}] stop must be a table (keys:"
                         f" {', '.join(specs)})")
    checker.keys(f"{title}.stop", table, list(specs))
    stop = {}
    for key, spec in specs.items():
        if key in table:
            stop[key] = checker.value(title, ["stages", index, "stop", key],
                                      spec, table[key])
        else:
            stop[key] = None if spec.derived else spec.default
    boxed = sections["box"]["enabled"]
    celled = sections["cell"]["enabled"]
    for key in ("packing_fraction", "pressure"):
        if stop[key] > 0 and not boxed and not (celled and
                                                key == "packing_fraction"):
            raise StageError(f"[{title}] stop.{key} = {stop[key]!r}: needs a"
                             " box (it is measured on the box's walls)"
                             + (" or a cell" if key == "packing_fraction"
                                else ""))
    moving = _fastest(drives)
    if stop["strain_wall"] is None:
        stop["strain_wall"] = moving if (stop["strain"] > 0 and moving) \
            else ""
    if stop["strain"] > 0:
        if not stop["strain_wall"]:
            raise StageError(
                f"[{title}] stop.strain = {stop['strain']!r}: the stage has"
                " no moving velocity-controlled wall; name the wall whose"
                " strain it is with stop.strain_wall")
        _check_strain_wall(title, stop["strain_wall"], sections["walls"])
    elif stop["strain_wall"]:
        _check_strain_wall(title, stop["strain_wall"], sections["walls"])
    if stop["max_time"] is None:
        speed = math.hypot(*drives[moving]["velocity"]) if moving else 0.0
        try:
            stop["max_time"] = half_box_time(
                f"[{title}] stop.max_time", sections["box"], speed,
                "the stage's fastest wall speed", "velocity-controlled wall")
        except Inconsistent as err:
            raise StageError(str(err)) from None
    return stop


def _fastest(drives) -> str:
    """The fastest moving velocity-controlled wall ("" when none)."""
    best, name = 0.0, ""
    for wall, d in drives.items():
        speed = math.hypot(*d["velocity"]) if d["control"] == "velocity" \
            else 0.0
        if speed > best:
            best, name = speed, wall
    return name


def _check_strain_wall(title, name, walls) -> None:
    """The wall exists and another faces it (its strain has a length)."""
    if name not in walls:
        raise StageError(f"[{title}] stop.strain_wall = {name!r}: unknown"
                         f" wall (walls: {', '.join(walls)})")
    n = walls[name]["normal"]
    if not any(other != name and n[0] * w["normal"][0] + n[1] *
               w["normal"][1] < -1 + FACING_TOLERANCE
               for other, w in walls.items()):
        raise StageError(f"[{title}] stop.strain_wall = {name!r}: no wall"
                         " faces it (opposite normal), so its strain has no"
                         " length")


def _global_stop(stop, given, stages) -> None:
    """[stop] with stages: no global Phi target; max_time the stages' sum."""
    if given.get("packing_fraction", 0) != 0:
        raise StageError(
            f"[stop] packing_fraction = {given['packing_fraction']!r}: must"
            " be 0 with [[stages]] (each stage has its own"
            " stop.packing_fraction)")
    stop["packing_fraction"] = 0.0
    total = sum(s["stop"]["max_time"] for s in stages)
    if stop["max_time"] is None:
        stop["max_time"] = total
    elif stop["max_time"] < total * (1 - 1e-12):
        raise StageError(
            f"[stop] max_time = {stop['max_time']!r}: must be >= {total:g} s,"
            " the sum of the stages' stop.max_time (or left out: it is then"
            " that sum)")
