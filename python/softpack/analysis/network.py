"""The contact network of every output step as one table: ``network.csv``.

One row per force-bearing pair (output step, particle ``a``, particle or
wall ``b``) from ``raw/contacts/step_NNNNNNNN.csv`` (nodal contacts) and
the particles' centroids of ``raw/particles.csv``; forces times the
thickness H (N), as in ``series.csv``. pandas reads it (``read_run(DIR,
"network")``); NetworkX takes a step's rows as an edge list::

    rows = net[net.step == step]
    graph = networkx.from_pandas_edgelist(rows, "a", "b", edge_attr=True)

Columns
-------
step, time
    The output step and its time (s).
a, b
    The particles (``a < b``), or particle ``a`` and wall ``w`` as ``b =
    -1 - w`` (each wall its own node of the graph; ``w`` indexes
    ``raw/setup.json``'s walls).
nodes
    The nodal contacts of the pair with a nonzero normal force
    (compressive, or tensile under a cohesive law or a bond).
fx, fy
    The force on ``a`` from ``b`` (N): the sum of its nodal forces.
fn, ft
    That force along the branch vector (compression positive: ``fn = -f .
    l / |l|``) and across it (``ft = f . (e_z x l) / |l|``).
branch_x, branch_y
    The branch vector ``l`` (m): from ``a``'s centroid to ``b``'s, or to
    the point of the wall nearest ``a``'s centroid (its projection).

A 3D run's (``NETWORK_COLUMNS_3D``) adds ``fz`` and ``branch_z`` (forces
in N, no thickness factor; the volume centroids of ``raw/particles.csv``;
``b = -1 - w`` for the six planes left, right, bottom, top, base, lid) and
its ``ft`` is the magnitude of the force across the branch vector (>= 0).
"""

from __future__ import annotations

import numpy as np

from softpack.analysis.cell import edges, image_offsets
from softpack.analysis.connectivity import contact_forces, read_contacts
from softpack.analysis.tensors import (axes, deviator_size,
                                       symmetric_components)
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import write_table

NETWORK_COLUMNS = ("step", "time", "a", "b", "nodes", "fx", "fy", "fn", "ft",
                   "branch_x", "branch_y")
#: A 3D run's ``network.csv`` (``fz``, ``branch_z``; ``ft`` >= 0).
NETWORK_COLUMNS_3D = ("step", "time", "a", "b", "nodes", "fx", "fy", "fz",
                      "fn", "ft", "branch_x", "branch_y", "branch_z")


def network_columns(dimension: int) -> tuple:
    """The columns of ``network.csv`` of a run of that dimension."""
    return NETWORK_COLUMNS_3D if dimension == 3 else NETWORK_COLUMNS


def pairs(contacts: dict, centroids: np.ndarray, walls: list,
          thickness: float, offsets=None) -> dict:
    """The network rows (without step and time) of one output step.

    Parameters
    ----------
    contacts : dict of arrays
        A contacts file (:func:`softpack.analysis.connectivity.read_contacts`).
    centroids : ndarray, shape (particles, d)
        The particles' centroids at that step (NaN: branch vectors NaN);
        d = 3 for a 3D run (its contact files have ``fz``).
    walls : list of (point, inward normal)
        Each wall's current point and unit normal (d components).
    thickness : float
        H (m): forces per unit length times H (1 in 3D: forces in N).
    offsets : ndarray, shape (contacts, 2), optional
        A periodic cell's: each contact's antagonist image translation h k
        (:func:`softpack.analysis.cell.image_offsets`); the branch vector
        runs to the image touched.
    """
    d = centroids.shape[1]
    loaded = contacts["fn"] != 0
    a = contacts["candidate"][loaded]
    wall = contacts["wall"][loaded]
    other = np.where(wall >= 0, -1 - wall, contacts["antagonist"][loaded])
    # The pair's force on its lower-numbered particle: a nodal force acts
    # on the candidate, from the antagonist.
    swap = (other >= 0) & (other < a)
    first, second = np.where(swap, other, a), np.where(swap, a, other)
    sign = np.where(swap, -1.0, 1.0)
    force = sign[:, None] * contact_forces(contacts)[loaded] * thickness
    keys, inverse, nodes = np.unique(np.column_stack((first, second)),
                                     axis=0, return_inverse=True,
                                     return_counts=True)
    inverse = inverse.reshape(-1)
    total = np.zeros((len(keys), d))
    np.add.at(total, inverse, force)
    branch = np.array([_branch(i, j, centroids, walls) for i, j in keys]
                      ).reshape(-1, d)
    if offsets is not None and len(keys):
        # The second particle's image seen from the first: one per pair
        seen = sign[:, None] * np.asarray(offsets)[loaded]
        shift = np.zeros((len(keys), 2))
        shift[inverse] = seen
        branch = branch + shift
    length = (np.hypot(branch[:, 0], branch[:, 1]) if d == 2
              else np.linalg.norm(branch, axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = branch / length[:, None]
    normal = (total * unit).sum(axis=1)
    rows = {"a": keys[:, 0], "b": keys[:, 1], "nodes": nodes,
            "fn": -normal}
    if d == 2:
        rows["ft"] = total[:, 1] * unit[:, 0] - total[:, 0] * unit[:, 1]
    else:  # the magnitude of the part across the branch vector
        rows["ft"] = np.linalg.norm(total - normal[:, None] * unit, axis=1)
    for i, axis in enumerate("xyz"[:d]):
        rows[f"f{axis}"] = total[:, i]
        rows[f"branch_{axis}"] = branch[:, i]
    return rows


def _branch(a, b, centroids, walls) -> np.ndarray:
    """From particle a's centroid to particle b's, or to wall -1 - b."""
    if b >= 0:
        return centroids[b] - centroids[a]
    point, normal = walls[-1 - b]
    return -np.dot(centroids[a] - point, normal) * normal


def network_table(run_dir, setup, steps: dict, particles: dict) -> dict:
    """The rows of ``network.csv`` of a run (every output step with a
    contacts file), from its ``raw/steps.csv`` and ``raw/particles.csv``
    (read by the caller)."""
    run = RunDirectory(run_dir)
    names = list(setup.walls)
    axes = "xyz"[:setup.dimension]
    columns = {name: [] for name in network_columns(setup.dimension)}
    for k, step in enumerate(steps["step"]):
        path = run.raw.contact_file(step)
        if not path.is_file():
            continue
        mine = particles["step"] == step
        centroids = np.full((setup.count, len(axes)), np.nan)
        if "centroid_x" in particles:
            ids = particles["particle"][mine].astype(np.int64)
            for i, axis in enumerate(axes):
                centroids[ids, i] = particles[f"centroid_{axis}"][mine]
        walls = [(np.array([steps[f"{w}_{axis}"][k] for axis in axes]),
                  setup.walls[w].normal) for w in names]
        contacts = read_contacts(path)
        if contacts["wall"].max(initial=-1) >= len(walls):
            raise ValueError(f"{path}: wall {contacts['wall'].max()}, the run"
                             f" has {len(walls)} walls ({', '.join(names)})")
        offsets = (image_offsets(contacts, edges(steps, k)) if setup.cell
                   else None)
        thickness = setup.thickness if setup.dimension == 2 else 1.0
        rows = pairs(contacts, centroids, walls, thickness, offsets)
        rows.update(step=np.full(len(rows["a"]), step),
                    time=np.full(len(rows["a"]), steps["time"][k]))
        for name in columns:
            columns[name].append(np.asarray(rows[name], dtype=float))
    return {name: np.concatenate(values) if values else np.zeros(0)
            for name, values in columns.items()}


def write_network(run_dir, table: dict):
    """Write :func:`network_table`'s rows as ``network.csv``; its path."""
    return write_table(RunDirectory(run_dir).network_csv, table,
                       NETWORK_COLUMNS_3D if "fz" in table
                       else NETWORK_COLUMNS)


#: The fabric columns of ``series.csv`` (:func:`fabric`).
FABRIC_COLUMNS = ("fabric_xx", "fabric_yy", "fabric_xy", "fabric_anisotropy",
                  "fabric_angle")
#: A 3D run's (no angle: the major direction is not one angle).
FABRIC_COLUMNS_3D = ("fabric_xx", "fabric_yy", "fabric_zz", "fabric_xy",
                     "fabric_xz", "fabric_yz", "fabric_anisotropy")


def fabric_columns(dimension: int) -> tuple:
    """The fabric columns of ``series.csv`` of a run of that dimension."""
    return FABRIC_COLUMNS_3D if dimension == 3 else FABRIC_COLUMNS


def fabric(table: dict, steps) -> dict:
    """The fabric tensor of the contact normals at each output step.

    ``F = <n (x) n>`` over the particle-particle pairs of ``network.csv``
    (walls left out), ``n`` the unit branch vector; trace 1; d x d, d the
    run's dimension (3 when the table has ``branch_z``). Its anisotropy
    ``a = |A'|_d`` (:func:`softpack.analysis.tensors.deviator_size`) of
    ``A = d (d + 2) / 2 F``, the second-order coefficient of the density of
    normals E(n) = (1 + A'_ij n_i n_j) / |S^(d-1)|: in 2D ``2 (F_1 - F_2)``
    (F_1 >= F_2 its eigenvalues: 0 for isotropic normals, 2 when all are
    parallel), in 3D sqrt(3/2 A':A') (0 isotropic, 7.5 when all are
    parallel; 15/2 |F_1 - F_3| for an axisymmetric F). In 2D also the angle
    of its major direction from x (rad, in (-pi/2, pi/2]). NaN at a step
    with no pair.
    """
    d = 3 if "branch_z" in table else 2
    names = fabric_columns(d)
    out = {name: np.full(len(steps), np.nan) for name in names}
    particles = table["b"] >= 0
    for k, step in enumerate(steps):
        mine = particles & (table["step"] == step)
        branch = np.column_stack([table[f"branch_{axis}"][mine]
                                  for axis in axes(d)])
        branch = branch[np.isfinite(branch).all(axis=1)]
        if not len(branch):
            continue
        n = branch / (np.hypot(*branch.T) if d == 2
                      else np.linalg.norm(branch, axis=1))[:, None]
        f = np.array([[np.mean(n[:, i] * n[:, j]) for j in range(d)]
                      for i in range(d)])
        for name in symmetric_components(d):
            out[f"fabric_{name}"][k] = f["xyz".index(name[0]),
                                         "xyz".index(name[1])]
        out["fabric_anisotropy"][k] = deviator_size(0.5 * d * (d + 2) * f)
        if d == 2:
            out["fabric_angle"][k] = 0.5 * np.arctan2(2 * f[0, 1],
                                                      f[0, 0] - f[1, 1])
    return out
