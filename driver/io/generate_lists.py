"""Generate the readers of the driver's list and map sections from the schema.

Called by generate_parameters.py, which writes ``list_sections.{h,cpp}``
next to ``parameters.{h,cpp}`` (``#include <softpack/list_sections.h>``,
library softpack_list_sections). driver.json holds each ``_list`` and ``_map``
section of the driver stage as a list of tables (a map's entries carry their
``name``); each becomes

- an element type: the driver's own :data:`DRIVER_TYPES` where the
  dynamics has one (a wall is ``dynamics::Wall``, its drive
  ``dynamics::WallDrive``), else a generated struct (``Stage``,
  ``FrictionPair``, ``MaterialsEntry``) whose dotted keys (``stop.strain``)
  form a nested struct (``StageStop``);
- ``read(json, Element&, where, path)``: every key required, unknown keys
  refused, types, ranges and choices checked (a ``str`` key with choices
  read into an enum of the same names when :data:`ENUMS` says so);
- ``read(json, std::vector<Element>&, where)``: the section's list.

Schema metadata read here (besides the keys): ``_drive`` of [walls], the key
that says what drives a wall; it and its choices are the keys of a drive.
``_drives`` of [stages], the key of each stage that holds a table of the
walls' new drives (``walls.NAME = {...}``).

Cross-entry rules (a name used twice, names of species and walls) and
cross-key ones (one drive per wall) are the hand-written reader's
(driver_config.cpp, material_config.cpp): a rule is written once there.
"""

from __future__ import annotations

# generate_parameters.py is the script run by CMake; it imports this module.
import generate_parameters as gp

#: The header of the driver's wall types (DRIVER_TYPES, DRIVE_TYPE, ENUMS).
WALLS_HEADER = "walls/walls.h"
#: Sections read into a type of the driver rather than a generated struct
#: (its members have the schema's key names): section -> C++ type.
DRIVER_TYPES = {"walls": "dynamics::Wall"}
#: The type of a wall's drive (a base of dynamics::Wall).
DRIVE_TYPE = "dynamics::WallDrive"
#: ``str`` keys read into an enum whose enumerators are the key's choices.
ENUMS = {("walls", "control"): "dynamics::WallControl"}
#: Names of the generated element structs (default: CamelCase + "Entry").
STRUCT_NAMES = {"stages": "Stage", "friction": "FrictionPair"}
#: Sections whose entries carry the law's parameters, like [material].
WITH_LAW_PARAMETERS = ("materials",)


def list_sections(schema: dict) -> list[tuple[str, dict]]:
    """Return the (name, table) of each driver section of lists or maps."""
    return [(name, table) for name, table in schema.items()
            if isinstance(table, dict) and table.get("_stage") == "driver"
            and (table.get("_list") or table.get("_map"))]


def element_type(name: str) -> str:
    """The C++ type of one element of section ``name``."""
    return DRIVER_TYPES.get(name) or STRUCT_NAMES.get(
        name, gp.camel_case(name) + "Entry")


def plain_keys(table: dict) -> list[tuple[str, dict]]:
    """The undotted keys of a section, in the schema's order."""
    return [(k, s) for k, s in gp.keys_of(table) if "." not in k]


def nested_keys(table: dict) -> dict[str, list[tuple[str, dict]]]:
    """``prefix -> [(key without prefix, spec)]`` of the dotted keys."""
    out: dict[str, list] = {}
    for key, spec in gp.keys_of(table):
        if "." in key:
            prefix, rest = key.split(".", 1)
            out.setdefault(prefix, []).append((rest, spec))
    return out


def drive_keys(schema: dict) -> list[str]:
    """The keys of a wall's drive: [walls] ``_drive`` and its choices."""
    walls = schema["walls"]
    control = walls["_drive"]
    return [control, *walls[control]["choices"]]


def enum_of(section: str, key: str) -> str | None:
    """The C++ enum a ``str`` key is read into, or None."""
    return ENUMS.get((section, key))


def read_key(section: str, key: str, spec: dict, path: str) -> str:
    """The statement reading ``key`` of an entry (``path``: C++ expression)."""
    enum = enum_of(section, key)
    statement = gp.read_statement(section, key, spec, path)
    if enum is None:
        return statement
    value = statement.split(" = ", 1)[1].rstrip(";")
    return f"  out.{key} = {enum_function(enum)}({value});"


def enum_function(enum: str) -> str:
    """Name of the function turning a choice into ``enum`` (to_wall_control)."""
    name = enum.split("::")[-1]
    return "to" + "".join("_" + c.lower() if c.isupper() else c for c in name)


def declarations(name: str, table: dict) -> list[str]:
    """The structs and reader declarations of one list or map section."""
    cls = element_type(name)
    out = []
    extra = []
    if table.get("_map"):
        extra += ["  /// Its name (driver.json writes [NAME.KEY] tables as a list)",
                  f"  std::string {gp.ENTRY_NAME};"]
    for prefix, keys in nested_keys(table).items():
        sub = cls + gp.camel_case(prefix)
        out += gp.struct_lines(sub, f"The {prefix}.KEY keys of [{name}]",
                                  keys)
        extra += [f"  /// The {prefix}.KEY keys", f"  {sub} {prefix};"]
    if table.get("_drives"):
        extra += [f"  /// {table['_drives']}.NAME: the named walls' new drives",
                  f"  std::map<std::string, {DRIVE_TYPE}> {table['_drives']};"]
    if name in WITH_LAW_PARAMETERS:
        extra += ["  /// The law's own parameters (checked by the body set)",
                  f"  std::map<std::string, double> {gp.MATERIAL_PARAMETERS};"]
    if name not in DRIVER_TYPES:
        out += gp.struct_lines(cls, f"One element of [{name}]: "
                                  + table.get("_doc", name), plain_keys(table),
                                  extra)
    out += [f"/// Read one element of driver.json's `{name}` at `path` (e.g.",
            f"/// \"{name}[0]\"): every key required and checked, unknown keys",
            "/// refused.",
            "/// @throws std::runtime_error naming `where` and the key path",
            f"void read(const nlohmann::json& j, {cls}& out, const std::string& where,",
            "          const std::string& path);",
            f"/// Read driver.json's list `{name}` (empty: none).",
            f"void read(const nlohmann::json& j, std::vector<{cls}>& out,",
            "          const std::string& where);\n"]
    return out


def header(schema: dict) -> str:
    """Return the text of list_sections.h."""
    out = ["// Generated by driver/io/generate_lists.py from schema/parameters.toml.",
           "// Do not edit: change the schema.",
           "#pragma once", "",
           f"#include <{WALLS_HEADER}>",
           "#include <map>",
           "#include <nlohmann/json.hpp>",
           "#include <softpack/parameters.h>",
           "#include <string>",
           "#include <vector>", "",
           "/// Readers of driver.json's list and map sections (walls, stages,",
           "/// friction, materials), generated from the schema.",
           "namespace softpack::parameters", "{", "",
           f"/// A wall's drive: the keys {', '.join(drive_keys(schema))} of [walls]",
           f"void read(const nlohmann::json& j, {DRIVE_TYPE}& out,",
           "          const std::string& where, const std::string& path);",
           f"/// The keys of [walls] of a {DRIVE_TYPE}",
           f"nlohmann::json to_json(const {DRIVE_TYPE}& drive);",
           "/// The schema's keys of a wall (without its name)",
           "nlohmann::json to_json(const dynamics::Wall& wall);"]
    for (section, key), enum in ENUMS.items():
        out += [f"/// The schema's choice of [{section}] {key} for `value`",
                f"std::string name_of({enum} value);"]
    out.append("")
    for name, table in list_sections(schema):
        out += declarations(name, table)
    out.append("} // namespace softpack::parameters")
    return "\n".join(out) + "\n"


def enum_functions(schema: dict) -> list[str]:
    """Each enum of :data:`ENUMS` from its choice (private)."""
    out = []
    for (section, key), enum in ENUMS.items():
        choices = schema[section][key]["choices"]
        out.append(f"{enum} {enum_function(enum)}(const std::string& s)\n{{")
        for c in choices:
            out.append(f"  if (s == {gp.cpp_string(c)})")
            out.append(f"    return {enum}::{c};")
        out.append(f"  throw std::logic_error(\"not a {key}: \" + s);\n}}\n")
    return out


def enum_names(schema: dict) -> list[str]:
    """The choice of each enum value of :data:`ENUMS` (declared public)."""
    out = []
    for (section, key), enum in ENUMS.items():
        choices = schema[section][key]["choices"]
        out.append(f"std::string name_of({enum} value)\n{{")
        out.append("  switch (value)\n  {")
        for c in choices:
            out.append(f"  case {enum}::{c}:\n    return {gp.cpp_string(c)};")
        out.append("  }")
        out.append(f"  throw std::logic_error(\"not a {key}\");\n}}\n")
    return out


def reader(name: str, cls: str, keys, table: dict, nested=False) -> list[str]:
    """The reader of one element (or of a nested struct) of a section."""
    names = [k for k, _ in keys]
    if not nested:
        if table.get("_map"):
            names.insert(0, gp.ENTRY_NAME)
        if table.get("_drives"):
            names.append(table["_drives"])
        names += list(nested_keys(table))
        if name in WITH_LAW_PARAMETERS:
            names.append(gp.MATERIAL_PARAMETERS)
    out = [f"void read(const nlohmann::json& j, {cls}& out, const std::string& where,",
           "          const std::string& path)\n{",
           "  check_keys(j, where, path, "
           "{" + ", ".join(gp.cpp_string(k) for k in names) + "});"]
    if not nested and table.get("_map"):
        out.append(f"  out.{gp.ENTRY_NAME} = read_name(j.at({gp.cpp_string(gp.ENTRY_NAME)}), "
                   f"where, path + {gp.cpp_string('.' + gp.ENTRY_NAME)});")
    for key, spec in keys:
        if key == gp.ENTRY_NAME:  # names what other keys refer to
            out.append(f"  out.{key} = read_name(j.at({gp.cpp_string(key)}), "
                       f"where, path + {gp.cpp_string('.' + key)});")
        else:
            out.append(read_key(name, key, spec,
                                f"path + {gp.cpp_string('.' + key)}"))
    if not nested:
        if table.get("_drives"):
            key = table["_drives"]
            out.append(f"  read_drives(j.at({gp.cpp_string(key)}), out.{key}, where, "
                       f"path + {gp.cpp_string('.' + key)});")
        for prefix in nested_keys(table):
            out.append(f"  read(j.at({gp.cpp_string(prefix)}), out.{prefix}, where, "
                       f"path + {gp.cpp_string('.' + prefix)});")
        if name in WITH_LAW_PARAMETERS:
            key = gp.MATERIAL_PARAMETERS
            out.append(f"  out.{key} = read_number_table(j.at({gp.cpp_string(key)}), "
                       f"where, path + {gp.cpp_string('.' + key)});")
    out.append("}\n")
    return out


def list_reader(name: str, cls: str) -> list[str]:
    """The reader of a section's list."""
    return [f"void read(const nlohmann::json& j, std::vector<{cls}>& out,",
            "          const std::string& where)\n{",
            "  if (!j.is_array())",
            f"    fail(where, {gp.cpp_string(name)}, \"must be a list (empty: none)\");",
            "  out.resize(j.size());",
            "  for (std::size_t i = 0; i < j.size(); ++i)",
            f"    read(j[i], out[i], where, {gp.cpp_string(name)} + (\"[\" + "
            "std::to_string(i) + \"]\"));",
            "}\n"]


def to_json(cls: str, keys, section: str) -> list[str]:
    """``to_json`` of a type whose members are the schema's ``keys``."""
    out = [f"nlohmann::json to_json(const {cls}& entry)\n{{",
           "  nlohmann::json j = nlohmann::json::object();"]
    for key in keys:
        value = f"entry.{key}"
        if enum_of(section, key):
            value = f"name_of({value})"
        out.append(f"  j[{gp.cpp_string(key)}] = {value};")
    out.append("  return j;\n}\n")
    return out


def source(schema: dict) -> str:
    """Return the text of list_sections.cpp."""
    walls = schema["walls"]
    drive = drive_keys(schema)
    out = ["// Generated by driver/io/generate_lists.py from schema/parameters.toml.",
           "// Do not edit: change the schema.",
           "#include <softpack/list_sections.h>", "",
           "#include <io/parameter_checks.h>",
           "#include <stdexcept>", "",
           "namespace softpack::parameters", "{",
           "using namespace detail;", "",
           "namespace", "{"]
    out += enum_functions(schema)
    out += ["/// A table walls.NAME of drives.",
            f"void read_drives(const nlohmann::json& j, std::map<std::string, {DRIVE_TYPE}>& out,",
            "                 const std::string& where, const std::string& path)\n{",
            "  if (!j.is_object())",
            "    fail(where, path, \"must be a table of walls by name\");",
            "  for (const auto& [name, drive] : j.items())",
            "    read(drive, out[name], where, path + \".\" + name);",
            "}",
            "} // namespace", ""]
    drive_specs = [(k, walls[k]) for k in drive]
    out += enum_names(schema)
    out += reader("walls", DRIVE_TYPE, drive_specs, walls, nested=True)
    out += to_json(DRIVE_TYPE, drive, "walls")
    out += to_json("dynamics::Wall", [k for k, _ in plain_keys(walls)], "walls")
    for name, table in list_sections(schema):
        cls = element_type(name)
        for prefix, keys in nested_keys(table).items():
            out += reader(name, cls + gp.camel_case(prefix), keys, table,
                          nested=True)
        out += reader(name, cls, plain_keys(table), table)
        out += list_reader(name, cls)
    out.append("} // namespace softpack::parameters")
    return "\n".join(out) + "\n"
