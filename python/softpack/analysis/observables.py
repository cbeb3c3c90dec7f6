"""The paper's observables from the raw output of ``softpack-simulate``.

Reads a run directory (``docs/driver_io.md``: ``raw/steps.csv``,
``raw/particles.csv``, ``raw/contacts/step_NNNNNNNN.csv``, ``driver.json``,
and the resolved ``config.toml`` written by ``./softpack run``) and writes

``series.csv``
    one row per output step (columns in :data:`SERIES_COLUMNS`);
``particles.csv``
    one row per (output step, particle) (columns in
    :data:`PARTICLE_COLUMNS`).

Definitions (paper Secs. IV-VII, METHOD.md §4). Forces and energies of the
2D model are per unit length; the CSV files give them times the thickness H
(N and J, comparable with the experiment). Psi_p is in J/m^3.

eps
    ``-ln(1 - delta / L0)``, delta = L0 - L(t) the piston displacement, L(t)
    the distance between the box walls ``left`` and ``right`` (Eq. 11).
Phi
    ``raw/steps.csv`` ``phi``; where empty, sum of current particle areas
    over the current box area.
E/(W H L mu)
    ``E = H x strain_energy``, with the set-up's constant W, H, L (the
    initial box) and the shear modulus mu; i.e. ``strain_energy / (W L mu)``.
Psi_p, c_v(Psi_p)
    ``Psi_p = E_p / V_p0`` = particle strain energy over its reference area;
    ``c_v = sqrt(<Psi_p^2> - <Psi_p>^2) / <Psi_p>`` (Eq. 16, population
    standard deviation). ``cv_psi`` averages over all particles, as the paper
    does ("the particles of the system"); ``cv_psi_retained`` over the
    particles retained for Z.
force-bearing contact (two-node rule)
    A nodal contact is active when its normal force ``fn`` exceeds
    ``contact_force_threshold`` x the largest ``fn`` of the output step.
    A particle pair is in contact when at least two nodes of each particle
    carry force (Sec. VI). With ``rule="loaded_nodes"`` (default) the loaded
    nodes of a particle are its own active candidate nodes plus the two end
    nodes of the segment that an active candidate of the other particle
    presses on; so a pair counts when it has >= 2 distinct active candidate
    nodes, all in one direction or some in each. (``raw/contacts`` does not
    name the segment; a candidate exactly at a segment end, loading one
    node only, is not distinguished.) With ``rule="candidate_nodes"`` each
    particle needs >= 2 active candidate nodes of its own against the other.
    A particle touches a wall when >= 2 of its nodes are active against it;
    that is one contact.
unbalanced particles
    ``|sum of contact forces on the particle| > f_p*``,
    ``f_p* = unbalanced_threshold x piston force`` (default 1e-3; the paper
    0.05 % ... 0.1 %). Resultants include all contacts, active or not.
rattlers (floating particles)
    Particles that are not unbalanced and have no force-bearing contact with
    a wall or with a particle that is not unbalanced.
Z
    Retained particles: neither unbalanced nor rattlers. ``Z = (2 N_pp +
    N_pw) / N_retained``, N_pp the force-bearing contacts between retained
    particles, N_pw those between retained particles and walls;
    ``z_without_walls = 2 N_pp / N_retained`` over the same particles. NaN
    when no particle is retained.
piston force
    ``-(f . n)`` of the piston wall (``box.right``), f the force it receives,
    n its inward normal: positive in compression.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis.strain import cumulative_strain
from softpack.analysis.tables import read_table, write_table

RULES = ("loaded_nodes", "candidate_nodes")
ENERGY_COLUMNS = ("strain_energy", "kinetic_energy", "wall_work",
                  "external_work", "damping", "friction", "contact_normal",
                  "numerical", "energy_residual")
SERIES_COLUMNS = (
    "step", "time", "piston_displacement", "eps", "phi", "E_over_WHLmu",
    "z", "z_without_walls", "retained", "rattlers", "unbalanced", "cv_psi",
    "cv_psi_retained", "piston_force", *ENERGY_COLUMNS,
    "energy_residual_relative", "newton_iterations", "nlgs_iterations",
    "nlgs_error", "nlgs_converged", "contacts", "active_contacts",
    "max_penetration", "seconds")
PARTICLE_COLUMNS = (
    "step", "time", "phi", "particle", "radius", "reference_area", "area",
    "psi_p", "contacts", "wall_contacts", "z_contacts", "resultant_force",
    "unbalanced", "rattler")
CONTACT_COLUMNS = ("candidate", "node", "antagonist", "wall", "fn", "ft",
                   "fx", "fy")


# -- pure functions on arrays ------------------------------------------------

def normalised_energy(strain_energy, width, length, shear_modulus):
    """``E / (W H L mu)`` from the 2D strain energy per unit length.

    ``E = H x strain_energy``, so H cancels.
    """
    return np.asarray(strain_energy, dtype=float) / (width * length
                                                     * shear_modulus)


def coefficient_of_variation(values) -> float:
    """``sqrt(<x^2> - <x>^2) / <x>`` (paper Eq. 16); NaN if empty or zero."""
    x = np.asarray(values, dtype=float)
    if x.size == 0 or x.mean() == 0.0:
        return float("nan")
    return float(x.std() / x.mean())


def active_mask(fn, threshold) -> np.ndarray:
    """Nodal contacts whose normal force is nonzero.

    ``fn > threshold x max(fn)`` and ``fn > 0``.
    """
    fn = np.asarray(fn, dtype=float)
    if fn.size == 0:
        return np.zeros(0, dtype=bool)
    return (fn > 0.0) & (fn > threshold * fn.max())


def force_bearing_pairs(candidate, node, antagonist, active,
                        rule="loaded_nodes") -> np.ndarray:
    """Particle pairs in contact by the two-node rule (see the module doc).

    Parameters
    ----------
    candidate, node, antagonist : array_like of int
        Per nodal contact: candidate particle, its boundary node, antagonist
        particle (negative for a wall).
    active : array_like of bool
        Which nodal contacts carry a nonzero normal force.
    rule : {"loaded_nodes", "candidate_nodes"}

    Returns
    -------
    ndarray of int, shape (k, 2)
        Pairs ``(i, j)`` with ``i < j``, sorted.
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, got {rule!r}")
    c, nd, a = (np.asarray(v, dtype=np.int64) for v in
                (candidate, node, antagonist))
    keep = np.asarray(active, dtype=bool) & (a >= 0) & (a != c)
    if not keep.any():
        return np.zeros((0, 2), dtype=np.int64)
    c, nd, a = np.unique(np.stack([c[keep], nd[keep], a[keep]], axis=1),
                         axis=0).T
    low = np.minimum(c, a)
    pairs, inverse = np.unique(np.stack([low, np.maximum(c, a)], axis=1),
                               axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    from_low = np.bincount(inverse, weights=(c == low), minlength=len(pairs))
    from_high = np.bincount(inverse, weights=(c != low),
                            minlength=len(pairs))
    if rule == "loaded_nodes":
        counted = from_low + from_high >= 2
    else:
        counted = (from_low >= 2) & (from_high >= 2)
    return pairs[counted]


def force_bearing_walls(candidate, node, wall, active) -> np.ndarray:
    """``(particle, wall)`` pairs with >= 2 active nodes of the particle.

    Returns
    -------
    ndarray of int, shape (k, 2)
    """
    c, nd, w = (np.asarray(v, dtype=np.int64) for v in (candidate, node, wall))
    keep = np.asarray(active, dtype=bool) & (w >= 0)
    if not keep.any():
        return np.zeros((0, 2), dtype=np.int64)
    nodes = np.unique(np.stack([c[keep], w[keep], nd[keep]], axis=1), axis=0)
    walls, counts = np.unique(nodes[:, :2], axis=0, return_counts=True)
    return walls[counts >= 2]


def resultant_forces(candidate, antagonist, fx, fy, n_particles):
    """Sum of the contact forces on each particle, shape ``(n, 2)``.

    The candidate receives ``(fx, fy)``; a particle antagonist the opposite.
    """
    c = np.asarray(candidate, dtype=np.int64)
    a = np.asarray(antagonist, dtype=np.int64)
    f = np.stack([np.asarray(fx, float), np.asarray(fy, float)], axis=1)
    total = np.zeros((n_particles, 2))
    np.add.at(total, c, f)
    np.add.at(total, a[a >= 0], -f[a >= 0])
    return total


@dataclass(frozen=True)
class ContactNetwork:
    """Force-bearing contacts of one output step and what Z retains.

    Attributes
    ----------
    pairs, walls : ndarray of int, shape (k, 2)
        Force-bearing particle pairs ``(i, j)`` and ``(particle, wall)``.
    contacts, wall_contacts : ndarray of int, shape (n,)
        Force-bearing contacts of each particle (walls included) and those
        with walls.
    z_contacts : ndarray of int, shape (n,)
        Contacts counted in Z (0 for particles not retained).
    resultant : ndarray, shape (n,)
        Magnitude of the resultant contact force on each particle.
    unbalanced, rattler, retained : ndarray of bool, shape (n,)
    z, z_without_walls : float
    """

    pairs: np.ndarray
    walls: np.ndarray
    contacts: np.ndarray
    wall_contacts: np.ndarray
    z_contacts: np.ndarray
    resultant: np.ndarray
    unbalanced: np.ndarray
    rattler: np.ndarray
    retained: np.ndarray
    z: float
    z_without_walls: float


def contact_network(contacts: dict, n_particles: int, piston_force: float,
                    *, force_threshold=1e-4, unbalanced_threshold=1e-3,
                    rule="loaded_nodes") -> ContactNetwork:
    """Connectivity, rattlers and unbalanced particles of one output step.

    Parameters
    ----------
    contacts : dict of array_like
        Columns of :data:`CONTACT_COLUMNS` (one entry per nodal contact).
    n_particles : int
    piston_force : float
        Force on the piston in the units of the contact forces.
    force_threshold, unbalanced_threshold : float
        Relative thresholds of :func:`active_mask` and of f_p*.
    rule : {"loaded_nodes", "candidate_nodes"}
        Two-node rule (see the module doc).

    Returns
    -------
    ContactNetwork
    """
    active = active_mask(contacts["fn"], force_threshold)
    pairs = force_bearing_pairs(contacts["candidate"], contacts["node"],
                                contacts["antagonist"], active, rule)
    walls = force_bearing_walls(contacts["candidate"], contacts["node"],
                                contacts["wall"], active)
    resultant = np.linalg.norm(resultant_forces(
        contacts["candidate"], contacts["antagonist"], contacts["fx"],
        contacts["fy"], n_particles), axis=1)
    unbalanced = resultant > unbalanced_threshold * piston_force
    pair_ok = ~unbalanced[pairs[:, 0]] & ~unbalanced[pairs[:, 1]]
    wall_ok = ~unbalanced[walls[:, 0]]
    pp = _count(pairs.reshape(-1), n_particles)
    pw = _count(walls[:, 0], n_particles)
    z_pp = _count(pairs[pair_ok].reshape(-1), n_particles)
    z_pw = _count(walls[wall_ok, 0], n_particles)
    rattler = ~unbalanced & (z_pp + z_pw == 0)
    retained = ~unbalanced & ~rattler
    n = int(retained.sum())
    z_contacts = np.where(retained, z_pp + z_pw, 0)
    return ContactNetwork(
        pairs=pairs, walls=walls, contacts=pp + pw, wall_contacts=pw,
        z_contacts=z_contacts, resultant=resultant, unbalanced=unbalanced,
        rattler=rattler, retained=retained,
        z=z_contacts.sum() / n if n else float("nan"),
        z_without_walls=z_pp[retained].sum() / n if n else float("nan"))


def _count(indices, n) -> np.ndarray:
    """How many times each of ``0..n-1`` occurs in ``indices``."""
    return np.bincount(np.asarray(indices, dtype=np.int64), minlength=n)


# -- reading the raw output --------------------------------------------------

def contacts_path(run_dir, step) -> Path:
    """``raw/contacts/step_NNNNNNNN.csv`` of an output step."""
    return Path(run_dir) / "raw" / "contacts" / f"step_{int(step):08d}.csv"


def read_contacts(path) -> dict:
    """One ``raw/contacts`` file as arrays (ints for the index columns)."""
    table = read_table(path)
    missing = set(CONTACT_COLUMNS) - table.keys()
    if missing:
        raise ValueError(f"{path}: missing columns {sorted(missing)}")
    for name in ("candidate", "node", "antagonist", "wall"):
        table[name] = table[name].astype(np.int64)
    return table


@dataclass(frozen=True)
class RunSetup:
    """What post-processing needs to know about a run.

    Attributes
    ----------
    length, width, thickness, shear_modulus : float
        The set-up's constant L, W, H and mu (SI).
    walls : dict
        ``name -> (point, inward normal)`` from ``driver.json``.
    box : dict
        ``left/right/bottom/top -> wall name``; ``right`` is the piston.
    radii : ndarray
        Particle radii in id order.
    force_threshold, unbalanced_threshold : float
    rule : str
    """

    length: float
    width: float
    thickness: float
    shear_modulus: float
    walls: dict
    box: dict
    radii: np.ndarray
    force_threshold: float = 1e-4
    unbalanced_threshold: float = 1e-3
    rule: str = "loaded_nodes"


def read_setup(run_dir) -> RunSetup:
    """Read ``config.toml``, ``driver.json`` and the mesh's body table."""
    from softpack.scene.config import load_config
    from softpack.scene.mesh import output_paths, read_bodies

    run_dir = Path(run_dir)
    config = load_config(run_dir / "config.toml")
    driver = json.loads((run_dir / "driver.json").read_text())
    g, o = config["geometry"], config["observables"]
    bodies = read_bodies(output_paths(driver["mesh"])[2])
    return RunSetup(
        length=g["length"], width=g["width"], thickness=g["thickness"],
        shear_modulus=config["material"]["shear_modulus"],
        walls={w["name"]: (np.array(w["point"], float),
                           np.array(w["normal"], float))
               for w in driver["walls"]},
        box=dict(driver["box"]), radii=bodies["radius"],
        force_threshold=o["contact_force_threshold"],
        unbalanced_threshold=o["unbalanced_threshold"],
        rule=o["two_node_rule"])


# -- per-step observables and the output files --------------------------------

def box_dimensions(steps: dict, box: dict):
    """Current box length (x) and width (y) of every output row."""
    length = steps[f"{box['right']}_x"] - steps[f"{box['left']}_x"]
    width = steps[f"{box['top']}_y"] - steps[f"{box['bottom']}_y"]
    return length, width


def piston_force(steps: dict, setup: RunSetup):
    """Force on the piston, ``-(f . n)`` per unit length (N/m)."""
    name = setup.box["right"]
    normal = setup.walls[name][1]
    return -(steps[f"{name}_fx"] * normal[0] + steps[f"{name}_fy"]
             * normal[1])


def series_from_steps(steps: dict, setup: RunSetup) -> dict:
    """The ``series.csv`` columns that need only ``raw/steps.csv``.

    The contact-based columns (Z, rattlers, unbalanced, c_v) are NaN;
    ``phi`` is NaN where the driver left it empty.
    """
    h = setup.thickness
    length, _ = box_dimensions(steps, setup.box)
    delta = setup.length - length
    series = {name: np.full(len(length), np.nan) for name in SERIES_COLUMNS}
    series.update(step=steps["step"], time=steps["time"],
                  piston_displacement=delta,
                  eps=cumulative_strain(delta, setup.length),
                  E_over_WHLmu=normalised_energy(
                      steps["strain_energy"], setup.width, setup.length,
                      setup.shear_modulus),
                  piston_force=h * piston_force(steps, setup))
    if "phi" in steps:
        series["phi"] = np.array(steps["phi"], dtype=float)
    for name in ENERGY_COLUMNS:
        series[name] = h * steps[name]
    supplied = np.abs(steps["wall_work"]) + np.abs(steps["external_work"])
    series["energy_residual_relative"] = np.divide(
        steps["energy_residual"], supplied,
        out=np.full(len(supplied), np.nan), where=supplied > 0)
    for name in ("newton_iterations", "nlgs_iterations", "nlgs_error",
                 "nlgs_converged", "contacts", "active_contacts",
                 "max_penetration", "seconds"):
        series[name] = steps[name]
    return series


def series_and_particles(steps: dict, particles: dict, contacts_of,
                         setup: RunSetup):
    """Compute ``series.csv`` and ``particles.csv`` columns.

    Parameters
    ----------
    steps, particles : dict of arrays
        ``raw/steps.csv`` and ``raw/particles.csv``.
    contacts_of : callable
        ``step -> dict of contact arrays``, or ``None`` when missing.
    setup : RunSetup

    Returns
    -------
    (dict, dict)
        Columns of :data:`SERIES_COLUMNS` and :data:`PARTICLE_COLUMNS`.
    """
    n = len(setup.radii)
    series = series_from_steps(steps, setup)
    length, width = box_dimensions(steps, setup.box)
    force = piston_force(steps, setup)
    rows = []
    for k, step in enumerate(steps["step"]):
        ref, area, energy = _per_particle(particles, step, n)
        psi = energy / ref
        if not np.isfinite(series["phi"][k]):
            series["phi"][k] = area.sum() / (length[k] * width[k])
        series["cv_psi"][k] = coefficient_of_variation(psi)
        contacts = contacts_of(step)
        net = None if contacts is None else contact_network(
            contacts, n, force[k], force_threshold=setup.force_threshold,
            unbalanced_threshold=setup.unbalanced_threshold, rule=setup.rule)
        if net is not None:
            series["z"][k], series["z_without_walls"][k] = \
                net.z, net.z_without_walls
            series["retained"][k] = net.retained.sum()
            series["rattlers"][k] = net.rattler.sum()
            series["unbalanced"][k] = net.unbalanced.sum()
            series["cv_psi_retained"][k] = coefficient_of_variation(
                psi[net.retained])
        rows.append(_particle_rows(step, steps["time"][k], series["phi"][k],
                                   setup, ref, area, psi, net))
    table = {name: np.concatenate([r[name] for r in rows]) if rows
             else np.zeros(0) for name in PARTICLE_COLUMNS}
    return series, table


def _per_particle(particles, step, n):
    """Reference area, area and strain energy of each particle at a step."""
    mine = particles["step"] == step
    ids = particles["particle"][mine].astype(np.int64)
    out = []
    for name in ("reference_area", "area", "strain_energy"):
        values = np.full(n, np.nan)
        values[ids] = particles[name][mine]
        out.append(values)
    return out


def _particle_rows(step, time, phi, setup, ref, area, psi, net) -> dict:
    """Columns of ``particles.csv`` for one output step."""
    n, h = len(setup.radii), setup.thickness
    missing = np.full(n, np.nan)
    return {
        "step": np.full(n, step), "time": np.full(n, time),
        "phi": np.full(n, phi), "particle": np.arange(n),
        "radius": setup.radii, "reference_area": ref, "area": area,
        "psi_p": psi,
        "contacts": missing if net is None else net.contacts,
        "wall_contacts": missing if net is None else net.wall_contacts,
        "z_contacts": missing if net is None else net.z_contacts,
        "resultant_force": missing if net is None else h * net.resultant,
        "unbalanced": missing if net is None else net.unbalanced,
        "rattler": missing if net is None else net.rattler}


def process_run(run_dir, setup: RunSetup | None = None) -> tuple[Path, Path]:
    """Write ``particles.csv`` then ``series.csv`` of a run directory.

    ``series.csv`` is renamed into place last, so its presence means the
    post-processing finished.

    Returns
    -------
    (Path, Path)
        The series and particles files.
    """
    run_dir = Path(run_dir)
    setup = setup or read_setup(run_dir)
    steps = read_table(run_dir / "raw" / "steps.csv")
    particles = read_table(run_dir / "raw" / "particles.csv")

    def contacts_of(step):
        path = contacts_path(run_dir, step)
        return read_contacts(path) if path.is_file() else None

    series, table = series_and_particles(steps, particles, contacts_of,
                                         setup)
    particles_csv = write_table(run_dir / "particles.csv", table,
                                PARTICLE_COLUMNS)
    series_csv = write_table(run_dir / "series.csv", series, SERIES_COLUMNS)
    return series_csv, particles_csv
