"""The material registry: the laws of ``forms/materials/`` and their keys.

The build writes ``<build>/forms/materials.json`` (docs/contract.md section
3) from the ``parameters`` dict of each ``forms/materials/LAW.py``; this
module reads it (:func:`load_registry`) so that ``[material] law`` and the
keys of ``[material.parameters]`` come from forms/ only: a new law file is
usable from a TOML file after a build, with no edit here.

A parameter's default is a number or an arithmetic expression of the law's
other parameters (``"2 * shear_modulus"``); :func:`evaluate` computes it
from the syntax tree, allowing numbers, names, ``+ - * /``, unary signs and
parentheses, nothing else.
"""

from __future__ import annotations

import ast
import json
import operator
from dataclasses import dataclass
from pathlib import Path

from softpack import paths
from softpack.contract.schema import Parameter, make_parameter

#: The registry layout this code reads.
REGISTRY_VERSION = 2
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub,
           ast.Mult: operator.mul, ast.Div: operator.truediv}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}


class RegistryError(ValueError):
    """The registry is missing or malformed, or a default cannot be
    evaluated; the message says which file and which key."""


@dataclass(frozen=True)
class Law:
    """One registered material law.

    Attributes
    ----------
    name, doc : str
        The law's name (the file stem in forms/materials/) and meaning.
    parameters : dict
        ``key -> Parameter`` (section ``material.parameters``); a default
        may be an expression string (see :func:`resolve`).
    dimensions : tuple of int
        Where its forms are compiled: (2,) plane strain only, (2, 3) also
        on tetrahedra (the file's ``dimensions``).
    """

    name: str
    doc: str
    parameters: dict
    dimensions: tuple = (2,)


def load_registry(path: Path | None = None) -> dict:
    """Read the registry: ``law name -> Law``.

    Parameters
    ----------
    path : Path, optional
        Default :data:`softpack.paths.MATERIALS` (read at call time).

    Raises
    ------
    RegistryError
        When the file is missing (with how to build it) or malformed.
    """
    path = Path(path or paths.MATERIALS)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise RegistryError(f"{path} not found: the build writes it from"
                            " forms/materials/ (./softpack build)") from None
    except (OSError, json.JSONDecodeError) as err:
        raise RegistryError(f"{path}: cannot read: {err}") from None
    if data.get("schema_version") != REGISTRY_VERSION:
        raise RegistryError(f"{path}: schema_version"
                            f" {data.get('schema_version')!r}, expected"
                            f" {REGISTRY_VERSION}: rebuild (./softpack build)")
    laws = {}
    for name, entry in data.get("materials", {}).items():
        parameters = {}
        for key, spec in entry.get("parameters", {}).items():
            spec = dict(spec, type="float")
            parameters[key] = make_parameter("material.parameters", key, spec)
        laws[name] = Law(name=name, doc=entry.get("doc", ""),
                         parameters=parameters,
                         dimensions=tuple(entry.get("dimensions", (2,))))
    if not laws:
        raise RegistryError(f"{path}: no materials registered")
    return laws


def evaluate(expression: str, values: dict) -> float:
    """Evaluate an arithmetic expression of named numbers, safely.

    Parameters
    ----------
    expression : str
        Numbers, names, ``+ - * /``, unary signs and parentheses.
    values : dict
        ``name -> number`` for the names it uses.

    Raises
    ------
    RegistryError
        For any other syntax, or an unknown name.
    """
    try:
        tree = ast.parse(expression, mode="eval")
    except SyntaxError:
        raise RegistryError(f"default {expression!r} is not an arithmetic"
                            " expression") from None

    def walk(node):
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant) and isinstance(
                node.value, (int, float)) and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id not in values:
                raise RegistryError(f"default {expression!r}: unknown name"
                                    f" {node.id!r}")
            return float(values[node.id])
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _UNARY[type(node.op)](walk(node.operand))
        raise RegistryError(f"default {expression!r}: only numbers, names,"
                            " + - * / and parentheses are allowed")

    return walk(tree)


def names_in(expression) -> set:
    """The names an expression default refers to (empty for a number)."""
    if not isinstance(expression, str):
        return set()
    return {node.id for node in ast.walk(ast.parse(expression, mode="eval"))
            if isinstance(node, ast.Name)}


def resolve(law: Law, given: dict) -> dict:
    """Every parameter of ``law``: the given values, defaults for the rest.

    Defaults that are expressions are evaluated once the parameters they
    name are known (in dependency order); a cycle is refused.

    Returns
    -------
    dict
        ``key -> float`` in the registry's key order.
    """
    values = {k: float(v) for k, v in given.items()}
    pending = [k for k in law.parameters if k not in values]
    while pending:
        ready = [k for k in pending
                 if names_in(law.parameters[k].default) <= values.keys()]
        if not ready:
            raise RegistryError(f"material {law.name}: the defaults of"
                                f" {', '.join(pending)} refer to each other"
                                " or to unknown names")
        for key in ready:
            default = law.parameters[key].default
            values[key] = (evaluate(default, values)
                           if isinstance(default, str) else float(default))
            pending.remove(key)
    return {k: values[k] for k in law.parameters}
