"""Generate the driver's parameter structs and their reader from the schema.

Run by CMake at build time (``/usr/bin/python3``; the schema is read by
the Python package's one reader, ``softpack.contract.schema``)::

    generate_parameters.py SCHEMA OUT_DIR

reads ``SCHEMA`` (schema/parameters.toml) and writes ``OUT_DIR/parameters.h``
and ``OUT_DIR/parameters.cpp`` (``#include <softpack/parameters.h>``). Every
section with ``_stage = "driver"`` that is neither a ``_list`` nor a ``_map``
becomes a struct of ``softpack::parameters`` named after the section in
CamelCase, one member per key with the schema's name, type and default, and
two functions:

- ``read(json, Section&, where)`` requires every key, refuses unknown keys and
  checks type, range and choices (except ``"@materials"``, checked by the
  body set against the forms registry), throwing ``std::runtime_error`` that
  names ``where`` (the file), the key path (``contact.friction``) and what is
  allowed;
- ``to_json(const Section&)``.

The material section also carries ``std::map<std::string, double>
parameters`` (the law's own constants, declared in forms/materials/LAW.py).
The checks themselves (no schema content) are written by hand:
driver/io/parameter_checks.{h,cpp}.

The ``_list`` and ``_map`` sections (walls, stages, friction, materials) are
read by ``OUT_DIR/list_sections.{h,cpp}``, written by generate_lists.py.

Nothing here repeats a name, range or default of the schema: they are all
read from it, so the schema stays the one place where they are defined.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

# The package's schema reader (python/softpack, beside driver/): one reader
# of schema/parameters.toml and of its ranges.
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
from softpack.contract import schema as schema_reader  # noqa: E402

CPP_TYPES = {
    "float": "double",
    "int": "int",
    "bool": "bool",
    "str": "std::string",
    "float_pair": "std::array<double, 2>",
    "float_vector": "std::vector<double>",
}

# The member of Material that is not a schema key: the law's parameters.
MATERIAL_PARAMETERS = "parameters"


def camel_case(name: str) -> str:
    """Return ``name`` in CamelCase (``time_step`` -> ``TimeStep``)."""
    return "".join(part.capitalize() for part in name.split("_"))


def cpp_string(text: str) -> str:
    """Return a C++ string literal for ``text`` (JSON escapes are valid C++)."""
    return json.dumps(text, ensure_ascii=True)


def cpp_double(x: float) -> str:
    """Return a C++ double literal that round-trips ``x``."""
    x = float(x)
    if math.isinf(x):
        return ("-" if x < 0 else "") + "std::numeric_limits<double>::infinity()"
    text = repr(x)
    return text if any(c in text for c in ".en") else text + ".0"


def cpp_value(kind: str, value) -> str:
    """Return the C++ initialiser of a default ``value`` of schema type ``kind``."""
    if kind == "float":
        return cpp_double(value)
    if kind == "int":
        return str(int(value))
    if kind == "bool":
        return "true" if value else "false"
    if kind == "str":
        return cpp_string(value)
    if kind in ("float_pair", "float_vector"):
        return "{" + ", ".join(cpp_double(v) for v in value) + "}"
    raise ValueError(f"unknown type {kind!r}")


def parse_range(text: str, where: str) -> tuple[float, bool, float, bool]:
    """An interval ``"(0, inf)"`` as (low, low_closed, high, high_closed),
    the ends infinite where open-ended (the schema reader's parse)."""
    low, high, low_open, high_open = schema_reader.parse_range(text, where)
    return (-math.inf if low is None else low, not low_open,
            math.inf if high is None else high, not high_open)


def driver_sections(schema: dict) -> list[tuple[str, dict]]:
    """Return the (name, table) of each driver section read into a struct."""
    return [
        (name, table)
        for name, table in schema.items()
        if isinstance(table, dict)
        and table.get("_stage") == "driver"
        and not table.get("_list")
        and not table.get("_map")
    ]


# driver.json writes a map section ([walls.NAME]) as a list of tables, each
# with the key "name" next to the schema's keys.
ENTRY_NAME = "name"


def keys_of(table: dict) -> list[tuple[str, dict]]:
    """Return the (key, spec) pairs of a section, metadata excluded."""
    return [(k, v) for k, v in table.items() if not k.startswith("_")]


def comment(text: str, indent: str) -> str:
    """Return ``text`` as ``///`` comment lines of at most ~80 columns."""
    lines, line = [], ""
    for word in text.split():
        if line and len(indent) + 4 + len(line) + 1 + len(word) > 80:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    lines.append(line)
    return "".join(f"{indent}/// {l}\n" for l in lines)


def member_doc(spec: dict) -> str:
    """Return the doc comment of a key: meaning, unit, range or choices."""
    extra = []
    if spec.get("unit"):
        extra.append(f"unit {spec['unit']}")
    if "range" in spec:
        extra.append(f"range {spec['range']}")
    if "choices" in spec:
        choices = spec["choices"]
        extra.append("choices " + (choices if isinstance(choices, str) else ", ".join(choices)))
    return spec["doc"] + (f" ({'; '.join(extra)})" if extra else "")


def string_list(values) -> str:
    """Return a C++ braced list of string literals."""
    return "{" + ", ".join(cpp_string(v) for v in values) + "}"


def struct_lines(cls: str, doc: str, keys, extra=()) -> list[str]:
    """A struct with one member per (key, spec), the schema's default as
    initialiser, then the ``extra`` lines."""
    out = [comment(doc, "").rstrip("\n"), f"struct {cls}\n{{"]
    for key, spec in keys:
        out.append(comment(member_doc(spec), "  ").rstrip("\n"))
        out.append(f"  {CPP_TYPES[spec['type']]} {key} = "
                   f"{cpp_value(spec['type'], spec['default'])};")
    return out + list(extra) + ["};\n"]


def section_lists(schema: dict) -> list[str]:
    """Return the declarations naming the sections and map keys of the schema.

    driver.json's top level holds the driver sections and ``scene`` the
    scene sections: their readers refuse unknown keys with these lists.
    """
    tables = [(n, t) for n, t in schema.items() if isinstance(t, dict)]
    out = []
    for stage in ("scene", "driver"):
        names = [n for n, t in tables if t.get("_stage") == stage]
        out.append(f"/// The sections of stage \"{stage}\", in the schema's order")
        out.append(f"inline const std::vector<std::string> {stage}_sections = "
                   f"{string_list(names)};")
    for name, table in tables:
        if table.get("_stage") == "driver" and table.get("_map"):
            out.append(f"/// The keys of each named table of `{name}`")
            out.append(f"inline const std::vector<std::string> {name}_keys = "
                       f"{string_list(k for k, _ in keys_of(table))};")
    return out + [""]


def header(schema: dict, sections: list[tuple[str, dict]]) -> str:
    """Return the text of parameters.h."""
    out = [
        "// Generated by driver/io/generate_parameters.py from schema/parameters.toml.",
        "// Do not edit: change the schema.",
        "#pragma once",
        "",
        "#include <array>",
        "#include <limits>",
        "#include <map>",
        "#include <nlohmann/json.hpp>",
        "#include <string>",
        "#include <vector>",
        "",
        "/// The driver's parameters, one struct per driver section of the schema.",
        "namespace softpack::parameters",
        "{",
        "",
        f"/// Version of schema/parameters.toml these structs were generated from",
        f"inline constexpr int schema_version = {int(schema['schema_version'])};",
        "",
    ]
    out += section_lists(schema)
    for name, table in sections:
        extra = []
        if name == "material":
            extra = ["  /// The law's own parameters (keys: its UFL constants, checked by",
                     "  /// the body set against the forms registry)",
                     f"  std::map<std::string, double> {MATERIAL_PARAMETERS};"]
        out += struct_lines(camel_case(name), table.get("_doc", name),
                            keys_of(table), extra)
    out.append("/// Every driver section")
    out.append("struct Parameters\n{")
    for name, _ in sections:
        out.append(f"  {camel_case(name)} {name};")
    out.append("};\n")
    for name, _ in sections:
        cls = camel_case(name)
        out.append(f"/// Read section `{name}` from `j`: every key required, unknown keys")
        out.append("/// refused, types, ranges and choices checked.")
        out.append("/// @throws std::runtime_error naming `where`, the key path and what is")
        out.append("/// allowed")
        out.append(f"void read(const nlohmann::json& j, {cls}& out, const std::string& where);")
        out.append(f"/// Section `{name}` as JSON (the keys of the schema)")
        out.append(f"nlohmann::json to_json(const {cls}& section);\n")
    out.append("/// Read every section from the object `j` that holds them under their")
    out.append("/// names (other keys of `j` are not looked at).")
    out.append("void read(const nlohmann::json& j, Parameters& out, const std::string& where);")
    out.append("/// Every section under its name")
    out.append("nlohmann::json to_json(const Parameters& parameters);\n")
    out.append("} // namespace softpack::parameters")
    return "\n".join(out) + "\n"


def read_statement(section: str, key: str, spec: dict, path: str = "") -> str:
    """Return the C++ statement that reads ``key`` of ``section`` into ``out``.

    ``path`` is the C++ expression of the key path in messages (default: the
    literal ``section.key``).
    """
    path = path or cpp_string(f"{section}.{key}")
    value = f"j.at({cpp_string(key)})"
    kind = spec["type"]
    if kind in ("float", "int"):
        if "range" not in spec:
            raise SystemExit(f"schema: {section}.{key} is a number without a range")
        lo, lo_closed, hi, hi_closed = parse_range(spec["range"], f"schema: {section}.{key}")
        func = "read_number" if kind == "float" else "read_int"
        args = (f"{cpp_double(lo)}, {str(lo_closed).lower()}, {cpp_double(hi)}, "
                f"{str(hi_closed).lower()}, {cpp_string(spec['range'])}")
        return f"  out.{key} = {func}({value}, where, {path}, {args});"
    if kind == "bool":
        return f"  out.{key} = read_bool({value}, where, {path});"
    if kind == "str":
        choices = spec.get("choices", [])
        # "@materials" names the forms registry: the body set checks the law.
        listed = [] if isinstance(choices, str) else choices
        init = "{" + ", ".join(cpp_string(c) for c in listed) + "}"
        return f"  out.{key} = read_string({value}, where, {path}, {init});"
    if kind == "float_pair":
        return f"  out.{key} = read_pair({value}, where, {path});"
    if kind == "float_vector":
        return f"  out.{key} = read_vector({value}, where, {path});"
    raise SystemExit(f"schema: {section}.{key}: unknown type {kind!r}")


def source(schema: dict, sections: list[tuple[str, dict]]) -> str:
    """Return the text of parameters.cpp."""
    out = [
        "// Generated by driver/io/generate_parameters.py from schema/parameters.toml.",
        "// Do not edit: change the schema.",
        "#include <softpack/parameters.h>",
        "",
        "#include <io/parameter_checks.h>",
        "",
        "namespace softpack::parameters",
        "{",
        "using namespace detail;",
    ]
    for name, table in sections:
        cls = camel_case(name)
        keys = [k for k, _ in keys_of(table)]
        if name == "material":
            keys.append(MATERIAL_PARAMETERS)
        out.append(f"void read(const nlohmann::json& j, {cls}& out, const std::string& where)\n{{")
        out.append(f"  check_keys(j, where, {cpp_string(name)}, "
                   "{" + ", ".join(cpp_string(k) for k in keys) + "});")
        for key, spec in keys_of(table):
            out.append(read_statement(name, key, spec))
        if name == "material":
            out.append(f"  out.{MATERIAL_PARAMETERS} = read_number_table("
                       f"j.at({cpp_string(MATERIAL_PARAMETERS)}), where, "
                       f"{cpp_string(name + '.' + MATERIAL_PARAMETERS)});")
        out.append("}\n")
        out.append(f"nlohmann::json to_json(const {cls}& section)\n{{")
        out.append("  nlohmann::json j = nlohmann::json::object();")
        for key, _ in keys_of(table):
            out.append(f"  j[{cpp_string(key)}] = section.{key};")
        if name == "material":
            out.append(f"  j[{cpp_string(MATERIAL_PARAMETERS)}] = section.{MATERIAL_PARAMETERS};")
        out.append("  return j;\n}\n")
    out.append("void read(const nlohmann::json& j, Parameters& out, const std::string& where)\n{")
    for name, _ in sections:
        out.append(f"  if (!j.is_object() || !j.contains({cpp_string(name)}))")
        out.append(f"    fail(where, {cpp_string(name)}, \"missing section\");")
        out.append(f"  read(j.at({cpp_string(name)}), out.{name}, where);")
    out.append("}\n")
    out.append("nlohmann::json to_json(const Parameters& parameters)\n{")
    out.append("  nlohmann::json j = nlohmann::json::object();")
    for name, _ in sections:
        out.append(f"  j[{cpp_string(name)}] = to_json(parameters.{name});")
    out.append("  return j;\n}\n")
    out.append("} // namespace softpack::parameters")
    return "\n".join(out) + "\n"


def main(argv: list[str]) -> int:
    """Generate parameters.{h,cpp} from the schema; see the module docstring."""
    if len(argv) != 3:
        print("usage: generate_parameters.py SCHEMA OUT_DIR", file=sys.stderr)
        return 2
    schema = schema_reader.read_document(Path(argv[1]))
    sections = driver_sections(schema)
    out_dir = Path(argv[2])
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "parameters.h").write_text(header(schema, sections))
    (out_dir / "parameters.cpp").write_text(source(schema, sections))
    # The list and map sections, read into types of the driver (io level).
    import generate_lists
    (out_dir / "list_sections.h").write_text(generate_lists.header(schema))
    (out_dir / "list_sections.cpp").write_text(generate_lists.source(schema))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
