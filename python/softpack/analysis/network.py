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
"""

from __future__ import annotations

import numpy as np

from softpack.analysis.cell import edges, image_offsets
from softpack.analysis.connectivity import read_contacts
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import write_table

NETWORK_COLUMNS = ("step", "time", "a", "b", "nodes", "fx", "fy", "fn", "ft",
                   "branch_x", "branch_y")


def pairs(contacts: dict, centroids: np.ndarray, walls: list,
          thickness: float, offsets=None) -> dict:
    """The network rows (without step and time) of one output step.

    Parameters
    ----------
    contacts : dict of arrays
        A contacts file (:func:`softpack.analysis.connectivity.read_contacts`).
    centroids : ndarray, shape (particles, 2)
        The particles' centroids at that step (NaN: branch vectors NaN).
    walls : list of (point, inward normal)
        Each wall's current point and unit normal.
    thickness : float
        H (m): forces per unit length times H.
    offsets : ndarray, shape (contacts, 2), optional
        A periodic cell's: each contact's antagonist image translation h k
        (:func:`softpack.analysis.cell.image_offsets`); the branch vector
        runs to the image touched.
    """
    loaded = contacts["fn"] != 0
    a = contacts["candidate"][loaded]
    wall = contacts["wall"][loaded]
    other = np.where(wall >= 0, -1 - wall, contacts["antagonist"][loaded])
    # The pair's force on its lower-numbered particle: a nodal force acts
    # on the candidate, from the antagonist.
    swap = (other >= 0) & (other < a)
    first, second = np.where(swap, other, a), np.where(swap, a, other)
    sign = np.where(swap, -1.0, 1.0)
    force = sign[:, None] * np.column_stack(
        (contacts["fx"][loaded], contacts["fy"][loaded])) * thickness
    keys, inverse, nodes = np.unique(np.column_stack((first, second)),
                                     axis=0, return_inverse=True,
                                     return_counts=True)
    inverse = inverse.reshape(-1)
    total = np.zeros((len(keys), 2))
    np.add.at(total, inverse, force)
    branch = np.array([_branch(i, j, centroids, walls) for i, j in keys]
                      ).reshape(-1, 2)
    if offsets is not None and len(keys):
        # The second particle's image seen from the first: one per pair
        seen = sign[:, None] * np.asarray(offsets)[loaded]
        shift = np.zeros((len(keys), 2))
        shift[inverse] = seen
        branch = branch + shift
    length = np.hypot(branch[:, 0], branch[:, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = branch / length[:, None]
    return {"a": keys[:, 0], "b": keys[:, 1], "nodes": nodes,
            "fx": total[:, 0], "fy": total[:, 1],
            "fn": -(total * unit).sum(axis=1),
            "ft": total[:, 1] * unit[:, 0] - total[:, 0] * unit[:, 1],
            "branch_x": branch[:, 0], "branch_y": branch[:, 1]}


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
    columns = {name: [] for name in NETWORK_COLUMNS}
    for k, step in enumerate(steps["step"]):
        path = run.raw.contact_file(step)
        if not path.is_file():
            continue
        mine = particles["step"] == step
        centroids = np.full((setup.count, 2), np.nan)
        if "centroid_x" in particles:
            ids = particles["particle"][mine].astype(np.int64)
            centroids[ids, 0] = particles["centroid_x"][mine]
            centroids[ids, 1] = particles["centroid_y"][mine]
        walls = [(np.array([steps[f"{w}_x"][k], steps[f"{w}_y"][k]]),
                  setup.walls[w].normal) for w in names]
        contacts = read_contacts(path)
        if contacts["wall"].max(initial=-1) >= len(walls):
            raise ValueError(f"{path}: wall {contacts['wall'].max()}, the run"
                             f" has {len(walls)} walls ({', '.join(names)})")
        offsets = (image_offsets(contacts, edges(steps, k)) if setup.cell
                   else None)
        rows = pairs(contacts, centroids, walls, setup.thickness, offsets)
        rows.update(step=np.full(len(rows["a"]), step),
                    time=np.full(len(rows["a"]), steps["time"][k]))
        for name in NETWORK_COLUMNS:
            columns[name].append(np.asarray(rows[name], dtype=float))
    return {name: np.concatenate(values) if values else np.zeros(0)
            for name, values in columns.items()}


def write_network(run_dir, table: dict):
    """Write :func:`network_table`'s rows as ``network.csv``; its path."""
    return write_table(RunDirectory(run_dir).network_csv, table,
                       NETWORK_COLUMNS)


#: The fabric columns of ``series.csv`` (:func:`fabric`).
FABRIC_COLUMNS = ("fabric_xx", "fabric_yy", "fabric_xy", "fabric_anisotropy",
                  "fabric_angle")


def fabric(table: dict, steps) -> dict:
    """The fabric tensor of the contact normals at each output step.

    ``F = <n (x) n>`` over the particle-particle pairs of ``network.csv``
    (walls left out), ``n`` the unit branch vector; trace 1. Its
    anisotropy ``a = 2 (F_1 - F_2)`` (F_1 >= F_2 its eigenvalues: 0 for
    isotropic normals, 2 when all are parallel) and the angle of its major
    direction from x (rad, in (-pi/2, pi/2]). NaN at a step with no pair.
    """
    out = {name: np.full(len(steps), np.nan) for name in FABRIC_COLUMNS}
    particles = table["b"] >= 0
    for k, step in enumerate(steps):
        mine = particles & (table["step"] == step)
        branch = np.column_stack((table["branch_x"][mine],
                                  table["branch_y"][mine]))
        branch = branch[np.isfinite(branch).all(axis=1)]
        if not len(branch):
            continue
        n = branch / np.hypot(*branch.T)[:, None]
        xx, yy, xy = (np.mean(n[:, 0] ** 2), np.mean(n[:, 1] ** 2),
                      np.mean(n[:, 0] * n[:, 1]))
        out["fabric_xx"][k], out["fabric_yy"][k], out["fabric_xy"][k] = \
            xx, yy, xy
        out["fabric_anisotropy"][k] = 2 * np.hypot(xx - yy, 2 * xy)
        out["fabric_angle"][k] = 0.5 * np.arctan2(2 * xy, xx - yy)
    return out
