"""The run configuration: one TOML file, validated before any computation.

A configuration has the sections of :data:`SCHEMA` ([geometry], [mesh],
[material], [loading], [contact], [time], [damping], [output],
[observables]); every key has a type, an allowed range or set of choices, a
default (the paper's value, METHOD.md §1) and a unit.  A file may set any
subset of the keys; the others take their defaults.  ``examples/paper.toml``
spells them all out with their sources.

:func:`load_config` raises :class:`ConfigError` for a file that cannot be
read or parsed, an unknown section or key, a value of the wrong type, a
value out of range, and inconsistent values (e.g. disks that do not fit in
the box).  The message names the file, the key and what is allowed::

    examples/x.toml: [contact] friction = -1: must be >= 0
    examples/x.toml: unknown key [time] stepp (allowed: time_step, theta, ...)

Two values are derived when absent: ``[material] lmbda = 2 shear_modulus``
(the paper's plane-strain effective Lamé parameter, Sec. III.B) and
``[loading] max_time = length / (2 piston_speed)`` (the piston would have
crossed half the box).  A loaded :class:`Config` holds every key, so
:func:`to_toml` writes a complete, reloadable copy.

:func:`to_driver_json` writes the resolved ``driver.json`` of
``docs/driver_io.md`` for the C++ driver ``softpack-simulate``.
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

#: Materials of forms/materials/ (the driver's registry).
MATERIALS = ("neo_hookean", "saint_venant_kirchhoff")
#: Fewest elements around the smallest disk (as softpack.scene.mesh demands).
MIN_BOUNDARY_ELEMENTS = 8
#: Densest packing fraction of rigid disks (hexagonal).
HEXAGONAL_FRACTION = math.pi / (2 * math.sqrt(3))


class ConfigError(ValueError):
    """An invalid configuration; the message names file, key and range."""


@dataclass(frozen=True)
class Key:
    """One configuration key: type, allowed values, default, meaning.

    Attributes
    ----------
    kind : str
        ``"float"``, ``"int"``, ``"bool"``, ``"str"``, ``"float_list"`` or
        ``"int_list"``.
    default : object
        The default; ``None`` for a value derived from others when absent.
    doc, unit : str
        Meaning and SI unit (``""`` when dimensionless).
    low, high : float or None
        Bounds of a number (of each element of a list).
    low_open, high_open : bool
        Whether a bound is excluded.
    choices : tuple of str
        Allowed values of a ``"str"`` key.
    """

    kind: str
    default: object
    doc: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple = ()

    def allowed(self) -> str:
        """The allowed range in words, e.g. ``"> 0"`` or ``"in [0.5, 1]"``."""
        if self.kind == "bool":
            return "true or false"
        if self.kind == "str":
            return "one of " + ", ".join(f'"{c}"' for c in self.choices)
        if self.low is not None and self.high is not None:
            return (f"in {'(' if self.low_open else '['}{self.low:g}, "
                    f"{self.high:g}{')' if self.high_open else ']'}")
        if self.low is not None:
            return f"{'>' if self.low_open else '>='} {self.low:g}"
        if self.high is not None:
            return f"{'<' if self.high_open else '<='} {self.high:g}"
        return "any value"

    def in_range(self, value) -> bool:
        """Whether a number lies within the bounds."""
        if self.low is not None and (value < self.low or
                                     (self.low_open and value == self.low)):
            return False
        return self.high is None or not (
            value > self.high or (self.high_open and value == self.high))


def _pos(default, doc, unit=""):
    """A positive float key."""
    return Key("float", default, doc, unit, low=0.0, low_open=True)


def _nonneg(default, doc, unit=""):
    """A non-negative float key."""
    return Key("float", default, doc, unit, low=0.0)


def _fraction(default, doc):
    """A float key in (0, 1)."""
    return Key("float", default, doc, low=0.0, high=1.0, low_open=True,
               high_open=True)


#: section -> key -> Key. The paper's values (METHOD.md §1) as defaults.
SCHEMA = {
    "geometry": {
        "length": _pos(0.286, "box length L along x, the piston axis", "m"),
        "width": _pos(0.202, "box width W along y", "m"),
        "thickness": _pos(0.015, "cylinder length H (out of plane)", "m"),
        "counts": Key("int_list", [70, 30], "number of disks per species",
                      low=0),
        "diameters": Key("float_list", [0.020, 0.030],
                         "diameter of each species", "m", low=0.0,
                         low_open=True),
        "seed": Key("int", 0, "seed of the random initial packing", low=0),
        "gap": _nonneg(1e-4, "minimum initial clearance between disks and"
                       " between disks and walls", "m"),
    },
    "mesh": {
        "element_size": _pos(1.065e-3, "absolute size of the linear"
                             " triangles, the same for all disks", "m"),
    },
    "material": {
        "name": Key("str", "neo_hookean", "constitutive law",
                    choices=MATERIALS),
        "shear_modulus": _pos(0.15e6, "shear modulus mu", "Pa"),
        "lmbda": Key("float", None, "effective first Lamé parameter of the"
                     " plane-strain model (default 2 mu)", "Pa", low=0.0),
        "density": _pos(1180.0, "mass density rho", "kg/m^3"),
    },
    "loading": {
        "piston_speed": _pos(0.1, "inward speed v_h of the piston", "m/s"),
        "target_packing_fraction": _fraction(0.88, "the run stops when the"
                                             " packing fraction Phi reaches"
                                             " this"),
        "max_time": _pos(None, "the run stops at this time in any case"
                         " (default length / (2 piston_speed))", "s"),
    },
    "contact": {
        "friction": _nonneg(0.3, "Coulomb coefficient mu_f, particle-particle"
                            " and particle-wall"),
        "alert_distance": _pos(2e-4, "pairs closer than this are contact"
                               " candidates for the step", "m"),
        "max_penetration": _pos(5e-4, "deeper detections are taken as"
                                " wrong-side and ignored", "m"),
        "nlgs_tolerance": _fraction(1e-6, "relative tolerance of the NLGS"
                                    " contact solver"),
        "nlgs_max_sweeps": Key("int", 2000, "NLGS sweeps at most per solve",
                               low=1),
        "nlgs_relaxation": Key("float", 1.8, "NLGS relaxation factor",
                               low=0.0, high=2.0, low_open=True,
                               high_open=True),
        "delassus_drop_tolerance": Key(
            "float", None, "off-diagonal Delassus blocks below this fraction"
            " of their contacts' diagonal blocks are dropped (default"
            " nlgs_tolerance / 1000)", low=0.0, high=1e-3),
    },
    "time": {
        "time_step": Key("float", 7.2e-5, "time step h", "s", low=0.0,
                         high=1e-2, low_open=True),
        "theta": Key("float", 0.55, "theta of the theta-method", low=0.5,
                     high=1.0),
        "mass": Key("str", "consistent", "mass matrix",
                    choices=("consistent", "lumped")),
        "newton_tolerance": _fraction(1e-4, "relative velocity-increment"
                                      " tolerance of the Newton iterations"),
        "newton_max_iterations": Key("int", 20, "Newton iterations at most"
                                     " per step", low=1),
        "full_newton": Key("bool", False, "refactor the iteration matrix at"
                           " every Newton iteration (else keep it, see"
                           " tangent_reuse_steps)"),
        "tangent_reuse_steps": Key("int", 50, "with full_newton = false:"
                                   " refactor the iteration matrix at least"
                                   " every this many steps", low=1),
        "refactor_above_iterations": Key("int", 5, "refactor at the next"
                                         " step when a step needed more"
                                         " Newton iterations than this",
                                         low=1),
    },
    "damping": {
        "alpha": _nonneg(30.0, "Rayleigh mass coefficient (C = alpha M +"
                         " beta K)", "1/s"),
        "beta": _nonneg(1e-5, "Rayleigh stiffness coefficient", "s"),
    },
    "output": {
        "every_steps": Key("int", 12, "write raw output every this many"
                           " time steps", low=1),
        "fields": Key("bool", True, "write fields.xdmf/.h5 for ParaView and"
                      " Fig. 7"),
        "fields_every": Key("int", 10, "write fields at every this many"
                            " output steps", low=1),
    },
    "observables": {
        "unbalanced_threshold": Key("float", 1e-3, "f_p* / piston force:"
                                    " particles with a larger resultant"
                                    " contact force are unbalanced", low=0.0,
                                    high=1.0, high_open=True),
        "contact_force_threshold": Key("float", 1e-4, "a nodal normal force"
                                       " is nonzero above this fraction of"
                                       " the step's largest one", low=0.0,
                                       high=1.0, high_open=True),
        "two_node_rule": Key("str", "loaded_nodes", "which nodes count in"
                             " the two-node rule of Z",
                             choices=("loaded_nodes", "candidate_nodes")),
    },
}


class Config(dict):
    """A validated configuration: ``config[section][key]``, every key set.

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


def load_config(path, overrides=None) -> Config:
    """Read and validate a TOML configuration file.

    Parameters
    ----------
    path : str or Path
        The TOML file.
    overrides : dict, optional
        ``{"section.key": value}`` applied on top of the file (e.g. from the
        command line), validated like the file's values.

    Returns
    -------
    Config

    Raises
    ------
    ConfigError
        With a message naming the file, the key and the allowed values.
    """
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except OSError as err:
        raise ConfigError(f"{path}: cannot read: {err.strerror}") from None
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"{path}: invalid TOML: {err}") from None
    return validate(data, path, overrides)


def validate(data: dict, source="<config>", overrides=None) -> Config:
    """Validate parsed TOML data; return the complete :class:`Config`.

    Parameters
    ----------
    data : dict
        ``{section: {key: value}}`` as parsed from TOML.
    source : str
        File name used in messages.
    overrides : dict, optional
        ``{"section.key": value}`` applied on top of ``data``.

    Raises
    ------
    ConfigError
    """
    data = {s: dict(v) if isinstance(v, dict) else v for s, v in data.items()}
    from_cli = set()
    for name, value in (overrides or {}).items():
        section, _, key = name.partition(".")
        if not isinstance(data.setdefault(section, {}), dict):
            raise ConfigError(f"{source}: [{section}] must be a table")
        data[section][key] = value
        from_cli.add((section, key))
    sections = {}
    allowed = f"(allowed sections: {', '.join(SCHEMA)})"
    for section, table in data.items():
        if not isinstance(table, dict):
            if section in SCHEMA:
                raise ConfigError(f"{source}: [{section}] must be a table")
            raise ConfigError(f"{source}: key {section} outside a section"
                              f" {allowed}")
        if section not in SCHEMA:
            raise ConfigError(f"{source}: unknown section [{section}]"
                              f" {allowed}")
    for section, keys in SCHEMA.items():
        table = data.get(section, {})
        for key in table:
            if key not in keys:
                raise ConfigError(
                    f"{source}: unknown key [{section}] {key}"
                    f" (allowed: {', '.join(keys)})")
        sections[section] = {
            key: (_check_value(source, section, key, spec, table[key],
                               (section, key) in from_cli)
                  if key in table else _copy(spec.default))
            for key, spec in keys.items()}
    _derive(sections)
    _check_consistency(source, sections)
    return Config(sections, source)


def _copy(value):
    """A default, lists copied so that configs never share them."""
    return list(value) if isinstance(value, list) else value


def _show(value) -> str:
    """A value as it would be written in TOML."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{...}"
    return repr(value)


def _check_value(source, section, key, spec: Key, value, from_cli=False):
    """Type- and range-check one value; return it converted."""
    where = f"{source}: [{section}] {key} = {_show(value)}"
    if from_cli:
        where += " (from the command line)"
    unit = f" {spec.unit}" if spec.unit else ""

    def fail(what):
        raise ConfigError(f"{where}: must be {what}")

    if spec.kind == "bool":
        if not isinstance(value, bool):
            fail("true or false")
        return value
    if spec.kind == "str":
        if not isinstance(value, str) or value not in spec.choices:
            fail(spec.allowed())
        return value
    if spec.kind in ("float_list", "int_list"):
        scalar = Key(spec.kind[:-5], None, spec.doc, spec.unit, spec.low,
                     spec.high, spec.low_open, spec.high_open)
        noun = "numbers" if scalar.kind == "float" else "integers"
        if not isinstance(value, list) or not value or not all(
                _is_number(v, scalar.kind) for v in value):
            fail(f"a non-empty list of {noun} {spec.allowed()}{unit}")
        if not all(scalar.in_range(v) for v in value):
            fail(f"a list of {noun} {spec.allowed()}{unit}")
        return [float(v) if scalar.kind == "float" else int(v)
                for v in value]
    noun = "a number" if spec.kind == "float" else "an integer"
    if not _is_number(value, spec.kind):
        fail(f"{noun} {spec.allowed()}{unit}")
    if not spec.in_range(value):
        fail(f"{spec.allowed()}{unit}")
    return float(value) if spec.kind == "float" else int(value)


def _is_number(value, kind) -> bool:
    """Whether a TOML value is a finite number of the kind (no booleans)."""
    if isinstance(value, bool):
        return False
    if kind == "int":
        return isinstance(value, int)
    return isinstance(value, (int, float)) and math.isfinite(value)


def _derive(sections) -> None:
    """Fill the values derived from others when absent."""
    material, loading = sections["material"], sections["loading"]
    if material["lmbda"] is None:
        material["lmbda"] = 2.0 * material["shear_modulus"]
    if loading["max_time"] is None:
        loading["max_time"] = (sections["geometry"]["length"]
                               / (2.0 * loading["piston_speed"]))
    contact = sections["contact"]
    if contact["delassus_drop_tolerance"] is None:
        contact["delassus_drop_tolerance"] = 1e-3 * contact["nlgs_tolerance"]


def _check_consistency(source, sections) -> None:
    """Checks that involve several keys: geometry, mesh, loading, time."""
    g = sections["geometry"]
    if len(g["counts"]) != len(g["diameters"]):
        raise ConfigError(
            f"{source}: [geometry] counts and diameters must have the same"
            f" length (got {len(g['counts'])} and {len(g['diameters'])})")
    if sum(g["counts"]) < 1:
        raise ConfigError(f"{source}: [geometry] counts = {g['counts']}:"
                          " must contain at least one disk")
    used = [d for n, d in zip(g["counts"], g["diameters"]) if n > 0]
    room = min(g["length"], g["width"]) - 2 * g["gap"]
    if max(used) >= room:
        raise ConfigError(
            f"{source}: [geometry] diameters = {_show(g['diameters'])}: must"
            f" be < {room:g} m (box side minus twice the gap)")
    area = sum(n * math.pi * d**2 / 4
               for n, d in zip(g["counts"], g["diameters"]))
    phi0 = area / (g["length"] * g["width"])
    target = sections["loading"]["target_packing_fraction"]
    if phi0 >= min(target, HEXAGONAL_FRACTION):
        raise ConfigError(
            f"{source}: [geometry] the disks fill {phi0:.3f} of the box:"
            f" must be < [loading] target_packing_fraction = {target:g} and"
            f" < {HEXAGONAL_FRACTION:.4f} (hexagonal packing)")
    h = sections["mesh"]["element_size"]
    h_max = math.pi * min(used) / MIN_BOUNDARY_ELEMENTS
    if h > h_max:
        raise ConfigError(
            f"{source}: [mesh] element_size = {h!r}: must be <= {h_max:.4g} m"
            f" (at least {MIN_BOUNDARY_ELEMENTS} elements around the smallest"
            f" disk, D = {min(used):g} m)")
    newton = sections["time"]["newton_tolerance"]
    nlgs = sections["contact"]["nlgs_tolerance"]
    if nlgs > 0.1 * newton:
        raise ConfigError(
            f"{source}: [contact] nlgs_tolerance = {nlgs!r}: must be <="
            f" {0.1 * newton:.3g} (a tenth of [time] newton_tolerance: the"
            " Newton iterations cannot converge below the noise of the"
            " contact solve)")
    step, speed = sections["time"]["time_step"], \
        sections["loading"]["piston_speed"]
    alert = sections["contact"]["alert_distance"]
    if speed * step > alert:
        raise ConfigError(
            f"{source}: [time] time_step = {step!r}: must be <="
            f" {alert / speed:.4g} s ([contact] alert_distance / [loading]"
            " piston_speed: the piston may not move more than the alert"
            " distance in one step)")


def defaults() -> Config:
    """The configuration with every key at its default (the paper's case)."""
    return validate({}, "<defaults>")


def initial_packing_fraction(config) -> float:
    """Packing fraction of the rigid disks in the initial box."""
    g = config["geometry"]
    area = sum(n * math.pi * d**2 / 4
               for n, d in zip(g["counts"], g["diameters"]))
    return area / (g["length"] * g["width"])


def to_toml(config) -> str:
    """A complete TOML text of a configuration (every key, derived too)."""
    lines = [f"# resolved from {config.source}"]
    for section, keys in SCHEMA.items():
        lines += ["", f"[{section}]"]
        for key, spec in keys.items():
            unit = f" ({spec.unit})" if spec.unit else ""
            lines.append(f"{key} = {_show(config[section][key])}"
                         f"  # {spec.doc}{unit}")
    return "\n".join(lines) + "\n"


def driver_input(config, mesh_xdmf, out_dir) -> dict:
    """The ``driver.json`` document of ``docs/driver_io.md`` (not written).

    The box is ``[0, length] x [0, width]``: walls ``left`` (x = 0, fixed),
    ``piston`` (x = length, moving at ``-piston_speed`` along x), ``bottom``
    (y = 0) and ``top`` (y = width), each with its inward normal.
    """
    g, m, t = config["geometry"], config["material"], config["time"]
    c, d, o = config["contact"], config["damping"], config["output"]
    length, width = g["length"], g["width"]
    speed = config["loading"]["piston_speed"]

    def wall(name, point, normal, velocity=(0.0, 0.0)):
        return {"name": name, "point": list(point), "normal": list(normal),
                "velocity": list(velocity)}

    return {
        "mesh": str(Path(mesh_xdmf).resolve()),
        "material": {"name": m["name"],
                     "parameters": {"mu": m["shear_modulus"],
                                    "lmbda": m["lmbda"]},
                     "density": m["density"]},
        "walls": [wall("left", (0.0, 0.0), (1.0, 0.0)),
                  wall("piston", (length, 0.0), (-1.0, 0.0), (-speed, 0.0)),
                  wall("bottom", (0.0, 0.0), (0.0, 1.0)),
                  wall("top", (0.0, width), (0.0, -1.0))],
        "box": {"left": "left", "right": "piston", "bottom": "bottom",
                "top": "top"},
        "time_stepping": {
            "time_step": t["time_step"], "theta": t["theta"],
            "mass": t["mass"], "rayleigh_alpha": d["alpha"],
            "rayleigh_beta": d["beta"],
            "newton_tolerance": t["newton_tolerance"],
            "newton_max_iterations": t["newton_max_iterations"],
            "full_newton": t["full_newton"], "velocity_scale": speed,
            "tangent_reuse_steps": t["tangent_reuse_steps"],
            "refactor_above_iterations": t["refactor_above_iterations"]},
        "contact": {key: c[key] for key in
                    ("friction", "alert_distance", "max_penetration",
                     "nlgs_tolerance", "nlgs_max_sweeps", "nlgs_relaxation",
                     "delassus_drop_tolerance")},
        "stop": {"packing_fraction":
                 config["loading"]["target_packing_fraction"],
                 "max_time": config["loading"]["max_time"]},
        "output": {"directory": str(Path(out_dir).resolve()),
                   "every_steps": o["every_steps"],
                   "fields": o["fields_every"] if o["fields"] else 0,
                   # raw/state.bin: the last output step's state, to
                   # continue from (bench --from-state) or inspect
                   "state": True},
    }


def to_driver_json(config, mesh_xdmf, out_dir, initial_state=None) -> dict:
    """Write ``out_dir/driver.json`` for ``softpack-simulate``; return it.

    Parameters
    ----------
    config : Config
        A validated configuration.
    mesh_xdmf : str or Path
        The mesh written by :func:`softpack.mesh.mesh_disks`.
    out_dir : str or Path
        The run directory: the driver writes its raw output there.
    initial_state : str or Path, optional
        A state file to start from (docs/driver_io.md).

    Returns
    -------
    dict
        The document written (see :func:`driver_input`).
    """
    document = driver_input(config, mesh_xdmf, out_dir)
    if initial_state is not None:
        document["initial_state"] = str(Path(initial_state).resolve())
    path = Path(out_dir) / "driver.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(".driver.json.tmp")
    tmp.write_text(json.dumps(document, indent=2) + "\n")
    tmp.replace(path)
    return document
