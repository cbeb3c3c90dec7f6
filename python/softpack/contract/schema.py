"""The parameter schema: ``schema/parameters.toml`` read into objects.

The schema file is the one definition of every parameter (type, range or
choices, default, unit, meaning, derivation rule, stage); its header
explains the layout. :func:`load_schema` reads it into :class:`Section`
and :class:`Parameter` objects that :mod:`softpack.scene.config` validates
with, and :func:`markdown` renders it as ``docs/parameters.md``::

    /usr/bin/python3 -m softpack.contract.schema --markdown > docs/parameters.md

Nothing here knows a parameter by name: ranges, defaults and names all come
from the file.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from softpack import paths

#: The values of ``type`` a parameter may have.
TYPES = ("float", "int", "bool", "str", "float_pair", "float_list",
         "float_vector")
#: The ``choices`` value that stands for the registered material laws.
MATERIAL_CHOICES = "@materials"


class SchemaError(ValueError):
    """The schema file itself is malformed (a bug of the project)."""


@dataclass(frozen=True)
class Parameter:
    """One key of a section: its type and what values it allows.

    Attributes
    ----------
    section, key : str
        The parameter's name ``section.key``.
    type : str
        One of :data:`TYPES`.
    default : object
        The value when absent (for a derived key: the rule's value in the
        paper's case; the rule itself is applied by the config stage).
    unit, doc : str
        SI unit (``""`` when dimensionless) and meaning.
    range : str or None
        An interval such as ``"(0, inf)"`` for numbers.
    choices : tuple of str or str or None
        The allowed strings, or :data:`MATERIAL_CHOICES`.
    derived : str or None
        The rule, in words, that gives the value when the user does not.
    """

    section: str
    key: str
    type: str
    default: object
    unit: str = ""
    doc: str = ""
    range: str | None = None
    choices: tuple | str | None = None
    derived: str | None = None
    bounds: tuple = field(default=(None, None, False, False), repr=False)

    def allowed(self, choices=None) -> str:
        """The allowed values in words, e.g. ``"> 0"``, ``"in [0.5, 1]"``."""
        if self.type == "bool":
            return "true or false"
        if self.type == "str":
            names = choices if choices is not None else self.choices
            if names is None:
                return "a string"
            return "one of " + ", ".join(f'"{c}"' for c in names)
        low, high, low_open, high_open = self.bounds
        if low is not None and high is not None:
            return (f"in {'(' if low_open else '['}{low:g}, {high:g}"
                    f"{')' if high_open else ']'}")
        if low is not None:
            return f"{'>' if low_open else '>='} {low:g}"
        if high is not None:
            return f"{'<' if high_open else '<='} {high:g}"
        return "any value"

    def in_range(self, value) -> bool:
        """Whether a number lies within the bounds."""
        low, high, low_open, high_open = self.bounds
        if low is not None and (value < low or (low_open and value == low)):
            return False
        return high is None or not (value > high
                                    or (high_open and value == high))


@dataclass(frozen=True)
class Section:
    """One table of the schema.

    Attributes
    ----------
    name, stage, doc : str
        The section's name, the stage that reads it, what it is.
    parameters : dict
        ``key -> Parameter`` in file order.
    is_list : bool
        An array of tables (``[[species]]``); ``default_list`` is its
        default content.
    is_map : bool
        A table of named tables (``[walls.NAME]``).
    """

    name: str
    stage: str
    doc: str
    parameters: dict
    is_list: bool = False
    is_map: bool = False
    default_list: tuple = ()


def parse_range(text: str, where: str = "") -> tuple:
    """``"(0, inf)"`` -> ``(0.0, None, True, False)``.

    Returns ``(low, high, low_open, high_open)``; an infinite end is None.
    """
    text = text.strip()
    if len(text) < 5 or text[0] not in "[(" or text[-1] not in "])" \
            or text.count(",") != 1:
        raise SchemaError(f"{where}: range {text!r} is not an interval")
    low_text, high_text = (s.strip() for s in text[1:-1].split(","))
    try:
        low, high = float(low_text), float(high_text)
    except ValueError:
        raise SchemaError(f"{where}: range {text!r} is not an interval") \
            from None
    return (None if math.isinf(low) else low,
            None if math.isinf(high) else high,
            text[0] == "(", text[-1] == ")")


def make_parameter(section: str, key: str, spec: dict) -> Parameter:
    """A :class:`Parameter` from its schema (or registry) table."""
    where = f"[{section}] {key}"
    kind = spec.get("type", "float")
    if kind not in TYPES:
        raise SchemaError(f"{where}: unknown type {kind!r}")
    rng = spec.get("range")
    bounds = parse_range(rng, where) if rng else (None, None, False, False)
    choices = spec.get("choices")
    if isinstance(choices, list):
        choices = tuple(choices)
    return Parameter(section=section, key=key, type=kind,
                     default=spec.get("default"), unit=spec.get("unit", ""),
                     doc=spec.get("doc", ""), range=rng, choices=choices,
                     derived=spec.get("derived"), bounds=bounds)


def read_document(path: Path | None = None) -> dict:
    """The schema file's tables as TOML gives them (metadata keys such as
    ``_stage`` and ``_drive`` included), its version checked: what the
    build-time generators of the driver's readers take
    (driver/io/generate_parameters.py)."""
    path = Path(path or paths.SCHEMA)
    with open(path, "rb") as f:
        data = tomllib.load(f)
    if data.get("schema_version") != 2:
        raise SchemaError(f"{path}: schema_version {data.get('schema_version')}"
                          " (this code reads 2)")
    return data


@functools.lru_cache(maxsize=4)
def load_schema(path: Path | None = None) -> dict:
    """Read the schema: ``section name -> Section``, in file order.

    Parameters
    ----------
    path : Path, optional
        The schema file (default :data:`softpack.paths.SCHEMA`).
    """
    data = read_document(path)
    sections = {}
    for name, table in data.items():
        if not isinstance(table, dict):
            continue
        parameters = {key: make_parameter(name, key, spec)
                      for key, spec in table.items()
                      if not key.startswith("_")}
        sections[name] = Section(
            name=name, stage=table.get("_stage", ""),
            doc=table.get("_doc", ""), parameters=parameters,
            is_list=bool(table.get("_list", False)),
            is_map=bool(table.get("_map", False)),
            default_list=tuple(table.get("_default", ())))
    return sections


def schema_version(path: Path | None = None) -> int:
    """The schema's version number (driver.json's ``schema_version``)."""
    with open(Path(path or paths.SCHEMA), "rb") as f:
        return int(tomllib.load(f)["schema_version"])


def _cell(value) -> str:
    """A value for a markdown table cell."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_cell(v) for v in value) + "]"
    if isinstance(value, str):
        return value.replace("|", "\\|")
    return repr(value)


def markdown(sections: dict | None = None) -> str:
    """``docs/parameters.md``: every section and key of the schema."""
    sections = sections or load_schema()
    lines = ["# Parameters", "",
             "Generated from `schema/parameters.toml` by `/usr/bin/python3 -m"
             " softpack.contract.schema --markdown`; do not edit (a test checks"
             " that it is current). Units: SI; the 2D model's forces and"
             " energies are per unit length along the cylinders' axis.", ""]
    for section in sections.values():
        title = f"[[{section.name}]]" if section.is_list else (
            f"[{section.name}.NAME]" if section.is_map else
            f"[{section.name}]")
        lines += [f"## `{title}` ({section.stage})", "", section.doc, ""]
        if section.is_list and section.default_list:
            lines += ["Default: " + "; ".join(
                ", ".join(f"{k} = {_cell(v)}" for k, v in item.items())
                for item in section.default_list) + ".", ""]
        lines += ["| key | type | default | allowed | unit | meaning |",
                  "|---|---|---|---|---|---|"]
        for p in section.parameters.values():
            allowed = p.range or ""
            if p.choices == MATERIAL_CHOICES:
                allowed = "a law of forms/materials/"
            elif p.choices:
                allowed = ", ".join(p.choices)
            doc = p.doc + (f" (derived: {p.derived})" if p.derived else "")
            lines.append(f"| `{p.key}` | {p.type} | {_cell(p.default)} |"
                         f" {_cell(allowed)} | {_cell(p.unit)} |"
                         f" {_cell(doc)} |")
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    """``python -m softpack.contract.schema --markdown``: print the doc page."""
    parser = argparse.ArgumentParser(
        prog="python -m softpack.contract.schema",
        description="Print the parameter schema as markdown.")
    parser.add_argument("--markdown", action="store_true", required=True,
                        help="print docs/parameters.md")
    parser.parse_args(argv)
    sys.stdout.write(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
