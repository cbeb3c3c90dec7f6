"""The ONE writer of ``driver.json``, the input of ``softpack-simulate``.

docs/contract.md section 4: every value explicit, one name per parameter
(the schema's), sections in the schema's order. The document is built from
the schema, not from a list of keys here: a parameter added to
``schema/parameters.toml`` reaches driver.json with no edit.

- ``scene``: the scene stage's record (:meth:`softpack.scene.build.Scene.
  record`), with the bodies' mesh and species;
- ``material``: law, density, rigid and the law's ``parameters`` (the
  default material); ``materials``: the named ones, a list of the same
  tables each with its ``name`` (a species' ``material`` names one);
- ``friction``: the [[friction]] tables (species, against, coefficient,
  law, cohesion, cohesive_distance, tensile_strength, shear_strength,
  bonding_distance);
- ``walls``: a list, box walls first (left, right, bottom, top), then the
  others in the TOML file's order;
- every other driver-stage section as a table of its keys.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from softpack.contract.run_directory import RunDirectory
from softpack.contract.schema import load_schema, schema_version


def _plain(value):
    """A tuple or list as a list, anything else as it is (JSON-ready)."""
    return list(value) if isinstance(value, (list, tuple)) else value


def driver_document(config, scene_record: dict, directory,
                    initial_state=None) -> dict:
    """The driver.json document (not written).

    Parameters
    ----------
    config : Config
        A validated configuration (every key set).
    scene_record : dict
        driver.json's ``scene`` (:meth:`Scene.record`).
    directory : path-like
        The run directory, where the driver writes its output.
    initial_state : path-like, optional
        A state file (``raw/state.bin`` of a run of the same scene) to start
        from instead of rest.
    """
    document = {"schema_version": schema_version(),
                "directory": str(Path(directory).resolve()),
                "initial_state": (None if initial_state is None
                                  else str(Path(initial_state).resolve())),
                "scene": scene_record}
    for name, section in load_schema().items():
        if section.stage != "driver":
            continue
        if section.is_map:
            # A named material carries its law's parameters too.
            extra = ("parameters",) if name == "materials" else ()
            document[name] = [{"name": entry, **{k: _plain(values[k]) for k
                                                 in (*section.parameters,
                                                     *extra)}}
                              for entry, values in config[name].items()]
        else:
            document[name] = json.loads(json.dumps(config[name]))
    return document


def write_driver_json(config, scene_record: dict, directory,
                      initial_state=None) -> dict:
    """Write ``directory/driver.json`` atomically; return the document.

    Parameters are those of :func:`driver_document`.
    """
    document = driver_document(config, scene_record, directory,
                               initial_state)
    _write(document, RunDirectory(directory).driver_json)
    return document


def edit_driver_json(directory, edit) -> dict:
    """Change ``directory/driver.json`` in place (``edit(document)``, e.g.
    a resumed run's start state and remaining steps), written atomically;
    return the document."""
    path = RunDirectory(directory).driver_json
    document = json.loads(path.read_text())
    edit(document)
    _write(document, path)
    return document


def _write(document: dict, path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        tmp.write_text(json.dumps(document, indent=2) + "\n")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
