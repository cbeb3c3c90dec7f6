"""Non-overlapping random placement of circles (spheres) in a box.

Every particle shape is placed through its bounding circle (see
:mod:`softpack.scene.packing` and :mod:`softpack.scene.shapes`). The box
is ``extent``: (length, width) in 2D, (length, width, height) in 3D; the
same algorithm places spheres in 3D (issue 40), with its own RSA fraction
(RSA of equal spheres saturates near 0.38) and without the growth
protocol, which is 2D.

Random sequential addition (RSA) alone saturates far below 0.75 (near 0.55
for equal disks), so :func:`place` first adds circles shrunken to a
packing fraction of ``RSA_FRACTION`` one at a time, the largest first, each
at the first free spot among a batch of random trial positions (a k-d tree
finds the placed neighbours); it then inflates them to their size in
``INFLATION_STEPS`` steps, relaxing the overlaps after each (projected
Jacobi sweeps that move every overlapping pair apart by half its shortfall
and keep every circle inside the box; the pairs from a k-d tree with a
Verlet skin, so a sweep costs O(n)). A relaxation that stalls (jammed)
starts again from a new random placement, up to ``ATTEMPTS`` times.
1,000 paper-like disks take about 3 s (bench/packing.py). With
``relax=False`` the algorithm is plain RSA of the full-size circles and
fails when the box is too full.

Measured (100 paper disks): phi = 0.748 for any seed; 0.78 works (seeds
0-2); at 0.79 and 0.80 the relaxation stalls in a jammed state (in 7-11 s).
Then :func:`place` goes on with the growth protocol of
:mod:`softpack.scene.preparation` (hard-disk Monte Carlo with slow growth),
which reaches 0.80; :class:`PackingError` is raised only when that jams too.
Configurations that the inflation places are placed exactly as before.
Relaxed circles often end exactly ``gap`` apart (or ``gap`` from a wall).
"""

from __future__ import annotations

import numpy as np

from softpack.scene.ball_fraction import ball_fraction
from softpack.scene.preparation import Jammed, grow

#: Relaxation sweeps over which the largest overlap must shrink by 10 %.
STALL_SWEEPS = 500
#: Packing fraction of the shrunken circles (spheres) placed by plain RSA
#: before they are inflated, per dimension (RSA of equal disks saturates
#: near 0.55, of equal spheres near 0.38).
RSA_FRACTION = {2: 0.35, 3: 0.25}
#: Inflation steps from the shrunken circles to their size, each followed
#: by a relaxation of the overlaps.
INFLATION_STEPS = 40
#: Size of the growth protocol's first circles relative to the inflation's
#: (plain RSA must place them all: packing fraction 0.35 x 0.8^2 = 0.22).
GROWTH_START = 0.8
#: Random starts tried before a jammed relaxation is reported.
ATTEMPTS = 10
#: Nearest placed circles examined per trial position (more: all of them).
NEIGHBOURS = 24
#: Densest packing fraction of disks in the plane (hexagonal).
HEXAGONAL_FRACTION = np.pi / (2 * np.sqrt(3))
#: The d-th root (the shrink factor of a fraction).
ROOT = {2: np.sqrt, 3: np.cbrt}


class PackingError(RuntimeError):
    """The scene cannot be built: the particles cannot be placed in the box
    (or, as :class:`softpack.scene.shapes.ShapeError`, a shape cannot be
    meshed); the message names the keys."""


def place(radii, extent, gap, rng, *, relax=True, trials=200,
          max_sweeps=20000, periodic=False) -> np.ndarray:
    """Centres of non-overlapping circles in the box (see the module doc).

    With ``periodic`` the box is a periodic cell: no walls, the distances
    between circles are those to the nearest images, the centres in
    ``[0, extent)``.

    Parameters
    ----------
    radii : ndarray, shape (n,)
        Circle radii (m), in particle order (placed largest first).
    extent : sequence of 2 or 3 floats
        The box's edges (m): (length, width) or (length, width, height).
    gap : float
        Smallest clearance (m).
    rng : numpy.random.Generator
    relax, trials, max_sweeps
        As :func:`random_packing`.
    periodic : bool
        A periodic cell instead of a box (the growth protocol is not
        periodic: a cell too full for the inflation is refused).

    Returns
    -------
    ndarray, shape (n, d)

    Raises
    ------
    PackingError
    """
    radii = np.asarray(radii, dtype=float)
    extent = tuple(float(e) for e in extent)
    order = np.argsort(-radii, kind="stable")  # largest first
    phi = ball_fraction(radii, extent)
    # with relaxation: RSA of shrunken circles, then inflated step by step
    start = (min(1.0, ROOT[len(extent)](RSA_FRACTION[len(extent)] / phi))
             if relax else 1.0)
    scales = np.linspace(start, 1.0, INFLATION_STEPS + 1)[1:]
    for attempt in range(ATTEMPTS if relax else 1):
        placed, overlapping = _sequential(radii[order] * start, extent,
                                          gap, rng, trials, relax, periodic)
        try:
            for scale in scales if start < 1.0 else [1.0] * overlapping:
                placed = _relax_overlaps(placed, radii[order] * scale,
                                         extent, gap, rng, max_sweeps,
                                         periodic)
        except PackingError as err:
            failure = (f"{len(radii)} particles (requested phi of bounding"
                       f" circles = {phi:.3f}), stuck at {scale:.3f} of their"
                       f" size in {attempt + 1} attempts: {err}")
            continue  # jammed: a new random start
        if not periodic:
            placed = _clear_of_walls(placed, radii[order], extent, gap, rng,
                                     max_sweeps)
        centres = np.empty_like(placed)
        centres[order] = placed
        return centres
    if not relax or start >= 1.0:
        raise PackingError(failure)
    if periodic or len(extent) != 2:
        raise PackingError(f"{failure}; the growth protocol that goes"
                           " further is for a 2D box only")
    placed = _grown(radii[order], start * GROWTH_START, extent, gap, rng,
                    trials, failure)
    centres = np.empty_like(placed)
    centres[order] = placed
    return centres


def _grown(radii, start, extent, gap, rng, trials, failure):
    """The growth protocol (:mod:`.preparation`) from a plain RSA of the
    shrunken circles, for a 2D box too full for the inflation."""
    try:
        placed, _ = _sequential(radii * start, extent, gap, rng, trials,
                                relax=False)
        return grow(placed, radii, *extent, _padded(gap), start, rng)
    except (PackingError, Jammed) as err:
        raise PackingError(f"{failure}; then {err}") from None


def _sequential(radii, extent, gap, rng, trials, relax, periodic=False):
    """Random sequential addition in the given order; with ``relax``, a
    circle with no free trial goes to the least-overlapping one; with
    ``periodic``, anywhere in the cell, clear of the nearest images.

    Returns the centres and whether any overlap.
    """
    d = len(extent)
    placed = np.empty((len(radii), d))
    overlapping = False
    cell = extent if periodic else None
    for k, r in enumerate(radii):
        lo = 0.0 if periodic else r + _padded(gap)
        candidates = rng.uniform((lo,) * d, tuple(e - lo for e in extent),
                                 size=(trials, d))
        clearance = _clearance_to(candidates, r, placed[:k], radii[:k],
                                  _padded(gap), cell)
        free = np.flatnonzero(clearance >= 0.0)
        if not len(free) and not relax:
            raise PackingError(
                f"random sequential addition placed {k} of {len(radii)}"
                f" particles (phi = {ball_fraction(radii, extent):.3f} of"
                f" bounding circles); no free spot for a circle of diameter"
                f" {2 * r:g} m in {trials} trials")
        pick = int(free[0]) if len(free) else int(np.argmax(clearance))
        overlapping |= not len(free)
        placed[k] = candidates[pick]
    return placed, overlapping


def _padded(gap) -> float:
    """Clearance aimed at so that ``gap`` holds despite rounding."""
    return 1.05 * gap + 1e-9


def _norm(diff) -> np.ndarray:
    """|diff| along the last axis (np.hypot in 2D: the placements made
    before 3D existed stay the same to the bit)."""
    if diff.shape[-1] == 2:
        return np.hypot(diff[..., 0], diff[..., 1])
    return np.linalg.norm(diff, axis=-1)


def _clearance_to(candidates, r, centres, radii, gap,
                  cell=None) -> np.ndarray:
    """For each candidate centre, the smallest clearance minus ``gap``
    (to the nearest images in a periodic ``cell`` = the box's extent).

    Only circles whose centres lie within ``r + max(radii) + gap`` can make
    it negative: a k-d tree finds the nearest ``NEIGHBOURS`` of each
    candidate, and a candidate with more than that many within reach is
    checked against all the circles (exact in every case).
    """
    if len(centres) == 0:
        return np.zeros(len(candidates))
    from scipy.spatial import cKDTree

    reach = r + radii.max() + gap
    k = min(NEIGHBOURS, len(centres))
    d, index = cKDTree(centres, boxsize=cell).query(
        candidates, k=[*range(1, k + 1)], distance_upper_bound=reach)
    found = np.isfinite(d)
    index = np.where(found, index, 0)
    clearance = np.where(found, d - r - radii[index] - gap, np.inf)
    out = clearance.min(axis=1)
    crowded = found[:, -1] & (k < len(centres))
    if crowded.any():  # the k nearest may miss a larger circle farther out
        diff = _nearest_image(candidates[crowded, None, :]
                              - centres[None, :, :], cell)
        out[crowded] = (_norm(diff) - r - radii - gap).min(axis=1)
    return np.minimum(out, np.inf)


def _relax_overlaps(centres, radii, extent, gap, rng, max_sweeps,
                    periodic=False):
    """Move circles apart until every pair is at least ``gap`` apart.

    Each sweep moves both circles of every pair closer than the target
    separation apart by half the shortfall (projected Jacobi iteration),
    then projects the centres back into the admissible box (in a periodic
    cell: wraps them into it, the pairs' distances to the nearest image).  The target
    clearance (:func:`_padded`) is slightly above ``gap`` so that the
    iteration ends with a strictly admissible configuration.  The pairs
    come from a k-d tree within the largest target distance plus a skin,
    and are searched again once a circle has moved half the skin (a
    Verlet list: no pair that can overlap is missed).
    """
    from scipy.spatial import cKDTree

    x = centres.copy()
    n, d = x.shape
    cell = extent if periodic else None
    skin = 0.2 * radii.min()
    reach = 2 * radii.max() + _padded(gap) + skin
    lo = radii + _padded(gap)
    hi = np.stack([e - lo for e in extent], axis=1)
    checkpoint, moved = np.inf, np.inf
    for sweep in range(max_sweeps):
        if moved > 0.5 * skin:
            pairs = cKDTree(x, boxsize=cell).query_pairs(
                reach, output_type="ndarray")
            i, j = pairs[:, 0], pairs[:, 1]
            target = radii[i] + radii[j] + _padded(gap)
            listed, moved = x.copy(), 0.0
        diff = _nearest_image(x[i] - x[j], cell)
        distance = _norm(diff)
        if np.all(distance - radii[i] - radii[j] >= gap):
            return x
        if np.any(distance == 0.0):  # coincident: a random direction
            x += 1e-9 * rng.standard_normal(x.shape)
            continue
        shortfall = np.maximum(target - distance, 0.0)
        if sweep % STALL_SWEEPS == 0:
            if shortfall.max() > 0.9 * checkpoint:
                break  # stalled: the overlaps no longer shrink
            checkpoint = shortfall.max()
        push = (0.5 * shortfall / distance)[:, None] * diff
        move = np.zeros_like(x)
        for axis in range(d):
            move[:, axis] = (np.bincount(i, push[:, axis], n)
                             - np.bincount(j, push[:, axis], n))
        x = (_wrapped(x + move, cell) if periodic
             else np.clip(x + move, lo[:, None], hi))
        moved = np.abs(_nearest_image(x - listed, cell)).max() * np.sqrt(d)
    raise PackingError(
        f"could not remove the overlaps of {n} circles (phi ="
        f" {ball_fraction(radii, extent):.3f} in a"
        f" {' x '.join(f'{e:g}' for e in extent)} m box) in {sweep + 1}"
        " relaxation sweeps; the box is too full")


def _clear_of_walls(x, radii, extent, gap, rng, max_sweeps):
    """The centres, each at least its radius plus the clearance from the
    walls: the relaxation puts into the box only when it moves circles, so
    circles grown in place with no pair left overlapping (a single one, a
    dilute box) can end too close to a wall, or through it."""
    lo = radii + _padded(gap)
    hi = np.stack([e - lo for e in extent], axis=1)
    if np.all(x >= lo[:, None]) and np.all(x <= hi):
        return x
    return _relax_overlaps(np.clip(x, lo[:, None], hi), radii, extent, gap,
                           rng, max_sweeps)


def _nearest_image(diff, cell):
    """Differences of positions to the nearest image in a periodic ``cell``
    = the box's extent (unchanged without a cell)."""
    if cell is None:
        return diff
    box = np.asarray(cell)
    return diff - box * np.round(diff / box)


def _wrapped(x, cell):
    """Positions wrapped into ``[0, extent)``."""
    box = np.asarray(cell)
    x = np.mod(x, box)
    return np.where(x >= box, 0.0, x)  # mod of a tiny negative: the length
