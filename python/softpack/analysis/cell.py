"""A periodic cell's geometry and stress (docs/periodic_cell.md).

The driver writes the cell's edge vectors a1, a2 at every output step
(``raw/steps.csv``: ``cell_a1x, cell_a1y, cell_a2x, cell_a2y``) and, for each
contact, the image k of its antagonist (``raw/contacts``: ``image1,
image2``): the antagonist touched is its body shifted by h k = k1 a1 + k2 a2.
The branch vector of a contact runs from that image's centroid to the
candidate's; the Love-Weber stress of the cell is sigma = (1/A) sum f (x) l,
A = det h, compression positive as for a box (:mod:`.stress`), with the
centroids of ``raw/particles.csv`` (written at each output step, after the
bodies were re-wrapped, as the images are). ``stress.csv`` of a cell has the
contact and finite-element estimates, the wall estimate NaN (no walls), and
the strains of the cell's diagonal, eps_xx = -ln(h_xx / h_xx0); then the
bulk columns gamma (:func:`shear_strain`: the imposed shear, from each
stage's start), mu_star, inertial_number and phi (the packing fraction,
whose change under a constant normal stress is the dilatancy).
"""

from __future__ import annotations

import numpy as np

from softpack.analysis.connectivity import read_contacts
from softpack.analysis.stress import (BOX, COLUMNS, COMPONENTS, fe_stress,
                                      stress_columns)
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table

#: The edge vectors' columns of raw/steps.csv
EDGE_COLUMNS = ("cell_a1x", "cell_a1y", "cell_a2x", "cell_a2y")
#: The columns a cell's stress.csv adds after stress.COLUMNS
BULK_COLUMNS = ("gamma", "mu_star", "inertial_number", "phi")


def edges(steps: dict, k: int) -> np.ndarray:
    """h at output row k: its columns a1, a2, shape (2, 2)."""
    a1x, a1y, a2x, a2y = (float(steps[c][k]) for c in EDGE_COLUMNS)
    return np.array([[a1x, a2x], [a1y, a2y]])


def cell_area(steps: dict) -> np.ndarray:
    """det h of every output row (m^2)."""
    return (np.asarray(steps["cell_a1x"], float) * steps["cell_a2y"]
            - np.asarray(steps["cell_a1y"], float) * steps["cell_a2x"])


def image_offsets(contacts: dict, h: np.ndarray) -> np.ndarray:
    """Each contact's antagonist image translation h k, shape (n, 2)."""
    k = np.column_stack((contacts["image1"], contacts["image2"]))
    return k.astype(float) @ h.T


def centroids_at(particles: dict, step, count: int) -> np.ndarray:
    """The particles' centroids of ``raw/particles.csv`` at one step."""
    mine = particles["step"] == step
    out = np.full((count, 2), np.nan)
    ids = particles["particle"][mine].astype(np.int64)
    out[ids, 0] = particles["centroid_x"][mine]
    out[ids, 1] = particles["centroid_y"][mine]
    return out


def love_weber(contacts: dict, centres: np.ndarray, h: np.ndarray):
    """(1/det h) sum f (x) l over the particle contacts, (2, 2),
    compression positive; l from the antagonist's image to the candidate."""
    cand, ant = contacts["candidate"], contacts["antagonist"]
    f = np.column_stack([contacts["fx"], contacts["fy"]])
    branch = (centres[cand] - centres[ant]
              - image_offsets(contacts, h))
    return f.T @ branch / np.linalg.det(h)


def cell_stress_table(run_dir, setup, steps: dict, particles: dict) -> dict:
    """:data:`softpack.analysis.stress.COLUMNS` of a periodic cell."""
    run = RunDirectory(run_dir)
    rows = len(steps["step"])
    area = cell_area(steps)
    nan = {c: np.full(rows, np.nan) for c in COMPONENTS}
    wall = {**nan, "area": area}
    contact = {c: np.full(rows, np.nan) for c in COMPONENTS}
    for k in range(rows):
        path = run.raw.contact_file(steps["step"][k])
        if not path.is_file():
            continue
        sigma = love_weber(read_contacts(path),
                           centroids_at(particles, steps["step"][k],
                                        setup.count), edges(steps, k))
        for i, c in enumerate(COMPONENTS):
            contact[c][k] = sigma.flat[i]
    eps_xx = -np.log(np.asarray(steps["cell_a1x"], float)
                     / steps["cell_a1x"][0])
    eps_yy = -np.log(np.asarray(steps["cell_a2y"], float)
                     / steps["cell_a2y"][0])
    table = stress_columns(steps, wall, contact, fe_stress(steps, area),
                           {"xx": eps_xx, "yy": eps_yy},
                           {f"{w}_stress": np.full(rows, np.nan) for w in BOX})
    table.update(bulk_columns(steps, table, setup))
    return table


def bulk_columns(steps: dict, table: dict, setup) -> dict:
    """:data:`BULK_COLUMNS` from the cell's edges and the contact stress
    (see the module doc)."""
    gamma = shear_strain(steps)
    time = np.asarray(steps["time"], float)
    rate = np.gradient(gamma, time) if len(time) > 1 else np.zeros(1)
    shear = 0.5 * (np.asarray(table["contact_xy"], float)
                   + np.asarray(table["contact_yx"], float))
    normal = np.asarray(table["contact_yy"], float)
    pressure = np.asarray(table["contact_P"], float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu_star = np.where(normal > 0, np.abs(shear) / normal, np.nan)
        inertial = np.where(pressure > 0, np.abs(rate)
                            * float(np.mean(setup.diameters))
                            * np.sqrt(float(np.mean(setup.body_density))
                                      / pressure), np.nan)
    return {"gamma": gamma, "mu_star": mu_star, "inertial_number": inertial,
            "phi": np.asarray(steps["phi"], float)}


def shear_strain(steps: dict) -> np.ndarray:
    """gamma of every output row: the integral of the imposed L_xy, i.e. the
    shear of h_xy over the height h_yy each stage started from. The driver
    moves the edges at dh/dt = L h0, h0 the cell at the start of the stage
    whose drive L is (a stage's drive replaces the previous one at its
    start), so within a stage gamma grows by (h_xy - h_xy0) / h_yy0; a
    stage starts from the last row of the stage before it (row 0 for the
    first). A run without stages is one stage from t = 0."""
    a2x = sheared_edge(steps)
    a2y = np.asarray(steps["cell_a2y"], float)
    stage = (np.asarray(steps["stage"], int) if "stage" in steps
             else np.zeros(len(a2x), int))
    gamma = np.zeros(len(a2x))
    start, base = 0, 0.0
    for k in range(1, len(a2x)):
        if stage[k] != stage[k - 1]:
            start, base = k - 1, gamma[k - 1]
        gamma[k] = base + (a2x[k] - a2x[start]) / a2y[start]
    return gamma


def sheared_edge(steps: dict) -> np.ndarray:
    """h_xy of the edge a2 as if never remapped: the driver replaces a2 by
    a2 - n a1 (the same lattice) when the cell leans past half its width,
    so h_xy jumps by -n h_xx between two rows; the n are recovered as the
    nearest integers of the jumps over h_xx (an output interval shears
    the cell by much less than half its width) and added back."""
    a1x = np.asarray(steps["cell_a1x"], float)
    a2x = np.asarray(steps["cell_a2x"], float)
    jumps = np.rint(np.diff(a2x) / a1x[1:])
    return a2x - np.concatenate(([0.0], np.cumsum(jumps))) * a1x


def write_cell_stress(run_dir, setup) -> None:
    """Write ``RUN/stress.csv`` of a periodic cell."""
    run = RunDirectory(run_dir)
    steps = read_table(run.raw.steps_csv)
    particles = read_table(run.raw.particles_csv)
    write_table(run.stress_csv,
                cell_stress_table(run_dir, setup, steps, particles),
                COLUMNS + BULK_COLUMNS)
