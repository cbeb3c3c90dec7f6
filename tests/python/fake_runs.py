"""Hand-made run directories for the analysis tests (no C++ needed).

``setup_document`` follows docs/contract.md section 5 (raw/setup.json).
"""

import json
import math
from pathlib import Path

import numpy as np


def setup_document(length=0.10, width=0.05, thickness=0.015,
                   diameters=(0.016,), species=None, friction=0.1, seed=3,
                   shear_modulus=0.15e6, law="neo_hookean", box=True,
                   piston_speed=-0.1, rigid=()):
    """A raw/setup.json document: a box of walls left/right/bottom/top.

    ``species`` is the body -> species index list (default: one body of
    each diameter); reference areas are the disks' pi D^2 / 4. The species
    of ``rigid`` (indices) are of a rigid material.
    """
    if species is None:
        species = list(range(len(diameters)))
    walls = [("left", [0, 0], [1, 0], [0, 0]),
             ("right", [length, 0], [-1, 0], [piston_speed, 0]),
             ("bottom", [0, 0], [0, 1], [0, 0]),
             ("top", [0, width], [0, -1], [0, 0])]
    if not box:
        walls = walls[2:]
    parameters = {"c1": 1.0} if shear_modulus is None else {
        "shear_modulus": shear_modulus, "lame_lambda": 2 * shear_modulus}
    kinds = [{"name": f"s{i}", "shape": "disk", "diameter": d,
              "count": species.count(i),
              "material": "hard" if i in rigid else ""}
             for i, d in enumerate(diameters)]
    return {
        "schema_version": 2,
        "units": {"length": "m", "time": "s", "mass": "kg", "force": "N/m",
                  "energy": "J/m", "stress": "Pa", "note": "2D model"},
        "scene": {"model": {"thickness": thickness},
                  "box": {"enabled": box, "length": length, "width": width},
                  "packing": {"seed": seed, "gap": 1e-4},
                  "species": kinds, "mesh": {"element_size": 1e-3},
                  "bodies": {"mesh": "/nowhere/packing.xdmf",
                             "species": species}},
        "material": {"law": law, "density": 1180.0, "parameters": parameters},
        "materials": [{"name": "hard", "law": law, "density": 1180.0,
                       "parameters": parameters, "rigid": True}] if rigid
        else [],
        "walls": [{"name": n, "point": p, "normal": q, "velocity": v}
                  for n, p, q, v in walls],
        "parameters": {"stop": {}, "contact": {"friction": friction},
                       "time": {}, "damping": {}, "output": {}},
        "initial_state": None,
        "bodies": {"count": len(species), "species": species,
                   "reference_area": [math.pi * diameters[s]**2 / 4
                                      for s in species],
                   "nodes": [], "triangles": []},
    }


def write_setup(run_dir, **kwargs):
    """Write ``run_dir/raw/setup.json``; returns the document."""
    doc = setup_document(**kwargs)
    (run_dir / "raw").mkdir(parents=True, exist_ok=True)
    (run_dir / "raw" / "setup.json").write_text(json.dumps(doc))
    return doc


def write_rules(run_dir, unbalanced=1e-3, force=1e-4, rule="loaded_nodes",
                other_sections=True):
    """A config.toml whose [observables] section holds the rules.

    Other sections hold values the analysis must not read (nonsense on
    purpose, so that a test fails if it does).
    """
    text = ("[observables]\n"
            f"unbalanced_threshold = {unbalanced!r}\n"
            f"contact_force_threshold = {force!r}\n"
            f"two_node_rule = \"{rule}\"\n")
    if other_sections:
        text = ("[model]\nthickness = -1.0\n[contact]\nfriction = 99.0\n\n"
                + text)
    (run_dir / "config.toml").write_text(text)


def write_fields(path, times):
    """Two triangles (bodies 0 and 1) in the dolfinx XDMF/HDF5 layout.

    u = (t, -2t) at every node, Psi = 1000 t per cell; keys as dolfinx
    writes them: repr(time) with '.' as '_'.
    """
    import h5py
    import numpy as np

    with h5py.File(path, "w") as f:
        f["Mesh/mesh/geometry"] = np.array([[0, 0], [1, 0], [1, 1], [0, 1.]])
        f["Mesh/mesh/topology"] = np.array([[0, 1, 2], [0, 2, 3]])
        for t in times:
            key = repr(float(t)).replace(".", "_")
            u = np.zeros((4, 3))
            u[:, 0], u[:, 1] = t, -2 * t
            f[f"Function/displacement/{key}"] = u
            f[f"Function/Psi/{key}"] = np.full((2, 1), 1000.0 * t)
            f[f"Function/particle/{key}"] = np.array([[0.0], [1.0]])
    return path


def write_loading_run(run_dir, phi, p, rigid=()):
    """A finished run in a box whose wall and finite-element pressures are
    ``p`` (and 1.01 p) at packing fractions ``phi``, at rest: raw/steps.csv,
    raw/setup.json (the species of ``rigid`` rigid), series.csv and
    stress.csv."""
    from softpack.analysis import stress as stress_module
    from softpack.contract.run_directory import RunDirectory
    from softpack.contract.tables import write_table

    run_dir = Path(run_dir)
    rows = len(p)
    write_setup(run_dir, diameters=(0.016, 0.02), rigid=rigid)
    write_table(run_dir / "raw" / "steps.csv",
                {"step": np.arange(rows), "kinetic_energy": np.zeros(rows),
                 "strain_energy": np.ones(rows)},
                ("step", "kinetic_energy", "strain_energy"))
    write_table(run_dir / "series.csv",
                {"phi": phi, "z": 3 + 10 * (phi - 0.8)}, ("phi", "z"))
    table = {c: np.full(rows, np.nan) for c in stress_module.COLUMNS}
    table.update(step=np.arange(rows), wall_P=p, wall_q=0.01 * p,
                 contact_P=0.99 * p, contact_q=0.01 * p,
                 fe_P=1.01 * p, fe_q=0.01 * p, eps_q=np.linspace(0, .1, rows),
                 eps_v=np.linspace(0, .05, rows),
                 difference_wall_fe=np.full(rows, 0.01))
    write_table(RunDirectory(run_dir).stress_csv, table,
                stress_module.COLUMNS)
    return run_dir
