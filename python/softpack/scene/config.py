"""The run configuration: one TOML file, validated before any computation.

The sections and keys, their types, ranges, choices, defaults and units
are those of ``schema/parameters.toml`` (:mod:`softpack.contract.schema`); the
material laws and the keys of ``[material.parameters]`` are those of the
registry built from ``forms/materials/`` (:mod:`softpack.scene.materials`).
Nothing here restates a range, a default or a name.

:func:`load_config` raises :class:`ConfigError` for a file that cannot be
read or parsed, an unknown section or key, a value of the wrong type or out
of range, and inconsistent values (:mod:`softpack.scene.consistency`). The
message names the file, the key and what is allowed::

    examples/x.toml: [contact] friction = -1: must be >= 0
    examples/x.toml: unknown key [time] stepp (allowed: time_step, max_step_factor, ...)

Values the user leaves out take their defaults; the schema's derived keys
(``derived = ...``) and the law's expression defaults are computed. A
:class:`Config` holds every key, so :func:`to_toml` writes a complete,
reloadable copy.

Layout of a :class:`Config`: ``config[section][key]`` for plain sections;
``config["species"]`` a list of dicts; ``config["walls"]`` an ordered dict
``name -> {"point", "normal", "velocity"}`` holding every wall (the box's
four first, their point and normal from the box); ``config["material"]
["parameters"]`` the law's parameters.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from pathlib import Path

from softpack.scene import consistency, dimension, species as species_rules, stages
from softpack.scene.materials import RegistryError, load_registry, resolve
from softpack.contract.schema import MATERIAL_CHOICES, load_schema
from softpack.scene.walls import BOX_WALLS, CONTROL, box_geometry, unit

#: The sub-table of [material] that holds the law's own parameters.
LAW_TABLE = "parameters"


class ConfigError(ValueError):
    """An invalid configuration; the message names file, key and range."""


class Config(dict):
    """A validated configuration, every key set (see the module doc).

    Attributes
    ----------
    source : str
        Where it came from (the file name), for messages.
    """

    def __init__(self, sections, source):
        super().__init__(sections)
        self.source = str(source)

    @property
    def stem(self) -> str:
        """The source file's name without suffix (``paper``)."""
        return Path(self.source).stem


def load_config(path, overrides=None, registry=None) -> Config:
    """Read and validate a TOML configuration file.

    Parameters
    ----------
    path : str or Path
        The TOML file.
    overrides : dict, optional
        ``{"section.key": value}`` applied on top of the file (e.g. from the
        command line), validated like the file's values and blamed on the
        command line in messages. Nested names: ``material.parameters.KEY``,
        ``walls.NAME.KEY``, ``species.INDEX.KEY``.
    registry : dict, optional
        The material laws (default: :func:`~softpack.scene.materials.
        load_registry`).

    Raises
    ------
    ConfigError
    """
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except OSError as err:
        raise ConfigError(f"{path}: cannot read: {err.strerror}") from None
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"{path}: invalid TOML: {err}") from None
    return validate(data, path, overrides, registry)


def validate(data: dict, source="<config>", overrides=None,
             registry=None) -> Config:
    """Validate parsed TOML data; return the complete :class:`Config`.

    Parameters are those of :func:`load_config` (``data`` in place of the
    file). ``data`` is not modified.

    Raises
    ------
    ConfigError
    """
    data = copy.deepcopy(data)
    from_cli = _apply_overrides(data, overrides or {}, source)
    checker = _Checker(source, from_cli, registry)
    schema = load_schema()
    allowed = f"(allowed sections: {', '.join(schema)})"
    for name, table in data.items():
        if name not in schema:
            if not isinstance(table, (dict, list)):
                raise ConfigError(f"{source}: key {name} outside a section"
                                  f" {allowed}")
            blame = next((f"--set {'.'.join(map(str, key))}" for key in
                          sorted(from_cli, key=str) if key[0] == name), source)
            raise ConfigError(f"{blame}: unknown section [{name}]"
                              f" {allowed}")
    sections = {}
    for name, section in schema.items():
        if name == "stages":
            continue  # after [walls], which they change
        if name == "friction":
            continue  # after [walls] and [materials], whose names it uses
        if section.is_list:
            sections[name] = checker.species(section, data.get(name))
        elif section.is_map:
            continue  # walls: after [box], which they depend on
        elif name == "material":
            sections[name] = checker.material(section, data.get(name, {}))
        else:
            sections[name] = checker.table(section, data.get(name, {}), name)
    for name, section in schema.items():
        if section.is_map and name == "materials":
            sections[name] = checker.materials(section, data.get(name, {}))
        elif section.is_map:
            sections[name] = checker.walls(section, data.get(name, {}),
                                           sections["box"])
    try:
        species_rules.check_materials(sections)
        sections["friction"] = species_rules.validate_friction(
            checker, schema["friction"], data.get("friction", []), sections)
    except species_rules.SpeciesError as err:
        raise ConfigError(f"{source}: {err}") from None
    try:
        sections["stages"] = stages.validate(
            checker, schema["stages"], data.get("stages"), sections,
            data.get("stop", {}))
    except stages.StageError as err:
        raise ConfigError(f"{source}: {err}") from None
    sections = {name: sections[name] for name in schema}
    try:
        dimension.check(sections, checker.registry())
    except dimension.DimensionError as err:
        raise ConfigError(f"{source}: {err}") from None
    try:
        consistency.derive(sections)
        consistency.check(sections)
    except consistency.Inconsistent as err:
        raise ConfigError(f"{source}: {err}") from None
    return Config(sections, source)


def _apply_overrides(data, overrides, source) -> set:
    """Set ``{"a.b.c": value}`` into ``data``; return the paths set."""
    schema = load_schema()
    done = set()
    for name, value in overrides.items():
        parts = name.split(".")
        if len(parts) < 2 or not all(parts):
            raise ConfigError(f"{source}: override {name!r}: expected"
                              " SECTION.KEY")
        node, path = data, []
        for part in parts[:-1]:
            if isinstance(node, list):
                if not part.isdigit() or int(part) >= len(node):
                    raise ConfigError(
                        f"{source}: override {name!r}: {part!r} is not one"
                        f" of the {len(node)} [[{path[0]}]] (0, 1, ...)")
                key = int(part)
            else:
                key = part
                if key not in node:
                    section = None if path else schema.get(key)
                    node[key] = (copy.deepcopy(list(section.default_list))
                                 if section is not None and section.is_list
                                 else {})
            node = node[key]
            path.append(key)
            if not isinstance(node, (dict, list)):
                raise ConfigError(f"{source}: override {name!r}:"
                                  f" [{'.'.join(map(str, path))}] is not a"
                                  " table")
        if isinstance(node, list):
            raise ConfigError(f"{source}: override {name!r}: expected"
                              f" {parts[0]}.INDEX.KEY")
        node[parts[-1]] = value
        done.add(tuple(path + [parts[-1]]))
    return done


def _show(value) -> str:
    """A value as it would be written in TOML."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{...}"
    return repr(value)


def _is_number(value, kind) -> bool:
    """Whether a TOML value is a finite number of the kind (no booleans)."""
    if isinstance(value, bool):
        return False
    if kind == "int":
        return isinstance(value, int)
    return isinstance(value, (int, float)) and math.isfinite(value)


class _Checker:
    """Type- and range-checks values against the schema, naming them."""

    def __init__(self, source, from_cli, registry):
        self.source = source
        self.from_cli = from_cli
        self._registry = registry

    def registry(self) -> dict:
        """The material laws (loaded once)."""
        if self._registry is None:
            try:
                self._registry = load_registry()
            except RegistryError as err:
                raise ConfigError(f"{self.source}: [material]: {err}") \
                    from None
        return self._registry

    def value(self, title, path, spec, value, choices=None):
        """Check one value; return it converted (float for numbers)."""
        where = f"{self.source}: [{title}] {spec.key} = {_show(value)}"
        if tuple(path) in self.from_cli:
            where += " (from the command line)"
        unit = f" {spec.unit}" if spec.unit else ""

        def fail(what):
            raise ConfigError(f"{where}: must be {what}")

        if spec.type == "bool":
            if not isinstance(value, bool):
                fail("true or false")
            return value
        if spec.type == "str":
            names = choices if choices is not None else spec.choices
            if not isinstance(value, str) or (names is not None
                                              and value not in names):
                fail(spec.allowed(names))
            return value
        if spec.type == "float_pair":
            if not isinstance(value, list) or len(value) != 2 or not all(
                    _is_number(v, "float") for v in value):
                fail(f"a pair of numbers [x, y]{unit}")
            return [float(v) for v in value]
        if spec.type == "float_vector":
            if not isinstance(value, list) or len(value) not in (2, 3) or not all(
                    _is_number(v, "float") for v in value):
                fail(f"a vector of 2 or 3 numbers [x, y] or [x, y, z]{unit}")
            return [float(v) for v in value]
        if spec.type == "float_list":  # each number within the range
            if not isinstance(value, list) or not all(
                    _is_number(v, "float") and spec.in_range(v)
                    for v in value):
                fail(f"a list of numbers {spec.allowed()}{unit}")
            return [float(v) for v in value]
        noun = "a number" if spec.type == "float" else "an integer"
        if not _is_number(value, spec.type):
            fail(f"{noun} {spec.allowed()}{unit}")
        if not spec.in_range(value):
            fail(f"{spec.allowed()}{unit}")
        return float(value) if spec.type == "float" else int(value)

    def keys(self, title, table, allowed) -> None:
        """Refuse a key not in ``allowed``, listing those that are."""
        if not isinstance(table, dict):
            raise ConfigError(f"{self.source}: [{title}] must be a table")
        for key in table:
            if key not in allowed:
                # An override's mistake is the command line's, not the file's.
                cli = f"{title}.{key}" in {".".join(map(str, p))
                                           for p in self.from_cli}
                blame = f"--set {title}.{key}" if cli else self.source
                raise ConfigError(f"{blame}: unknown key [{title}] {key}"
                                  f" (allowed: {', '.join(allowed)})")

    def table(self, section, table, title, path=None, skip=()) -> dict:
        """A plain section: every key checked or defaulted (derived: None)."""
        path = list(path or [section.name])
        self.keys(title, table, [*section.parameters, *skip])
        out = {}
        for key, spec in section.parameters.items():
            if key in table:
                choices = (sorted(self.registry())
                           if spec.choices == MATERIAL_CHOICES else None)
                out[key] = self.value(title, path + [key], spec, table[key],
                                      choices)
            else:
                out[key] = None if spec.derived else copy.deepcopy(
                    spec.default)
        return out

    def material(self, section, table, title="material") -> dict:
        """[material] (or [materials.NAME]: ``title``) and its parameters
        sub-table for the chosen law."""
        path = title.split(".")
        out = self.table(section, table, title, path, skip=(LAW_TABLE,))
        law = self.registry().get(out["law"])
        if law is None:  # the default law is not registered
            raise ConfigError(f"{self.source}: [{title}] law ="
                              f" {_show(out['law'])}: not registered (laws:"
                              f" {', '.join(sorted(self.registry()))})")
        given = table.get(LAW_TABLE, {})
        title = f"{title}.{LAW_TABLE}"
        self.keys(title, given, law.parameters)
        checked = {key: self.value(title, path + [LAW_TABLE, key],
                                   law.parameters[key], value)
                   for key, value in given.items()}
        try:
            out[LAW_TABLE] = resolve(law, checked)
        except RegistryError as err:
            raise ConfigError(f"{self.source}: [{title}]: {err}") from None
        return out

    def materials(self, section, tables) -> dict:
        """[materials.NAME]: each a material like [material]."""
        if not isinstance(tables, dict) or not all(
                isinstance(t, dict) for t in tables.values()):
            raise ConfigError(f"{self.source}: [{section.name}] must be a"
                              f" table of [{section.name}.NAME] tables")
        return {name: self.material(section, table, f"{section.name}.{name}")
                for name, table in tables.items()}

    def species(self, section, items) -> list:
        """[[species]]: each table checked; the schema's list when absent."""
        if items is None:
            items = copy.deepcopy(list(section.default_list))
        if not isinstance(items, list) or not items or not all(
                isinstance(i, dict) for i in items):
            raise ConfigError(f"{self.source}: [[{section.name}]] must be one"
                              " or more tables")
        out = []
        for i, item in enumerate(items):
            entry = self.table(section, item, f"{section.name}.{i}",
                               [section.name, i])
            if not entry["name"]:
                entry["name"] = f"{section.name}{i}"
            out.append(entry)
        names = [e["name"] for e in out]
        if len(set(names)) != len(names):
            raise ConfigError(f"{self.source}: [[{section.name}]] names"
                              f" {_show(names)}: must differ")
        return out

    def walls(self, section, tables, box) -> dict:
        """[walls.NAME]: every wall, box walls first, normals of length 1."""
        if not isinstance(tables, dict):
            raise ConfigError(f"{self.source}: [{section.name}] must be a"
                              " table of [walls.NAME] tables")
        geometry = box_geometry(box["length"], box["width"]) \
            if box["enabled"] else {}
        names = [*geometry, *(n for n in tables if n not in geometry)]
        out = {}
        for name in names:
            table = tables.get(name, {})
            title = f"{section.name}.{name}"
            values = self.table(section, table, title, [section.name, name])
            if name in geometry:
                for key in ("point", "normal"):
                    if key in table:
                        raise ConfigError(
                            f"{self.source}: [{title}] {key}: the box's walls"
                            " take their point and normal from [box]; set"
                            " only velocity (or [box] enabled = false)")
                values["point"], values["normal"] = map(list, geometry[name])
            else:
                for key in ("point", "normal"):
                    if key not in table:
                        raise ConfigError(
                            f"{self.source}: [{title}] {key} missing: a wall"
                            " not of the box needs point and normal")
                try:
                    values["normal"] = list(unit(values["normal"]))
                except ValueError:
                    raise ConfigError(f"{self.source}: [{title}] normal ="
                                      f" {_show(table['normal'])}: must not"
                                      " be zero") from None
            out[name] = values
        return out


def initial_packing_fraction(config) -> float:
    """Packing fraction of the rigid particles in the initial box."""
    return consistency.initial_packing_fraction(config)


def to_toml(config) -> str:
    """A complete TOML text of a configuration (every key, derived too).

    Box walls are written with their velocity only (their point and normal
    follow from [box]), so that the text reloads to the same Config.
    """
    schema = load_schema()
    lines = [f"# resolved from {config.source}"]

    def entries(section, values, params):
        for key, spec in params.items():
            unit = f" ({spec.unit})" if spec.unit else ""
            lines.append(f"{key} = {_show(values[key])}  # {spec.doc}{unit}")

    for name, section in schema.items():
        if name == "stages":
            lines += _stage_lines(config[name], config["cell"]["enabled"])
        elif section.is_list:
            for item in config[name]:
                lines += ["", f"[[{name}]]"]
                entries(name, item, section.parameters)
        elif section.is_map:
            boxed = config["box"]["enabled"]
            for wall, values in config[name].items():
                lines += ["", f"[{name}.{wall}]"]
                keep = {k: p for k, p in section.parameters.items()
                        if not (boxed and wall in BOX_WALLS
                                and k in ("point", "normal"))}
                entries(name, values, keep)
                if name == "materials":
                    lines += _law_lines(f"{name}.{wall}", values)
        else:
            lines += ["", f"[{name}]"]
            entries(name, config[name], section.parameters)
            if name == "material":
                lines += _law_lines(name, config[name])
    return "\n".join(lines) + "\n"


def _stage_lines(program, cell=False) -> list:
    """The ``[[stages]]`` tables of a resolved configuration (reloadable:
    each wall entry has only its drive's keys; with a cell, every stage's
    cell drive)."""
    lines = []
    for stage in program:
        lines += ["", "[[stages]]", f"name = {_show(stage['name'])}"]
        for wall, d in stage["walls"].items():
            control = d[CONTROL]
            lines.append(f"walls.{wall} = {{ {CONTROL} = {_show(control)},"
                         f" {control} = {_show(d[control])} }}")
        for table in ("contact", "cell", "stop"):
            if table == "cell" and not cell:
                continue
            keys = ", ".join(f"{k} = {_show(v)}"
                             for k, v in stage[table].items())
            lines.append(f"{table} = {{ {keys} }}")
    return lines


def _law_lines(title, material) -> list:
    """The TOML lines of a material's [TITLE.parameters] sub-table."""
    lines = ["", f"[{title}.{LAW_TABLE}]"]
    law = _law_or_none(material["law"])
    for key, value in material[LAW_TABLE].items():
        spec = law.parameters.get(key) if law else None
        doc = (f"  # {spec.doc}" + (f" ({spec.unit})" if spec.unit else "")
               if spec else "")
        lines.append(f"{key} = {_show(value)}{doc}")
    return lines


def _law_or_none(name):
    """The registered law (for its parameters' docs), None if unavailable."""
    try:
        return load_registry().get(name)
    except RegistryError:
        return None
