"""The assembly's stress at every output step, written to ``stress.csv``.

Three estimates of the mean Cauchy stress of a box of particles (2D: per
unit length along z; 3D: the d = 3 tensors of a 3D run, below), compression
counted positive (the granular convention), A the current box area (3D:
volume) from the walls' positions in ``raw/steps.csv``:

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

Scalars (compression positive): the pressure P = tr(sigma) / d
(= -tr(sigma_tension) / d) and the deviator q = |sigma'|_d of the symmetric
part (:func:`softpack.analysis.tensors.deviator_size`: in 2D the maximum
shear stress sqrt(((sigma_xx - sigma_yy) / 2)^2 + sigma_xy^2), in 3D
sqrt(3/2 s:s)) of each estimate; the
relative difference of each pair, ``difference`` = |sigma_wall -
sigma_contact|_F / |sigma_wall|_F, ``difference_wall_fe`` = |sigma_wall -
sigma_fe|_F / |sigma_wall|_F and ``difference_contact_fe`` = |sigma_contact
- sigma_fe|_F / |sigma_contact|_F, so that a user sees when they do not
agree (they must in equilibrium: at rest, the integral of sigma over a
particle is the sum over its contacts of force (x) point, what the other
two sum). Strains from the box, compression positive: eps_xx = -ln(L /
L0), eps_yy = -ln(H / H0), volumetric eps_v = eps_xx + eps_yy, deviatoric
eps_q = eps_xx - eps_yy.

3D runs (``scene.model.dimension = 3``, docs/driver_io.md "3D runs"): the
same three estimates with d = 3, over the box's volume V = (x_right -
x_left) (y_top - y_bottom) (z_lid - z_base), from the six planes' columns
of ``raw/steps.csv`` (the wall totals: component ij = sum over the two
planes normal to j of F_i x_j / V), the node-to-face contact files (``fx,
fy, fz`` on the candidate node; its position and the tetrahedral bodies'
volume centroids from ``fields.h5``) and the nine ``cauchy_*`` integrals
(N m); forces in N, stresses in Pa. The columns have the nine components
(``xx, yy, xy, yx, zz, xz, zx, yz, zy``: the raw files' order) of each
estimate, ``volume`` in place
of ``area``, ``eps_zz`` (0 while the lid is fixed), ``eps_v`` the trace
and ``eps_q = sqrt(2/3 e:e)`` (e the deviator of the diagonal strain, the
work conjugate of q), and each of the six planes' ``NAME_stress`` (its
normal force over its current area).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis import fields as fields_h5
from softpack.analysis.connectivity import contact_forces, read_contacts
from softpack.analysis.setup import read_setup
from softpack.analysis.tensors import (axes, components, deviator_size,
                                       stack, trace_mean)
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table

#: The box walls and the axis of each one's normal.
BOX = {"left": 0, "right": 0, "bottom": 1, "top": 1}
#: A 3D box's six planes (driver/simulation/box_3d.h).
BOX_3D = {**BOX, "base": 2, "lid": 2}
#: Each axis's lower and upper wall.
SIDES = (("left", "right"), ("bottom", "top"), ("base", "lid"))

COMPONENTS = components(2)


def columns(dimension: int = 2) -> tuple:
    """The columns of ``stress.csv``, in order, for a box of that
    dimension (2D: :data:`COLUMNS`)."""
    c = ("xx", "yy", "xy", "yx")  # the raw files' order: 2D's four first
    if dimension == 3:
        c = (*c, "zz", "xz", "zx", "yz", "zy")
    a = axes(dimension)
    box = BOX if dimension == 2 else BOX_3D

    def estimate(name):
        return (*(f"{name}_{x}" for x in c), f"{name}_P", f"{name}_q")

    return ("step", "time", "area" if dimension == 2 else "volume",
            *(f"eps_{x}{x}" for x in a), "eps_v", "eps_q",
            *(f"{w}_stress" for w in box), *estimate("wall"),
            *estimate("contact"), "difference", *estimate("fe"),
            "difference_wall_fe", "difference_contact_fe")


#: The columns of a 2D ``stress.csv``, in order.
COLUMNS = columns(2)


def pressure_deviator(xx, yy, xy, yx):
    """P = tr(sigma) / 2 and q = sqrt(((xx - yy) / 2)^2 + sym(xy)^2)."""
    return scalars({"xx": xx, "yy": yy, "xy": xy, "yx": yx}, 2)


def scalars(sigma: dict, dimension: int):
    """P = tr(sigma) / d and q = |sym(sigma)'|_d of the columns ``ij`` of
    ``sigma`` (:mod:`softpack.analysis.tensors`)."""
    t = stack(sigma, dimension)
    return trace_mean(t), deviator_size(t)


def box_walls(steps: dict):
    """Current box positions (x_left, x_right, y_bottom, y_top) from steps."""
    return (np.asarray(steps["left_x"]), np.asarray(steps["right_x"]),
            np.asarray(steps["bottom_y"]), np.asarray(steps["top_y"]))


def box_extents(steps: dict, dimension: int = 2) -> list:
    """Per axis, the (lower, upper) wall positions of every row."""
    return [(np.asarray(steps[f"{lo}_{a}"]), np.asarray(steps[f"{hi}_{a}"]))
            for a, (lo, hi) in zip(axes(dimension), SIDES)]


def wall_normal_stresses(steps: dict, dimension: int = 2) -> dict:
    """``NAME_stress``: each box wall's normal force / its current length
    (3D: area).

    The force is the one the particles exert on the wall along its outward
    direction (compression positive); the length is the distance between
    the wall's two neighbours (3D: the product of the two other axes'
    extents).
    """
    extents = [hi - lo for lo, hi in box_extents(steps, dimension)]
    out = {}
    for j, (a, sides) in enumerate(zip(axes(dimension), SIDES)):
        size = 1.0
        for i, e in enumerate(extents):
            if i != j:
                size = size * e
        lo, hi = sides
        out[f"{lo}_stress"] = -np.asarray(steps[f"{lo}_f{a}"]) / size
        out[f"{hi}_stress"] = np.asarray(steps[f"{hi}_f{a}"]) / size
    return out


def wall_totals_stress(steps: dict, dimension: int = 2) -> dict:
    """The boundary stress from the wall totals (frictionless walls).

    Component ij = sum over the two walls normal to j of F_i x_j / A, F
    the force the wall receives and x_j its position (A the box area;
    3D: volume).

    Returns
    -------
    dict with ``area`` and the components ``ij`` (Pa), one value per row of
    ``raw/steps.csv``.
    """
    a = axes(dimension)
    extents = box_extents(steps, dimension)
    area = 1.0
    for lo, hi in extents:
        area = area * (hi - lo)
    out = {"area": area}
    for i in a:
        for j, (lo, hi), (wlo, whi) in zip(a, extents, SIDES):
            out[i + j] = (np.asarray(steps[f"{whi}_f{i}"]) * hi
                          + np.asarray(steps[f"{wlo}_f{i}"]) * lo) / area
    return out


@dataclass(frozen=True)
class Geometry:
    """The deformed particles at one stored time."""

    centres: np.ndarray  #: (particles, d) area (3D: volume) centroids
    current: np.ndarray  #: (nodes, d) current node positions
    nodes: list          #: per particle, its global nodes in local order


def particle_nodes(cells, body, count: int) -> list:
    """Each particle's global nodes in the driver's local order.

    The driver numbers a body's nodes by increasing global index
    (``driver/bodies/BodySet.cpp``), so local node k of particle b is the
    k-th smallest node of b's cells.
    """
    return [np.unique(cells[body == b]) for b in range(count)]


def centroids(current, cells, body, count: int) -> np.ndarray:
    """Area centroids of the deformed particles, shape ``(count, d)``
    (triangles: d = 2; tetrahedra: volume centroids, d = 3)."""
    corners = [current[cells[:, k]] for k in range(cells.shape[1])]
    d = current.shape[1]
    if d == 2:
        a, b, c = corners
        size = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                            - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
        centre = (a + b + c) / 3.0
    else:
        a = corners[0]
        size = np.abs(np.einsum("ij,ij->i", np.cross(corners[1] - a,
                                                     corners[2] - a),
                                corners[3] - a)) / 6.0
        centre = sum(corners) / 4.0
    total = np.bincount(body, weights=size, minlength=count)
    out = np.empty((count, d))
    for k in range(d):
        out[:, k] = np.bincount(body, weights=size * centre[:, k],
                                minlength=count) / total
    return out


def contact_points(contacts: dict, geometry: Geometry) -> np.ndarray:
    """Current position of each contact's candidate node, ``(contacts, d)``."""
    return np.array([geometry.current[geometry.nodes[b][k]] for b, k in
                     zip(contacts["candidate"], contacts["node"])]
                    ).reshape(-1, geometry.current.shape[1])


def love_weber(contacts: dict, geometry: Geometry, area: float):
    """Love-Weber stress (1/A) sum f (x) l, compression positive, (d, d).

    Parameters
    ----------
    contacts : dict
        One ``raw/contacts`` file (:func:`read_contacts`): ``candidate``,
        ``node``, ``antagonist`` (-1 for a wall), ``fx``, ``fy`` (and
        ``fz`` in 3D; the force on the candidate).
    geometry : Geometry
        The particles at that step.
    area : float
        The box area (3D: volume).
    """
    f = contact_forces(contacts)
    cand, ant = contacts["candidate"], contacts["antagonist"]
    centres = geometry.centres
    body = ant >= 0
    branch = centres[cand] - contact_points(contacts, geometry)
    branch[body] = centres[cand[body]] - centres[ant[body]]
    return f.T @ branch / area


def boundary_stress(contacts: dict, geometry: Geometry, area: float):
    """(1/A) sum over wall contacts of F (x) x_c, F the force on the wall."""
    wall = contacts["antagonist"] < 0
    f = -contact_forces(contacts)[wall]
    return f.T @ contact_points(contacts, geometry)[wall] / area
def stored_geometries(run_dir, count: int):
    """``(times, [Geometry])`` of every time stored in fields.h5, or None."""
    path = RunDirectory(run_dir).fields_h5
    if not path.is_file():
        return None
    times = fields_h5.stored_times(path)
    if not len(times):
        return None
    first = fields_h5.read_snapshot(path, times[0])
    if first.body is None:
        return None
    stored = fields_h5.read_displacements(path, first.points.shape[1])
    nodes = particle_nodes(first.cells, first.body, count)
    out = []
    for _, u in stored:
        current = first.points + u
        out.append(Geometry(centroids(current, first.cells, first.body,
                                      count), current, nodes))
    return np.array([t for t, _ in stored]), out


def stress_table(run_dir) -> dict:
    """Every output step's stress columns (:func:`columns`).

    Parameters
    ----------
    run_dir : path-like
        A finished run directory with a box (2D or 3D).
    """
    run = RunDirectory(run_dir)
    setup = read_setup(run_dir)
    d = setup.dimension
    steps = read_table(run.raw.steps_csv)
    wall = wall_totals_stress(steps, d)
    eps = {a + a: -np.log((hi - lo) / (hi[0] - lo[0]))
           for a, (lo, hi) in zip(axes(d), box_extents(steps, d))}
    stored = stored_geometries(run_dir, len(setup.reference_area))
    rows = len(steps["step"])
    contact = {c: np.full(rows, np.nan) for c in components(d)}
    for k in range(rows):
        path = run.raw.contact_file(steps["step"][k])
        if stored is None or not path.is_file():
            continue
        times, geometries = stored
        geometry = geometries[int(np.argmin(np.abs(times - steps["time"][k])))]
        table = read_contacts(path)
        lw = love_weber(table, geometry, wall["area"][k])
        bs = boundary_stress(table, geometry, wall["area"][k])
        for i, c in enumerate(components(d)):
            contact[c][k] = lw.flat[i]
            wall[c][k] = bs.flat[i]
    return stress_columns(steps, wall, contact,
                          fe_stress(steps, wall["area"], d), eps,
                          wall_normal_stresses(steps, d), d)


def fe_stress(steps: dict, area, dimension: int = 2) -> dict:
    """The finite elements' mean stress, compression positive.

    ``-cauchy_C / area`` (3D: volume) for each component C of
    ``raw/steps.csv`` (the sum over particles of the integral of their
    Cauchy stress, tension positive); NaN when the run has no such columns.
    """
    area = np.asarray(area, float)
    return {c: (-np.asarray(steps[f"cauchy_{c}"], float) / area
                if f"cauchy_{c}" in steps else np.full(area.shape, np.nan))
            for c in components(dimension)}


def relative_difference(a: dict, b: dict, dimension: int = 2):
    """|a - b|_F / |a|_F over the components (NaN where |a| = 0)."""
    c = components(dimension)
    diff = np.sqrt(sum((np.asarray(a[k]) - b[k]) ** 2 for k in c))
    norm = np.sqrt(sum(np.asarray(a[k]) ** 2 for k in c))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, diff / norm, np.nan)


def strain_columns(eps: dict) -> dict:
    """``eps_ii``, ``eps_v`` and ``eps_q`` from the box's diagonal strains
    ``eps = {"xx": .., "yy": ..[, "zz": ..]}`` (module doc)."""
    out = {f"eps_{k}": v for k, v in eps.items()}
    if len(eps) == 2:
        out["eps_v"] = eps["xx"] + eps["yy"]
        out["eps_q"] = eps["xx"] - eps["yy"]
        return out
    volumetric = eps["xx"] + eps["yy"] + eps["zz"]
    dev = [eps[k] - volumetric / 3.0 for k in ("xx", "yy", "zz")]
    out["eps_v"] = volumetric
    out["eps_q"] = np.sqrt(2.0 / 3.0 * sum(e * e for e in dev))
    return out


def stress_columns(steps, wall, contact, fe, eps, normal_stresses,
                   dimension: int = 2) -> dict:
    """The table of :func:`stress_table` from its parts (and of a periodic
    cell's, :mod:`softpack.analysis.cell`); ``eps`` the box's diagonal
    strains (:func:`strain_columns`), ``normal_stresses`` the box walls'
    ``NAME_stress`` columns."""
    d = dimension
    c = components(d)
    out = {"step": steps["step"], "time": steps["time"],
           "area" if d == 2 else "volume": wall["area"],
           **strain_columns(eps), **normal_stresses}
    for name, sigma in (("wall", wall), ("contact", contact), ("fe", fe)):
        out.update({f"{name}_{k}": sigma[k] for k in c})
        out[f"{name}_P"], out[f"{name}_q"] = scalars(sigma, d)
    out["difference"] = relative_difference(wall, contact, d)
    out["difference_wall_fe"] = relative_difference(wall, fe, d)
    out["difference_contact_fe"] = relative_difference(contact, fe, d)
    return out


def write_stress(run_dir) -> Path:
    """Write ``RUN/stress.csv`` (:func:`stress_table`); return its path."""
    table = stress_table(run_dir)
    return write_table(RunDirectory(run_dir).stress_csv, table,
                       columns(3 if "volume" in table else 2))
