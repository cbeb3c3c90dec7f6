"""Write the materials registry from the material files (docs/contract.md 3).

Run by CMake at build time (``/usr/bin/python3``, with UFL)::

    registry.py [--cpp OUT_CPP] OUT_JSON MATERIAL_FILE...

Each material file is plain UFL Python: it is executed, its ``ufl.Constant``
variables are found by name, and its ``parameters`` dict must declare exactly
those names (but those it lists in ``driver_constants``, which the driver
sets), each with ``unit``, ``range``, ``default`` and ``doc``. Any
disagreement fails the build with a message naming the file. The registry
``OUT_JSON`` (``build/forms/materials.json``) lists every law with its doc
(the first line of the file's header comment, or its docstring) and its
parameters; a default that is an expression of the other parameters stays a
string. With ``--cpp``, the same defaults as C++ (``OUT_CPP``, the table of
``forms/material_defaults.h``), so that C++ code building a material without
driver.json takes them from the material file too.
"""

from __future__ import annotations

import ast
import json
import re
import runpy
import sys
from pathlib import Path

import ufl

SCHEMA_VERSION = 2
FIELDS = ("unit", "range", "default", "doc")
INTERVAL = re.compile(r"^\s*[\[(]\s*([^,]+?)\s*,\s*([^,]+?)\s*[\])]\s*$")
# Nodes allowed in a default expression: + - * / and parentheses of numbers
# and the law's other parameters.
ALLOWED_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Add, ast.Sub,
                 ast.Mult, ast.Div, ast.USub, ast.UAdd, ast.Constant,
                 ast.Name, ast.Load)


class MaterialError(Exception):
    """A material file that does not follow the contract."""


def constants_of(namespace: dict) -> list[str]:
    """Return the names of the ufl.Constant variables of a material file."""
    return sorted(name for name, value in namespace.items()
                  if isinstance(value, ufl.Constant) and not name.startswith("_"))


def check_bound(text: str, what: str) -> None:
    """Refuse an interval end that is not a number or +-inf."""
    try:
        float(text)
    except ValueError:
        raise MaterialError(f"{what}: {text!r} is not a number or inf") from None


def check_default(key: str, default, names: list[str]) -> None:
    """Refuse a default that is neither a number nor an expression of the others."""
    if isinstance(default, bool) or not isinstance(default, (int, float, str)):
        raise MaterialError(f"parameter {key!r}: default must be a number or an "
                            "expression string")
    if not isinstance(default, str):
        return
    try:
        tree = ast.parse(default, mode="eval")
    except SyntaxError:
        raise MaterialError(f"parameter {key!r}: default {default!r} is not an "
                            "arithmetic expression") from None
    for node in ast.walk(tree):
        if not isinstance(node, ALLOWED_NODES):
            raise MaterialError(f"parameter {key!r}: default {default!r} may only "
                                "use numbers, + - * / and parentheses and the "
                                "law's other parameters")
        if isinstance(node, ast.Name) and (node.id not in names or node.id == key):
            raise MaterialError(f"parameter {key!r}: default {default!r} uses "
                                f"{node.id!r}, not another parameter of the law "
                                f"({', '.join(names)})")


def check_parameters(declared, constants: list[str]) -> dict:
    """Return the checked ``parameters`` dict of a material (keys = constants)."""
    if not isinstance(declared, dict):
        raise MaterialError("no dict `parameters` declaring its UFL constants "
                            f"({', '.join(constants)})")
    if sorted(declared) != constants:
        missing = sorted(set(constants) - set(declared))
        extra = sorted(set(declared) - set(constants))
        raise MaterialError(
            "the keys of `parameters` differ from the UFL constants "
            f"({', '.join(constants)}): "
            + "; ".join(part for part in (
                f"undeclared constants: {', '.join(missing)}" if missing else "",
                f"keys that are no constant: {', '.join(extra)}" if extra else "")
                if part))
    out = {}
    for key in declared:  # the file's order
        spec = declared[key]
        if not isinstance(spec, dict) or sorted(spec) != sorted(FIELDS):
            raise MaterialError(f"parameter {key!r} must have exactly the fields "
                                f"{', '.join(FIELDS)}")
        match = INTERVAL.match(str(spec["range"]))
        if not match:
            raise MaterialError(f"parameter {key!r}: range {spec['range']!r} is not "
                                "an interval like '(0, inf)'")
        for bound in match.groups():
            check_bound(bound, f"parameter {key!r}: range {spec['range']!r}")
        check_default(key, spec["default"], constants)
        default = spec["default"]
        out[key] = {"unit": str(spec["unit"]), "range": spec["range"],
                    "default": default if isinstance(default, str) else float(default),
                    "doc": str(spec["doc"])}
    return out


def material_doc(path: Path, namespace: dict) -> str:
    """Return the law's one-line description (docstring or header comment)."""
    doc = namespace.get("__doc__")
    if doc:
        return doc.strip().splitlines()[0]
    for line in path.read_text().splitlines():
        if line.startswith("#") and line.lstrip("#").strip():
            return line.lstrip("#").strip()
    return path.stem


def check_dimensions(path: Path, namespace: dict) -> tuple:
    """Refuse a ``dimensions`` other than (2,) (the default: plane strain
    only) or (2, 3), and a file declaring (2, 3) whose forms are not on
    tetrahedra with the same constants when run with ``cell`` = tetrahedron
    (what forms/solid_wrapper.py.in compiles); the dimensions."""
    dimensions = tuple(namespace.get("dimensions", (2,)))
    if dimensions not in ((2,), (2, 3)):
        raise MaterialError(f"`dimensions` = {dimensions!r} must be (2,) or (2, 3)")
    if dimensions == (2,):
        return dimensions
    # forms/CMakeLists.txt finds the 3D laws by this exact line
    if not re.search(r"^dimensions = \(2, 3\)", path.read_text(), re.MULTILINE):
        raise MaterialError("write `dimensions = (2, 3)` on a line of its own")
    solid = runpy.run_path(str(path), init_globals={"cell": ufl.tetrahedron},
                           run_name=f"material_{path.stem}_tetrahedron")
    for name in ("energy", "residual", "tangent"):
        form = solid.get(name)
        cells = {d.ufl_cell() for d in form.ufl_domains()} if form else set()
        if cells != {ufl.tetrahedron}:
            raise MaterialError(
                f"declares dimensions = (2, 3), but its form `{name}` is not on "
                "tetrahedra when the file runs with cell = tetrahedron (take "
                'the cell from `cell = globals().get("cell", triangle)`)')
    if constants_of(solid) != constants_of(namespace):
        raise MaterialError("its constants differ between triangles and "
                            "tetrahedra")
    return dimensions


def read_material(path: Path) -> dict:
    """Return the registry entry of one material file (raises MaterialError)."""
    namespace = runpy.run_path(str(path), run_name=f"material_{path.stem}")
    dimensions = check_dimensions(path, namespace)
    # Constants the driver sets itself (a viscoelastic law's time step):
    # no parameter of the law.
    driver = namespace.get("driver_constants", [])
    constants = [c for c in constants_of(namespace) if c not in driver]
    entry = {"doc": material_doc(path, namespace),
             "parameters": check_parameters(namespace.get("parameters"), constants),
             "dimensions": list(dimensions)}
    nodal = namespace.get("nodal_volumetric")
    if nodal is not None and nodal not in entry["parameters"]:
        raise MaterialError(f"`nodal_volumetric` = {nodal!r} must name one of "
                            f"the parameters ({', '.join(entry['parameters'])})")
    initial = namespace.get("internal_initial")
    if initial is not None:
        if "internal_update" not in namespace or not all(
                isinstance(a, (int, float)) for a in initial):
            raise MaterialError("`internal_initial` must be a list of numbers "
                                "beside a form `internal_update`")
        entry["internal_initial"] = [float(a) for a in initial]
    return entry


def cpp_expression(default) -> tuple[str, list[str]]:
    """A checked default as a C++ expression of ``p`` (the parameter values)
    and the names it uses; every number a double (C++ 1/3 would be 0)."""
    if not isinstance(default, str):
        return repr(float(default)), []
    names = []

    def emit(node):
        if isinstance(node, ast.Expression):
            return emit(node.body)
        if isinstance(node, ast.Constant):
            return repr(float(node.value))
        if isinstance(node, ast.Name):
            names.append(node.id)
            return f'p.at("{node.id}")'
        if isinstance(node, ast.UnaryOp):
            return f"({'-' if isinstance(node.op, ast.USub) else '+'}" \
                f"{emit(node.operand)})"
        op = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
        return f"({emit(node.left)} {op[type(node.op)]} {emit(node.right)})"

    return emit(ast.parse(default, mode="eval")), sorted(set(names))


def cpp_table(materials: dict) -> str:
    """The C++ source of ``forms::parameter_defaults`` for the registry."""
    rows, cases, initial = [], [], []
    for law, entry in materials.items():
        rows.append(f"  static const ParameterDefault {law}[] = {{")
        for key, spec in entry["parameters"].items():
            code, uses = cpp_expression(spec["default"])
            listed = ", ".join(f'"{n}"' for n in uses)
            rows.append(f'      {{"{key}", {{{listed}}},'
                        f" []([[maybe_unused]] const ParameterValues& p)"
                        f" {{ return {code}; }}}},")
        rows.append("  };")
        cases.append(f'  if (law == "{law}")\n    return {law};')
        if "internal_initial" in entry:
            values = ", ".join(repr(a) for a in entry["internal_initial"])
            initial.append(f"  static const double {law}[] = {{{values}}};\n"
                           f'  if (law == "{law}")\n    return {law};')
    return ("// Generated by forms/registry.py from forms/materials/*.py.\n"
            '#include "material_defaults.h"\n#include "material_registry.h"\n\nnamespace softpack::forms\n'
            "{\nstd::span<const ParameterDefault>"
            " parameter_defaults(std::string_view law)\n{\n"
            + "\n".join(rows + cases)
            + "\n  return {};\n}\n\nstd::span<const double>"
            " internal_initial(std::string_view law)\n{\n"
            + "\n".join(initial)
            + "\n  return {};\n}\n} // namespace softpack::forms\n")


def write_atomically(out: Path, text: str) -> None:
    """Write ``text`` as ``out`` through a temporary file."""
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".tmp")
    tmp.write_text(text)
    tmp.replace(out)


def main(argv: list[str]) -> int:
    """Write the registry; exit 1 naming the file of a bad material."""
    cpp = None
    if len(argv) > 2 and argv[1] == "--cpp":
        cpp, argv = Path(argv[2]), argv[:1] + argv[3:]
    if len(argv) < 2:
        print("usage: registry.py [--cpp OUT_CPP] OUT_JSON MATERIAL_FILE...",
              file=sys.stderr)
        return 2
    materials = {}
    for name in sorted(argv[2:]):
        path = Path(name)
        try:
            materials[path.stem] = read_material(path)
        except MaterialError as error:
            print(f"forms/registry.py: material file {path}: {error}", file=sys.stderr)
            return 1
    text = json.dumps({"schema_version": SCHEMA_VERSION, "materials": materials},
                      indent=2) + "\n"
    write_atomically(Path(argv[1]), text)
    if cpp is not None:
        write_atomically(cpp, cpp_table(materials))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
