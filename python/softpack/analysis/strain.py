"""The cumulative compressive strain of the paper (Eq. 11), written once.

``eps = -ln(1 - delta / L0)``: delta the approach of the loading walls (the
piston's displacement, or the plates' approach of a single disk), L0 their
initial distance (the box length, or the disk's diameter).
"""

from __future__ import annotations

import numpy as np


def cumulative_strain(delta, length0):
    """``eps = -ln(1 - delta / L0)`` (paper Eq. 11).

    Parameters
    ----------
    delta : array_like
        Approach of the loading walls (m), ``0 <= delta < L0``.
    length0 : float
        Their initial distance (m).

    Returns
    -------
    ndarray
        eps; exactly 0 (not -0) where delta is 0.
    """
    return 0.0 - np.log1p(-np.asarray(delta, dtype=float) / length0)


def approach(eps, length0):
    """The inverse of :func:`cumulative_strain`: ``delta = L0 (1 - e^-eps)``.

    Parameters
    ----------
    eps : array_like
    length0 : float

    Returns
    -------
    ndarray
    """
    return -length0 * np.expm1(-np.asarray(eps, dtype=float))
