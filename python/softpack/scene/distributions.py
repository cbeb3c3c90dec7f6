"""Particle sizes of a species: fixed, uniform, lognormal or a given list.

A species' ``distribution`` (docs/parameters.md, ``[[species]]``) says how
its ``count`` diameters are drawn:

``fixed``      every particle ``diameter``;
``uniform``    uniform in ``[diameter_min, diameter_max]``;
``lognormal``  ``exp(N(ln diameter, sigma^2))``: median ``diameter``; when
               ``diameter_min`` or ``diameter_max`` is > 0 the draws outside
               are drawn again (a truncated lognormal);
``list``       the ``diameters`` given, in order (``count`` must be their
               number).

Draws are seeded: species ``s`` of a scene with ``[packing] seed`` uses
``numpy.random.default_rng([seed, SIZE_STREAM, s])``: a species' sizes
depend on its position in the list, not on the other species (adding one
at the end leaves the others' sizes unchanged). All lengths in metres.
"""

from __future__ import annotations

import math

import numpy as np

#: The stream of the seed sequence used for sizes (orientations use 2).
SIZE_STREAM = 1
#: A truncated lognormal gives up after this many rounds of redraws.
MAX_REDRAWS = 100


class DistributionError(ValueError):
    """A species' size keys that do not fit together; names the keys."""


def check(spec, where) -> None:
    """Refuse size keys that do not fit the species' distribution.

    Parameters
    ----------
    spec : dict
        One ``[[species]]`` table (every key present, as the config has it).
    where : str
        How to name the table in messages, e.g. ``"[species.0]"``.

    Raises
    ------
    DistributionError
    """
    kind = spec["distribution"]
    low, high = spec["diameter_min"], spec["diameter_max"]
    if kind == "uniform" and not 0 < low <= high:
        raise DistributionError(
            f"{where} distribution = \"uniform\": needs 0 < diameter_min <="
            f" diameter_max, got diameter_min = {low!r}, diameter_max ="
            f" {high!r}")
    if kind == "lognormal":
        if spec["sigma"] <= 0:
            raise DistributionError(f"{where} distribution = \"lognormal\":"
                                    " needs sigma > 0")
        if high > 0 and not low < spec["diameter"] < high:
            raise DistributionError(
                f"{where} distribution = \"lognormal\": the median diameter ="
                f" {spec['diameter']!r} must lie between the cuts"
                f" diameter_min = {low!r} and diameter_max = {high!r}")
        if low > 0 and high == 0 and not low < spec["diameter"]:
            raise DistributionError(
                f"{where} distribution = \"lognormal\": diameter_min ="
                f" {low!r} must be below the median diameter ="
                f" {spec['diameter']!r}")
    if kind == "list" and len(spec["diameters"]) != spec["count"]:
        raise DistributionError(
            f"{where} count = {spec['count']!r}: distribution = \"list\""
            f" gives {len(spec['diameters'])} diameters; count must be"
            " their number")


def bounds(spec) -> tuple[float, float]:
    """Smallest and largest diameter a species can have (m).

    A lognormal without cuts is bounded at its 1e-4 and 1 - 1e-4
    quantiles (about 3.7 sigma from the median), the range inside which
    practically all of a thousand draws fall.
    """
    kind = spec["distribution"]
    if kind == "uniform":
        return spec["diameter_min"], spec["diameter_max"]
    if kind == "list" and spec["diameters"]:
        return min(spec["diameters"]), max(spec["diameters"])
    if kind == "lognormal":
        spread = math.exp(3.719 * spec["sigma"])
        low = spec["diameter_min"] or spec["diameter"] / spread
        high = spec["diameter_max"] or spec["diameter"] * spread
        return low, high
    return spec["diameter"], spec["diameter"]


def bound_keys(spec, end) -> str:
    """The keys behind :func:`bounds`' ``end`` ("min" or "max") as a
    message names them, with their values: the key the user wrote
    (``diameter_max = 0.03``), not the diameter it bounds.
    """
    kind, low_end = spec["distribution"], end == "min"
    key = f"diameter_{end}"
    if kind == "uniform" or (kind == "lognormal" and spec[key]):
        return f"{key} = {spec[key]!r}"
    if kind == "list" and spec["diameters"]:
        pick = min if low_end else max
        return (f"diameters = {spec['diameters']!r} (the"
                f" {'smallest' if low_end else 'largest'},"
                f" {pick(spec['diameters'])!r})")
    if kind == "lognormal":  # the quantile of bounds()
        value = bounds(spec)[0 if low_end else 1]
        return (f"diameter = {spec['diameter']!r}, sigma ="
                f" {spec['sigma']!r} (lognormal without {key}: its"
                f" {'1e-4' if low_end else '1 - 1e-4'} quantile, {value:.4g}"
                " m)")
    return f"diameter = {spec['diameter']!r}"


def mean_square(spec) -> float:
    """The expected D^2 of one particle (m^2): area = pi/4 of it."""
    kind = spec["distribution"]
    if kind == "uniform":
        a, b = spec["diameter_min"], spec["diameter_max"]
        return (a * a + a * b + b * b) / 3
    if kind == "list":
        d = np.asarray(spec["diameters"], dtype=float)
        return float(np.mean(d ** 2)) if len(d) else 0.0
    if kind == "lognormal" and not (spec["diameter_min"]
                                    or spec["diameter_max"]):
        return spec["diameter"] ** 2 * math.exp(2 * spec["sigma"] ** 2)
    if kind == "lognormal":  # truncated: a quadrature of the density
        low, high = bounds(spec)
        z = np.linspace(math.log(low), math.log(high), 2001)
        weight = np.exp(-0.5 * ((z - math.log(spec["diameter"]))
                                / spec["sigma"]) ** 2)
        return float(np.trapz(weight * np.exp(2 * z), z)
                     / np.trapz(weight, z))
    return spec["diameter"] ** 2


def draw(spec, seed, index) -> np.ndarray:
    """The ``count`` diameters of species number ``index`` (m).

    Parameters
    ----------
    spec : dict
        The species (checked by :func:`check`).
    seed : int
        ``[packing] seed``.
    index : int
        The species' position in ``[[species]]``.
    """
    n = int(spec["count"])
    kind = spec["distribution"]
    rng = np.random.default_rng([int(seed), SIZE_STREAM, int(index)])
    if kind == "uniform":
        return rng.uniform(spec["diameter_min"], spec["diameter_max"], n)
    if kind == "list":
        return np.asarray(spec["diameters"], dtype=float)[:n].copy()
    if kind == "lognormal":
        return _lognormal(spec, rng, n)
    return np.full(n, float(spec["diameter"]))


def _lognormal(spec, rng, n) -> np.ndarray:
    """Lognormal draws, redrawn outside the cuts."""
    low = spec["diameter_min"] or 0.0
    high = spec["diameter_max"] or math.inf
    out = rng.lognormal(math.log(spec["diameter"]), spec["sigma"], n)
    for _ in range(MAX_REDRAWS):
        bad = (out < low) | (out > high)
        if not bad.any():
            return out
        out[bad] = rng.lognormal(math.log(spec["diameter"]), spec["sigma"],
                                 int(bad.sum()))
    raise DistributionError(
        f"[[species]] {spec.get('name', '')!r} distribution = \"lognormal\":"
        f" draws keep falling outside diameter_min = {low:g} m,"
        f" diameter_max = {high:g} m (median diameter = {spec['diameter']:g}"
        f" m, sigma = {spec['sigma']:g}): widen the cuts")
