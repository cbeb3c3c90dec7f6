"""The contact network of one output step: the paper's Z (Sec. VI).

Reads ``raw/contacts/step_NNNNNNNN.csv`` (one row per nodal contact:
``candidate`` particle, its boundary ``node``, ``antagonist`` particle or -1,
``wall`` index or -1, forces ``fn``, ``ft``, ``fx``, ``fy`` per unit length)
and applies the rules of :class:`softpack.analysis.setup.Rules`. A 3D run's
files have node-to-face contacts (``candidate`` body and its boundary
``node``, the ``antagonist`` body's boundary triangle or a ``wall`` of the
box's six planes; ``fn, ft1, ft2, fx, fy, fz``, N): the same rules apply to
them unchanged, a node being a node and the antagonist's face in place of
its segment (``loaded_nodes`` counts the distinct active candidate nodes of
the pair, from either body, so a pair of bodies is in contact when at least
two of their nodes carry force between them; a face touched by one node
does not count its three nodes), and the resultants have three components.

force-bearing contact (two-node rule)
    A nodal contact is active when its normal force ``fn`` exceeds
    ``contact_force_threshold`` x the largest ``fn`` of the output step.
    Under a cohesive law or a bond ``fn`` may be tensile (negative); with
    ``tensile_contacts = "bearing"`` (the default) a tensile force bears
    load as a compressive one does (``|fn|`` against the largest ``|fn|``:
    the contact constrains both particles whichever its sign), with
    ``"ignored"`` only compressive forces count. Without a tensile force
    both readings are the same.
    A particle pair is in contact when at least two nodes of each particle
    carry force (Sec. VI). With ``rule="loaded_nodes"`` the loaded nodes of
    a particle are its own active candidate nodes plus the two end nodes of
    the segment that an active candidate of the other particle presses on;
    so a pair counts when it has >= 2 distinct active candidate nodes, all
    in one direction or some in each. (A candidate exactly at a segment
    end, loading one node only, is not distinguished.) With
    ``rule="candidate_nodes"`` each particle needs >= 2 active candidate
    nodes of its own against the other. A particle touches a wall when
    >= 2 of its nodes are active against it; that is one contact.
unbalanced particles
    ``|sum of contact forces on the particle| > f_p*``,
    ``f_p* = unbalanced_threshold x f`` (the paper: 0.05 % ... 0.1 % of "the
    total compressive force f of the system"). Resultants include all
    contacts, active or not. Two readings of f (``unbalanced_reference``):
    ``"total_normal_force"`` (the default), the sum of the normal forces of
    all nodal contacts of the output step (particle-particle and
    particle-wall); ``"piston_force"``, the force on the piston. The
    default readings are those under which Z does not change between
    f_p* = 0.05 % and 0.1 % on the paper's runs (docs/paper/
    exclusion_rule.md).
excluded particles' contacts (``excluded_contacts``)
    ``"kept"`` (the default): the balanced neighbour of an unbalanced
    particle keeps their contact (only the unbalanced particle leaves the
    average); ``"dropped"``: the contact leaves the neighbour's count too.
rattlers (floating particles)
    Particles that are not unbalanced and have no counted force-bearing
    contact (with a wall, or with a particle under the reading above).
Z
    Retained particles: neither unbalanced nor rattlers. ``Z = sum of the
    counted contacts of the retained particles / N_retained``; with
    ``"dropped"`` this is ``(2 N_pp + N_pw) / N_retained``, N_pp the
    force-bearing contacts between retained particles, N_pw those between
    retained particles and walls. ``z_without_walls`` counts only the
    particle contacts, over the same particles. Undefined (NaN) when no
    particle is retained; :func:`z_undefined_code` says why
    (:data:`Z_UNDEFINED`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softpack.analysis.setup import Rules
from softpack.contract.tables import read_table

RULES = ("loaded_nodes", "candidate_nodes")
#: Readings of the paper's f in f_p* (``unbalanced_reference``).
REFERENCES = ("piston_force", "total_normal_force")
#: What an unbalanced particle's contacts do for its neighbours.
EXCLUDED_CONTACTS = ("dropped", "kept")
#: Whether a tensile normal force bears load (``tensile_contacts``).
TENSILE_CONTACTS = ("bearing", "ignored")
#: Why Z is undefined (``series.csv`` column ``z_undefined``; 0: defined).
Z_UNDEFINED = {
    1: "no raw/contacts file for this output step",
    2: "no force-bearing contact: every particle floats (a rattler)",
    3: "every particle is unbalanced",
    4: "every particle is unbalanced or a rattler"}
CONTACT_COLUMNS = ("candidate", "node", "antagonist", "wall", "fn", "ft",
                   "fx", "fy")
#: The columns of a 3D run's contact files read here (docs/driver_io.md,
#: "3D runs": node-to-face contacts, the force in the frame (n, t1, t2)
#: and in world components).
CONTACT_COLUMNS_3D = ("candidate", "node", "antagonist", "wall", "fn",
                      "ft1", "ft2", "fx", "fy", "fz")


def active_mask(fn, threshold, tensile="ignored") -> np.ndarray:
    """Nodal contacts whose normal force is nonzero.

    ``fn > threshold x max(fn)`` and ``fn > 0``; with ``tensile =
    "bearing"``, ``|fn|`` in place of ``fn``.
    """
    fn = _bearing(fn, tensile)
    if fn.size == 0:
        return np.zeros(0, dtype=bool)
    return (fn > 0.0) & (fn > threshold * fn.max())


def force_bearing_pairs(candidate, node, antagonist, active,
                        rule) -> np.ndarray:
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


def contact_forces(contacts: dict) -> np.ndarray:
    """The force on each contact's candidate, shape ``(contacts, d)``: the
    columns ``fx, fy`` (and ``fz`` in a 3D run's files)."""
    names = ("fx", "fy", "fz") if "fz" in contacts else ("fx", "fy")
    return np.stack([np.asarray(contacts[k], float) for k in names],
                    axis=1)


def resultant_forces(candidate, antagonist, fx, fy, n_particles, fz=None):
    """Sum of the contact forces on each particle, shape ``(n, d)``, d = 2,
    or 3 with ``fz``.

    The candidate receives ``(fx, fy[, fz])``; a particle antagonist the
    opposite.
    """
    c = np.asarray(candidate, dtype=np.int64)
    a = np.asarray(antagonist, dtype=np.int64)
    f = contact_forces({"fx": fx, "fy": fy} if fz is None
                       else {"fx": fx, "fy": fy, "fz": fz})
    total = np.zeros((n_particles, f.shape[1]))
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
                    rules: Rules, body_forces=None,
                    uncounted_walls=()) -> ContactNetwork:
    """Connectivity, rattlers and unbalanced particles of one output step.

    Parameters
    ----------
    contacts : dict of array_like
        Columns of :data:`CONTACT_COLUMNS` (one entry per nodal contact).
    n_particles : int
    piston_force : float
        Force on the piston in the units of the contact forces.
    rules : Rules
        Relative thresholds of :func:`active_mask` and of f_p*, the
        two-node rule, the reading of f and of the excluded particles'
        contacts (see the module doc).
    body_forces : array_like, shape (n_particles, d), optional
        Forces on the particles besides the contacts (their weight under
        [gravity]), added to each resultant: a particle resting on others
        is balanced.
    uncounted_walls : sequence of int, optional
        Walls whose contacts are no contacts for Z (a 3D box's base and
        lid for standing cylinders: out of the 2D model's plane); their
        forces still enter the resultants and the reference force.

    Returns
    -------
    ContactNetwork
    """
    tensile = _rule(rules, "tensile_contacts")
    active = active_mask(contacts["fn"], rules.force_threshold, tensile)
    pairs = force_bearing_pairs(contacts["candidate"], contacts["node"],
                                contacts["antagonist"], active, rules.rule)
    walls = force_bearing_walls(contacts["candidate"], contacts["node"],
                                contacts["wall"], active)
    if len(uncounted_walls):
        walls = walls[~np.isin(walls[:, 1], uncounted_walls)]
    resultant = resultant_forces(contacts["candidate"],
                                 contacts["antagonist"], contacts["fx"],
                                 contacts["fy"], n_particles,
                                 contacts.get("fz"))
    if body_forces is not None:
        resultant = resultant + np.asarray(body_forces, float)
    resultant = np.linalg.norm(resultant, axis=1)
    reference = reference_force(contacts, piston_force,
                                _rule(rules, "unbalanced_reference"),
                                tensile)
    unbalanced = resultant > rules.unbalanced_threshold * reference
    if _rule(rules, "excluded_contacts") == "kept":
        pair_ok = np.ones(len(pairs), dtype=bool)
        wall_ok = np.ones(len(walls), dtype=bool)
    else:
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


def reference_force(contacts: dict, piston_force: float,
                    reference: str, tensile: str = "ignored") -> float:
    """The f of f_p* = unbalanced_threshold x f under a reading.

    ``"piston_force"``: ``piston_force``; ``"total_normal_force"``: the sum
    of the positive normal forces of all nodal contacts (of their
    magnitudes with ``tensile = "bearing"``).
    """
    if reference == "piston_force":
        return float(piston_force)
    if reference == "total_normal_force":
        return float(np.sum(np.maximum(_bearing(contacts["fn"], tensile),
                                       0.0)))
    raise ValueError(f"unbalanced_reference must be one of {REFERENCES},"
                     f" got {reference!r}")


def z_undefined_code(network) -> int:
    """Why Z is undefined (a key of :data:`Z_UNDEFINED`), 0 when it is
    defined; ``network`` None means no contacts file."""
    if network is None:
        return 1
    if network.retained.any():
        return 0
    if not network.unbalanced.any():
        return 2
    return 3 if network.unbalanced.all() else 4


def z_change(phi, z_a, z_b, phi_range=None) -> float:
    """The insensitivity criterion: max |Z_a - Z_b| over the output steps
    (within ``phi_range = (lo, hi)`` if given) where both are defined.

    NaN when there is no such step.
    """
    phi, z_a, z_b = (np.asarray(v, dtype=float) for v in (phi, z_a, z_b))
    keep = np.isfinite(z_a) & np.isfinite(z_b)
    if phi_range is not None:
        keep &= (phi >= phi_range[0]) & (phi <= phi_range[1])
    if not keep.any():
        return float("nan")
    return float(np.max(np.abs(z_a[keep] - z_b[keep])))


def _bearing(fn, tensile) -> np.ndarray:
    """The normal forces as they bear load under ``tensile_contacts``."""
    if tensile not in TENSILE_CONTACTS:
        raise ValueError(f"tensile_contacts must be one of"
                         f" {TENSILE_CONTACTS}, got {tensile!r}")
    fn = np.asarray(fn, dtype=float)
    return np.abs(fn) if tensile == "bearing" else fn


_READINGS = {"unbalanced_reference": REFERENCES,
             "excluded_contacts": EXCLUDED_CONTACTS,
             "tensile_contacts": TENSILE_CONTACTS}


def _rule(rules, name):
    """A reading of ``rules``, checked."""
    value = getattr(rules, name)
    allowed = _READINGS[name]
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    return value


def _count(indices, n) -> np.ndarray:
    """How many times each of ``0..n-1`` occurs in ``indices``."""
    return np.bincount(np.asarray(indices, dtype=np.int64), minlength=n)


def read_contacts(path) -> dict:
    """One ``raw/contacts`` file as arrays (ints for the index columns)."""
    table = read_table(path)
    required = CONTACT_COLUMNS_3D if "fz" in table else CONTACT_COLUMNS
    missing = set(required) - table.keys()
    if missing:
        raise ValueError(f"{path}: missing columns {sorted(missing)}")
    for name in ("candidate", "node", "antagonist", "wall"):
        table[name] = table[name].astype(np.int64)
    return table
