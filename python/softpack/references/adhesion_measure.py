"""What the adhesion run measures (:mod:`softpack.references.adhesion`).

From the driver's files (docs/driver_io.md), at every output row of the
pull stage:

* P, the bottom plate's force per unit length, compressive positive
  (``-bottom_fy`` of raw/steps.csv: the impulses of the output interval
  over its duration);
* the contact half-width a: a bottom contact is CLOSED when its gap at the
  start of the output step is below CLOSED_GAP x g_c: the solver holds it
  in contact (R_n + c > 0: compressive or adhesive, the theory's |x| < a;
  its gap stays at round-off, ~1e-12 m), while an open node is pulled by
  its cohesion (R_n = -c: the Dugdale zone a < |x| < c; its gap grows from
  the edge, 7e-7 m for the first open node of a 50-um mesh). The normal
  force does not tell them apart: a node at the zone's end carries only
  the part of its cohesion within g_c (docs/contact_laws.md), whose bound
  the force of a closed node may pass. On each side the edge is put midway
  between the outermost closed node and the next boundary node outward,
  in the current configuration (fields.h5), and a is half the distance of
  the two edges. Its resolution is the boundary spacing: +-h/2 per edge;
* the cohesive zone's edge c likewise from the nodes whose gap at the start
  of the step is within g_c.

The pull-off force is the least P of the pull stage; a_0 and c_0 are
interpolated linearly in P between the two output rows where P changes
sign (compressive to tensile) in the pull stage. At the loads
``HYSTERESIS_LOADS`` a and c are read on both branches, pressing and
pulling (the discrete edge's hysteresis). The theory's R is the
radius of the circle fitted to the reference boundary nodes within
``fine_arc`` of the axis.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

#: A contact is closed when its gap is below this fraction of g_c.
CLOSED_GAP = 1e-3
#: Loads (N/m) at which a is read on both branches (the hysteresis).
HYSTERESIS_LOADS = (5.0, 10.0, 15.0)


class MeasureError(RuntimeError):
    """The run's files do not give the measurement."""


def boundary(points, triangles):
    """Boundary nodes ordered counter-clockwise and their shares l_k."""
    edges = np.sort(np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]],
                               triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    nodes = np.unique(unique[counts == 1])
    centre = points.mean(axis=0)
    angle = np.arctan2(*(points[nodes] - centre).T[::-1])
    ordered = nodes[np.argsort(angle)]
    ring = points[ordered]
    seg = np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1)
    share = 0.5 * (seg + np.roll(seg, 1))
    return ordered, share


def fitted_radius(points, ordered, fit_arc) -> float:
    """Radius of the circle through the lowest boundary nodes (those within
    ``fit_arc`` of the axis), least squares on x^2 + y^2 = 2 x0 x + 2 y0 y
    + k: the meshed arc's own curvature (a .msh is scaled to its area)."""
    x, y = points[ordered].T
    near = (np.abs(x) < fit_arc) & (y < 0)
    matrix = np.column_stack([2 * x[near], 2 * y[near],
                              np.ones(near.sum())])
    (x0, y0, k), *_ = np.linalg.lstsq(matrix, x[near] ** 2 + y[near] ** 2,
                                      rcond=None)
    return float(np.sqrt(k + x0 * x0 + y0 * y0))


def _contacts(path, wall):
    rows = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if int(row["wall"]) == wall:
                rows[int(row["node"])] = (float(row["gap"]), float(row["fn"]))
    return rows


def _edge_width(x_current, ordered, inside):
    """Half the distance between the two edges of the set ``inside``
    (a mask over ``ordered``), each midway to the next node outward."""
    idx = np.flatnonzero(inside)
    if idx.size == 0:
        return 0.0
    n = len(ordered)
    # the set is one arc around the lowest node: walk both ways from it
    lowest = int(np.argmin(x_current[ordered, 1]))
    if not inside[lowest]:
        return 0.0
    right = lowest
    while inside[(right + 1) % n]:
        right = (right + 1) % n
    left = lowest
    while inside[(left - 1) % n]:
        left = (left - 1) % n
    edge_r = 0.5 * (x_current[ordered[right], 0]
                    + x_current[ordered[(right + 1) % n], 0])
    edge_l = 0.5 * (x_current[ordered[left], 0]
                    + x_current[ordered[(left - 1) % n], 0])
    return 0.5 * abs(edge_r - edge_l)


def widths(sim_dir, step, time, params, geometry):
    """(a, c) at one output row."""
    from softpack.analysis.fields import read_function

    points, ordered, _, wall = geometry
    rows = _contacts(Path(sim_dir) / "raw" / "contacts"
                     / f"step_{step:08d}.csv", wall)
    u, _ = read_function(Path(sim_dir) / "fields.h5", "displacement", time)
    x = points + u
    closed = np.zeros(len(ordered), bool)
    zone = np.zeros(len(ordered), bool)
    for i, node in enumerate(ordered):
        if node in rows:
            gap, _ = rows[node]
            zone[i] = gap <= params.cohesive_distance
            closed[i] = gap <= CLOSED_GAP * params.cohesive_distance
    return _edge_width(x, ordered, closed), _edge_width(x, ordered,
                                                        zone | closed)


def _steps(sim_dir):
    from softpack.contract.tables import read_table

    return read_table(Path(sim_dir) / "raw" / "steps.csv")


def measure(sim_dir, params) -> dict:
    """Pull-off force, a_0, c_0, the P(a) points of the pull stage, the
    widths on both branches, the energy balance, and the theory's
    numbers (:mod:`.adhesion_theory`)."""
    import json

    from softpack.analysis.fields import read_mesh

    sim_dir = Path(sim_dir)
    steps = _steps(sim_dir)
    driver = json.loads((sim_dir / "driver.json").read_text())
    points, triangles = read_mesh(sim_dir / "fields.h5")
    ordered, share = boundary(points, triangles)
    geometry = (points, ordered, share,
                [w["name"] for w in driver["walls"]].index("bottom"))
    pull = np.flatnonzero(steps["stage"] == 1)
    if pull.size < 3:
        raise MeasureError(f"{sim_dir}: no pull stage in raw/steps.csv")
    load = -steps["bottom_fy"]
    k = int(pull[np.argmin(load[pull])])
    a0, c0 = zero_load_widths(sim_dir, steps, load, pull, params, geometry)
    curve = [(float(load[i]),) + widths(sim_dir, int(steps["step"][i]),
                                        steps["time"][i], params, geometry)
             for i in pull[::2]]
    radius = fitted_radius(points, ordered, params.fine_arc)
    theory = theory_of(driver["material"]["parameters"], radius, params)
    return {
        "pull_off": float(load[k]), "pull_off_time": float(steps["time"][k]),
        "a_pull_off": widths(sim_dir, int(steps["step"][k]),
                             steps["time"][k], params, geometry)[0],
        "a0": a0, "c0": c0, "radius_fitted": radius,
        "theory": theory_numbers(theory), "balance": balance(steps),
        "branches": {f"{target:g}": branch_widths(
            sim_dir, steps, load, target, params, geometry, theory)
            for target in HYSTERESIS_LOADS},
        "curve": curve,
        "boundary_spacing_at_contact": float(np.median(
            share[np.abs(points[ordered, 0]) < params.fine_arc]))}


def theory_of(material, radius, params):
    """The line contact of the run: plane strain, E* = 4 mu (lambda + mu)
    / (lambda + 2 mu) = E / (1 - nu^2) (3 mu for lambda = 2 mu)."""
    from softpack.references.adhesion_theory import LineContact

    mu, lam = material["shear_modulus"], material["lame_lambda"]
    return LineContact(radius, 4 * mu * (lam + mu) / (lam + 2 * mu),
                       params.cohesion, params.cohesive_distance)


def zero_load_widths(sim_dir, steps, load, pull, params, geometry):
    """(a_0, c_0): interpolated in P between the two rows where the pull
    stage's load turns from compressive to tensile."""
    cross = [i for i in pull[1:] if load[i - 1] > 0 >= load[i]]
    if not cross:
        raise MeasureError(f"{sim_dir}: the load never turns tensile")
    i0, i1 = cross[0] - 1, cross[0]
    s = load[i0] / (load[i0] - load[i1])
    at = [widths(sim_dir, int(steps["step"][i]), steps["time"][i], params,
                 geometry) for i in (i0, i1)]
    return (float((1 - s) * at[0][0] + s * at[1][0]),
            float((1 - s) * at[0][1] + s * at[1][1]))


def branch_widths(sim_dir, steps, load, target, params, geometry,
                  theory) -> dict:
    """a and c at the output row nearest the load ``target`` on the
    pressing and on the pulling branch, and the theory's a and c there."""
    from scipy import optimize

    out = {}
    for name, stage in (("press", 0), ("pull", 1)):
        rows = np.flatnonzero(steps["stage"] == stage)
        i = int(rows[np.argmin(np.abs(load[rows] - target))])
        a, c = widths(sim_dir, int(steps["step"][i]), steps["time"][i],
                      params, geometry)
        out[name] = {"P": float(load[i]), "a": a, "c": c}
    a_c, _ = theory.md_pull_off()
    hi = 2 * a_c
    while theory.md_load(hi) < target:
        hi *= 2
    a = optimize.brentq(lambda x: theory.md_load(x) - target, a_c, hi)
    out["md"] = {"P": float(target), "a": a, "c": theory.zone_end(a)}
    return out


def theory_numbers(theory) -> dict:
    """Pull-off and zero-load widths of both theories."""
    a_c, p_c = theory.md_pull_off()
    j_ac, j_pc = theory.jkr_pull_off()
    a0 = theory.md_zero_load_width()
    return {"E_star": theory.modulus, "lambda": theory.maugis_lambda,
            "md_pull_off": p_c, "md_a_pull_off": a_c, "md_a0": a0,
            "md_c0": theory.zone_end(a0),
            "jkr_pull_off": j_pc, "jkr_a_pull_off": j_ac,
            "jkr_a0": theory.jkr_zero_load_width()}


def balance(steps) -> dict:
    """The energy balance at the end: residual over the largest |wall
    work| seen and over the cohesion account's scale."""
    scale = float(np.max(np.abs(steps["wall_work"])))
    return {"residual_end": float(steps["energy_residual"][-1]),
            "max_abs_residual": float(np.max(np.abs(
                steps["energy_residual"]))),
            "max_abs_wall_work": scale,
            "cohesion_end": float(steps["cohesion"][-1])}


def summary(result) -> str:
    """Lines for the terminal."""
    t = result["theory"]
    return "\n".join([
        f"pull-off P = {result['pull_off']:.4g} N/m (Maugis-Dugdale"
        f" {t['md_pull_off']:.4g}, JKR {t['jkr_pull_off']:.4g};"
        f" lambda = {t['lambda']:.3g})",
        f"zero-load a0 = {result['a0'] * 1e3:.4g} mm (MD"
        f" {t['md_a0'] * 1e3:.4g}, JKR {t['jkr_a0'] * 1e3:.4g}),"
        f" c0 = {result['c0'] * 1e3:.4g} mm (MD {t['md_c0'] * 1e3:.4g})",
        f"energy residual {result['balance']['max_abs_residual']:.3g} J/m"
        f" of |wall work| {result['balance']['max_abs_wall_work']:.3g}"])
