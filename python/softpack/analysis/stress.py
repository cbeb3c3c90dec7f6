"""The assembly's stress at every output step, written to ``stress.csv``.

Three estimates of the mean (2D, per unit length along z) Cauchy stress of a
box of particles, compression counted positive (the granular convention),
A the current box area from the walls' positions in ``raw/steps.csv``:

From the wall forces (the boundary average sigma = (1/A) sum over the wall
contacts of F (x) x_c, F the force the particle exerts on the wall and x_c
the contact point): ``raw/contacts/step_NNNNNNNN.csv`` gives each wall
contact's force (``fx, fy`` on the candidate, averaged over the output
interval) and its candidate node, whose current position is read from
``fields.h5``. The walls' tangential (friction) forces enter through their
contact points: with friction on the walls the mean stress is not the
imposed wall pressure (the walls parallel to the load carry part of it).
Without ``fields.h5`` the contact points are unknown and the estimate falls
back on the wall totals of ``raw/steps.csv``: sigma_xx = (F_right,x x_right
+ F_left,x x_left) / A (= F_right,x / H in equilibrium, H the height),
sigma_yy likewise, sigma_xy = (F_top,x y_top + F_bottom,x y_bottom) / A,
sigma_yx = (F_right,y x_right + F_left,y x_left) / A: exact for frictionless
walls only.

From the contact forces (Love-Weber: sigma = (1/A) sum over contacts of
f (x) l): l is the branch vector from the antagonist particle's centre to
the candidate's for a particle contact, and from the contact point to the
candidate's centre for a wall contact; centres are the area centroids of
the deformed particles.

From the finite elements (the volume average of the particles' own
stress, zero in the voids): sigma = -(1/A) sum over particles of the
integral of their Cauchy stress over the deformed particle, the columns
``cauchy_xx, cauchy_yy, cauchy_xy, cauchy_yx`` of ``raw/steps.csv`` (N per
unit length, tension positive: hence the sign). The driver computes
int sigma da = int P F^T dX (plane strain, F33 = 1) at each output step
from the internal force, sum over nodes of f_int (x) x, exact for P1
elements (``driver/bodies/stress_average.h``; checked against the law's
compiled form ``forms/cauchy_integral.py`` and homogeneous deformations).
It is the stress at the output step itself, not an interval average. Runs
written before these columns existed get NaN.

Each box wall's own normal stress, ``NAME_stress`` = normal force on the
wall / its current length (the distance between its two neighbours), is
what a pressure-controlled wall holds.

Approximations: the fields are those of the stored time nearest the output
step (``[output] fields_every`` > 1 leaves steps without their own), and
the contact forces are averages over the output interval while positions
are the end's. Steps with no contacts file or no fields have NaN contact
estimates.

Scalars (compression positive): the pressure P = (sigma_xx + sigma_yy) / 2
and the deviator q = sqrt(((sigma_xx - sigma_yy) / 2)^2 + sigma_xy^2) (the
2D maximum shear stress, of the symmetric part) of each estimate; the
relative difference of each pair, ``difference`` = |sigma_wall -
sigma_contact|_F / |sigma_wall|_F, ``difference_wall_fe`` = |sigma_wall -
sigma_fe|_F / |sigma_wall|_F and ``difference_contact_fe`` = |sigma_contact
- sigma_fe|_F / |sigma_contact|_F, so that a user sees when they do not
agree (they must in equilibrium: at rest, the integral of sigma over a
particle is the sum over its contacts of force (x) point, what the other
two sum). Strains from the box, compression positive: eps_xx = -ln(L /
L0), eps_yy = -ln(H / H0), volumetric eps_v = eps_xx + eps_yy, deviatoric
eps_q = eps_xx - eps_yy.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis import fields as fields_h5
from softpack.analysis.connectivity import read_contacts
from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table

#: The box walls and the axis of each one's normal.
BOX = {"left": 0, "right": 0, "bottom": 1, "top": 1}

#: The columns of ``stress.csv``, in order.
COLUMNS = ("step", "time", "area", "eps_xx", "eps_yy", "eps_v", "eps_q",
           *(f"{w}_stress" for w in BOX),
           "wall_xx", "wall_yy", "wall_xy", "wall_yx", "wall_P", "wall_q",
           "contact_xx", "contact_yy", "contact_xy", "contact_yx",
           "contact_P", "contact_q", "difference",
           "fe_xx", "fe_yy", "fe_xy", "fe_yx", "fe_P", "fe_q",
           "difference_wall_fe", "difference_contact_fe")

COMPONENTS = ("xx", "xy", "yx", "yy")


def pressure_deviator(xx, yy, xy, yx):
    """P = tr(sigma) / 2 and q = sqrt(((xx - yy) / 2)^2 + sym(xy)^2)."""
    xx, yy = np.asarray(xx, float), np.asarray(yy, float)
    shear = 0.5 * (np.asarray(xy, float) + np.asarray(yx, float))
    return 0.5 * (xx + yy), np.hypot(0.5 * (xx - yy), shear)


def box_walls(steps: dict):
    """Current box positions (x_left, x_right, y_bottom, y_top) from steps."""
    return (np.asarray(steps["left_x"]), np.asarray(steps["right_x"]),
            np.asarray(steps["bottom_y"]), np.asarray(steps["top_y"]))


def wall_normal_stresses(steps: dict) -> dict:
    """``NAME_stress``: each box wall's normal force / its current length.

    The force is the one the particles exert on the wall along its outward
    direction (compression positive); the length is the distance between
    the wall's two neighbours.
    """
    x0, x1, y0, y1 = box_walls(steps)
    width, height = x1 - x0, y1 - y0
    return {"left_stress": -np.asarray(steps["left_fx"]) / height,
            "right_stress": np.asarray(steps["right_fx"]) / height,
            "bottom_stress": -np.asarray(steps["bottom_fy"]) / width,
            "top_stress": np.asarray(steps["top_fy"]) / width}


def wall_totals_stress(steps: dict) -> dict:
    """The boundary stress from the wall totals (frictionless walls).

    Returns
    -------
    dict with ``area`` and ``xx``, ``xy``, ``yx``, ``yy`` (Pa), one value
    per row of ``raw/steps.csv``.
    """
    x0, x1, y0, y1 = box_walls(steps)
    area = (x1 - x0) * (y1 - y0)
    f = {k: np.asarray(steps[k]) for k in steps if k.endswith(("_fx", "_fy"))}
    return {"area": area,
            "xx": (f["right_fx"] * x1 + f["left_fx"] * x0) / area,
            "yy": (f["top_fy"] * y1 + f["bottom_fy"] * y0) / area,
            "xy": (f["top_fx"] * y1 + f["bottom_fx"] * y0) / area,
            "yx": (f["right_fy"] * x1 + f["left_fy"] * x0) / area}


@dataclass(frozen=True)
class Geometry:
    """The deformed particles at one stored time."""

    centres: np.ndarray  #: (particles, 2) area centroids
    current: np.ndarray  #: (nodes, 2) current node positions
    nodes: list          #: per particle, its global nodes in local order


def particle_nodes(cells, body, count: int) -> list:
    """Each particle's global nodes in the driver's local order.

    The driver numbers a body's nodes by increasing global index
    (``driver/bodies/BodySet.cpp``), so local node k of particle b is the
    k-th smallest node of b's cells.
    """
    return [np.unique(cells[body == b]) for b in range(count)]


def centroids(current, cells, body, count: int) -> np.ndarray:
    """Area centroids of the deformed particles, shape ``(count, 2)``."""
    a, b, c = (current[cells[:, k]] for k in range(3))
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    centre = (a + b + c) / 3.0
    total = np.bincount(body, weights=area, minlength=count)
    out = np.empty((count, 2))
    for d in range(2):
        out[:, d] = np.bincount(body, weights=area * centre[:, d],
                                minlength=count) / total
    return out


def contact_points(contacts: dict, geometry: Geometry) -> np.ndarray:
    """Current position of each contact's candidate node, ``(contacts, 2)``."""
    return np.array([geometry.current[geometry.nodes[b][k]] for b, k in
                     zip(contacts["candidate"], contacts["node"])]
                    ).reshape(-1, 2)


def love_weber(contacts: dict, geometry: Geometry, area: float):
    """Love-Weber stress (1/A) sum f (x) l, compression positive, (2, 2).

    Parameters
    ----------
    contacts : dict
        One ``raw/contacts`` file (:func:`read_contacts`): ``candidate``,
        ``node``, ``antagonist`` (-1 for a wall), ``fx``, ``fy`` (the force
        on the candidate).
    geometry : Geometry
        The particles at that step.
    area : float
        The box area.
    """
    f = np.column_stack([contacts["fx"], contacts["fy"]])
    cand, ant = contacts["candidate"], contacts["antagonist"]
    centres = geometry.centres
    body = ant >= 0
    branch = centres[cand] - contact_points(contacts, geometry)
    branch[body] = centres[cand[body]] - centres[ant[body]]
    return f.T @ branch / area


def boundary_stress(contacts: dict, geometry: Geometry, area: float):
    """(1/A) sum over wall contacts of F (x) x_c, F the force on the wall."""
    wall = contacts["antagonist"] < 0
    f = -np.column_stack([contacts["fx"], contacts["fy"]])[wall]
    return f.T @ contact_points(contacts, geometry)[wall] / area


def stored_geometries(run_dir, count: int):
    """``(times, [Geometry])`` of every time stored in fields.h5, or None."""
    path = RunDirectory(run_dir).fields_h5
    if not path.is_file():
        return None
    stored = fields_h5.read_displacements(path)
    if not stored:
        return None
    first = fields_h5.read_snapshot(path, stored[0][0])
    if first.body is None:
        return None
    nodes = particle_nodes(first.cells, first.body, count)
    out = []
    for _, u in stored:
        current = first.points + u
        out.append(Geometry(centroids(current, first.cells, first.body,
                                      count), current, nodes))
    return np.array([t for t, _ in stored]), out


def stress_table(run_dir) -> dict:
    """Every output step's stress columns (:data:`COLUMNS`).

    Parameters
    ----------
    run_dir : path-like
        A finished run directory with a box.
    """
    run = RunDirectory(run_dir)
    setup = read_setup(run_dir)
    steps = read_table(run.raw.steps_csv)
    wall = wall_totals_stress(steps)
    x0, x1, y0, y1 = box_walls(steps)
    eps_xx = -np.log((x1 - x0) / (x1[0] - x0[0]))
    eps_yy = -np.log((y1 - y0) / (y1[0] - y0[0]))
    stored = stored_geometries(run_dir, len(setup.reference_area))
    rows = len(steps["step"])
    contact = {c: np.full(rows, np.nan) for c in COMPONENTS}
    for k in range(rows):
        path = run.raw.contact_file(steps["step"][k])
        if stored is None or not path.is_file():
            continue
        times, geometries = stored
        geometry = geometries[int(np.argmin(np.abs(times - steps["time"][k])))]
        table = read_contacts(path)
        lw = love_weber(table, geometry, wall["area"][k])
        bs = boundary_stress(table, geometry, wall["area"][k])
        for i, c in enumerate(COMPONENTS):
            contact[c][k] = lw.flat[i]
            wall[c][k] = bs.flat[i]
    return stress_columns(steps, wall, contact,
                          fe_stress(steps, wall["area"]), eps_xx, eps_yy,
                          wall_normal_stresses(steps))


def fe_stress(steps: dict, area) -> dict:
    """The finite elements' mean stress, compression positive.

    ``-cauchy_C / area`` for each component C of ``raw/steps.csv`` (the sum
    over particles of the integral of their Cauchy stress, tension
    positive); NaN when the run has no such columns.
    """
    area = np.asarray(area, float)
    return {c: (-np.asarray(steps[f"cauchy_{c}"], float) / area
                if f"cauchy_{c}" in steps else np.full(area.shape, np.nan))
            for c in COMPONENTS}


def relative_difference(a: dict, b: dict):
    """|a - b|_F / |a|_F over the components (NaN where |a| = 0)."""
    diff = np.sqrt(sum((np.asarray(a[c]) - b[c]) ** 2 for c in COMPONENTS))
    norm = np.sqrt(sum(np.asarray(a[c]) ** 2 for c in COMPONENTS))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, diff / norm, np.nan)


def stress_columns(steps, wall, contact, fe, eps_xx, eps_yy,
                   normal_stresses) -> dict:
    """The table of :func:`stress_table` from its parts (and of a periodic
    cell's, :mod:`softpack.analysis.cell`); ``normal_stresses`` the box
    walls' ``NAME_stress`` columns."""
    wall_P, wall_q = pressure_deviator(wall["xx"], wall["yy"], wall["xy"],
                                       wall["yx"])
    contact_P, contact_q = pressure_deviator(contact["xx"], contact["yy"],
                                             contact["xy"], contact["yx"])
    fe_P, fe_q = pressure_deviator(fe["xx"], fe["yy"], fe["xy"], fe["yx"])
    return {"step": steps["step"], "time": steps["time"],
            "area": wall["area"], "eps_xx": eps_xx, "eps_yy": eps_yy,
            "eps_v": eps_xx + eps_yy, "eps_q": eps_xx - eps_yy,
            **normal_stresses,
            **{f"wall_{c}": wall[c] for c in COMPONENTS},
            "wall_P": wall_P, "wall_q": wall_q,
            **{f"contact_{c}": contact[c] for c in COMPONENTS},
            "contact_P": contact_P, "contact_q": contact_q,
            "difference": relative_difference(wall, contact),
            **{f"fe_{c}": fe[c] for c in COMPONENTS},
            "fe_P": fe_P, "fe_q": fe_q,
            "difference_wall_fe": relative_difference(wall, fe),
            "difference_contact_fe": relative_difference(contact, fe)}


def write_stress(run_dir) -> Path:
    """Write ``RUN/stress.csv`` (:func:`stress_table`); return its path."""
    return write_table(RunDirectory(run_dir).stress_csv, stress_table(run_dir),
                       COLUMNS)
