"""Dense initial packings by growth: the preparation past the inflation.

:func:`softpack.scene.placement.place` inflates circles from a random
sequential addition and removes the overlaps by projected Jacobi sweeps.
For the paper's 70 + 30 disks that reaches a packing fraction of 0.78 and
stalls at 0.79 (seeds 0-3), in a jammed state: a quench jams early (an
energy minimisation of the overlaps, FIRE, after each growth step jams at
0.79 too). :func:`grow` goes further with an event-free
Lubachevsky-Stillinger-like protocol, hard-disk Monte Carlo with growth:

1. start from non-overlapping circles at a fraction ``start`` of their
   size (the random sequential addition of :mod:`.placement`);
2. one sweep: every circle proposes a random Gaussian displacement (all at
   once); a proposal that would bring it closer than the padded gap to a
   wall or to another circle (at its new or old place) is rejected
   (repeated until no conflict is left, so the state stays admissible); the
   step size adapts to keep about a third of the moves accepted;
3. after each sweep every radius grows by the same factor, by half the
   room left: the scale becomes ``s + (s_max - s) / 2``, ``s_max`` the
   largest scale at which every clearance would still be the padded gap;
   when ``s_max >= 1`` the circles take their full size and the
   preparation ends (every clearance >= the padded gap > ``gap``);
4. when the scale has grown by less than ``STALL_GROWTH`` (relative) over
   ``STALL_SWEEPS`` sweeps, the circles are jammed: :class:`Jammed` names
   the scale reached (:mod:`.placement` turns it into its PackingError).

The random motion lets the circles find room that a quench does not. The
result depends only on the generator's state.
"""

from __future__ import annotations

import numpy as np

from softpack.scene.ball_fraction import ball_fraction

#: Monte Carlo sweeps at most.
MAX_SWEEPS = 200000
#: Stall test: the scale must grow by this (relative) over STALL_SWEEPS.
STALL_GROWTH = 1e-5
STALL_SWEEPS = 2000
#: Aimed fraction of accepted moves.
ACCEPTANCE = 0.35
#: Fraction of the room taken by each growth.
GROWTH = 0.05


class Jammed(RuntimeError):
    """The circles jammed before reaching their full size."""


def grow(centres, radii, length, width, padded_gap, start, rng):
    """Grow circles from ``start`` x ``radii`` to ``radii`` (module doc).

    Parameters
    ----------
    centres : ndarray, shape (n, 2)
        Centres of circles of radii ``start * radii``, each at least
        ``padded_gap`` from the others and from the walls.
    radii : ndarray, shape (n,)
        Full radii (m).
    length, width : float
        The box (m).
    padded_gap : float
        Smallest clearance kept throughout (m).
    start : float
        Size fraction of the starting circles, in (0, 1].
    rng : numpy.random.Generator

    Returns
    -------
    ndarray, shape (n, 2)
        Centres at which the full-size circles are ``padded_gap`` apart.

    Raises
    ------
    Jammed
        When the circles jam before full size.
    """
    x = np.array(centres, dtype=float)
    radii = np.asarray(radii, dtype=float)
    scale, step = float(start), 0.1 * radii.min()
    checkpoint = scale
    for sweep in range(MAX_SWEEPS):
        room = _room(x, radii, length, width, padded_gap)
        if room < scale * (1 - 1e-12):
            raise Jammed("growth lost admissibility (a bug)")
        if room >= 1.0:
            return x
        scale += GROWTH * (room - scale)
        x, accepted = _sweep(x, radii * scale, length, width, padded_gap,
                             step, rng)
        step *= 1.1 if accepted > ACCEPTANCE else 0.9
        step = min(step, radii.min())
        if (sweep + 1) % STALL_SWEEPS == 0:
            if scale < checkpoint * (1 + STALL_GROWTH):
                break
            checkpoint = scale
    raise Jammed(
        f"growth jammed at {scale:.5f} of the particles' size (packing"
        f" fraction {scale**2 * ball_fraction(radii, (length, width)):.4f} of"
        f" {ball_fraction(radii, (length, width)):.4f}) after {sweep + 1} Monte"
        " Carlo sweeps; the box is too full")


def _pairs(x, reach):
    """Index arrays of the pairs of centres closer than ``reach``."""
    from scipy.spatial import cKDTree

    pairs = cKDTree(x).query_pairs(reach, output_type="ndarray")
    return pairs[:, 0], pairs[:, 1]


def _room(x, radii, length, width, gap) -> float:
    """The largest scale of ``radii`` keeping every clearance >= ``gap``
    (``inf`` bounded by the walls)."""
    i, j = _pairs(x, 2 * radii.max() + gap)
    d = np.hypot(*(x[i] - x[j]).T)
    walls = np.min(np.stack([x[:, 0] - gap, length - x[:, 0] - gap,
                             x[:, 1] - gap, width - x[:, 1] - gap]), axis=0)
    room = np.min(walls / radii)
    if len(i):
        room = min(room, float(np.min((d - gap) / (radii[i] + radii[j]))))
    return float(room)


def _sweep(x, radii, length, width, gap, step, rng):
    """All circles propose a move at once; conflicting ones are undone
    until none is left. Returns the centres and the accepted fraction."""
    proposal = x + step * rng.standard_normal(x.shape)
    lo = radii + gap
    moved = np.all((proposal >= lo[:, None])
                   & (proposal <= np.stack([length - lo, width - lo], 1)),
                   axis=1)
    reach = 2 * radii.max() + gap
    while moved.any():
        now = np.where(moved[:, None], proposal, x)
        i, j = _pairs(now, reach)
        d = np.hypot(*(now[i] - now[j]).T)
        bad = d - radii[i] - radii[j] < gap
        if not bad.any():
            return now, float(moved.mean())
        moved[i[bad]] = False  # undo every moved circle of a conflict
        moved[j[bad]] = False
    return x, 0.0
