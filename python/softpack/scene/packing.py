"""Random initial packings of particles in a rectangular box.

The paper's assembly is 70 disks of diameter D1 = 20 mm and 30 disks of
D2 = 30 mm at random, non-overlapping positions in a box of L x W =
286 x 202 mm (x along the piston axis), an initial packing fraction of about
0.75.  The box spans ``(0, 0)`` to ``(length, width)``; all lengths are in
metres.  Any particle shape is placed through its bounding circle (radius =
the largest distance of its boundary from its centre, see
:mod:`softpack.scene.shapes`): circles at least ``gap`` apart keep the true
shapes at least ``gap`` apart.

The placement itself is :func:`softpack.scene.placement.place` (RSA of
shrunken circles, then inflation with relaxation of the overlaps; 1,000
particles in a few seconds; past about Phi = 0.78 the growth protocol of
:mod:`softpack.scene.preparation`). The box sets the initial packing
fraction: with the particles' sizes fixed, Phi0 = their area / (L W), so a
requested Phi0 ([packing] initial_packing_fraction) is a box length L, the
piston's start.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softpack.scene.ball_fraction import ball_fraction
from softpack.scene.placement import (HEXAGONAL_FRACTION, PackingError,
                                      _padded, place)
from softpack.contract.schema import load_schema



def _schema_defaults() -> dict:
    """The paper's set-up as the schema's defaults (metres)."""
    schema = load_schema()
    species = schema["species"].default_list
    box, packing = schema["box"].parameters, schema["packing"].parameters
    return {"counts": tuple(int(s["count"]) for s in species),
            "diameters": tuple(float(s["diameter"]) for s in species),
            "length": box["length"].default, "width": box["width"].default,
            "gap": packing["gap"].default}


_DEFAULTS = _schema_defaults()
#: The paper's set-up (schema/parameters.toml defaults, metres).
PAPER_COUNTS = _DEFAULTS["counts"]
PAPER_DIAMETERS = _DEFAULTS["diameters"]
PAPER_LENGTH = _DEFAULTS["length"]
PAPER_WIDTH = _DEFAULTS["width"]
#: Default clearance between disks and between disks and walls (metres).
DEFAULT_GAP = _DEFAULTS["gap"]

CSV_COLUMNS = "particle,x,y,radius,area"


@dataclass(frozen=True)
class Packing:
    """Disks in the box ``[0, length] x [0, width]``.

    Parameters
    ----------
    centres : ndarray, shape (n, 2)
        Disk centres (m).
    radii : ndarray, shape (n,)
        Disk radii (m).
    length, width : float
        Box dimensions along x (piston axis) and y (m).
    seed : int or None
        Seed of the generator that produced the packing, if any.
    ids : ndarray of int, shape (n,)
        Particle ids; ``0..n-1`` when not given.
    shape_areas : ndarray, shape (n,), optional
        Each particle's area (m^2) when it is not a disk of radius
        ``radii`` (which are then the bounding radii).
    """

    centres: np.ndarray
    radii: np.ndarray
    length: float
    width: float
    seed: int | None = None
    ids: np.ndarray = field(default=None)
    shape_areas: np.ndarray = field(default=None)

    def __post_init__(self):
        centres = np.array(self.centres, dtype=float).reshape(-1, 2)
        radii = np.array(self.radii, dtype=float).reshape(-1)
        if len(centres) != len(radii):
            raise ValueError(
                f"{len(centres)} centres but {len(radii)} radii")
        ids = (np.arange(len(radii)) if self.ids is None
               else np.array(self.ids, dtype=int).reshape(-1))
        if len(ids) != len(radii):
            raise ValueError(f"{len(ids)} ids but {len(radii)} radii")
        object.__setattr__(self, "centres", centres)
        object.__setattr__(self, "radii", radii)
        object.__setattr__(self, "ids", ids)
        if self.shape_areas is not None:
            areas = np.array(self.shape_areas, dtype=float).reshape(-1)
            if len(areas) != len(radii):
                raise ValueError(f"{len(areas)} areas but {len(radii)} radii")
            object.__setattr__(self, "shape_areas", areas)
        object.__setattr__(self, "length", float(self.length))
        object.__setattr__(self, "width", float(self.width))

    @property
    def n_particles(self) -> int:
        """Number of disks."""
        return len(self.radii)

    @property
    def areas(self) -> np.ndarray:
        """Particle areas: ``shape_areas``, else the disks' ``pi r^2``
        (m^2)."""
        if self.shape_areas is not None:
            return self.shape_areas
        return np.pi * self.radii**2

    @property
    def packing_fraction(self) -> float:
        """Initial packing fraction ``sum(pi r^2) / (L W)`` (NaN without
        a box, ``length = width = 0``)."""
        if not self.length * self.width > 0:
            return float("nan")
        return float(self.areas.sum() / (self.length * self.width))

    def min_particle_gap(self) -> float:
        """Smallest surface-to-surface distance between two disks (m).

        Negative when two disks overlap; ``inf`` for fewer than two disks.
        """
        if self.n_particles < 2:
            return float("inf")
        clearance = _pair_clearance(self.centres, self.radii)
        return float(clearance[np.triu_indices(self.n_particles, 1)].min())

    def min_wall_gap(self) -> float:
        """Smallest distance from a disk to one of the four walls (m).

        Negative when a disk crosses a wall.
        """
        x, y = self.centres.T
        r = self.radii
        return float(np.min([x - r, self.length - x - r,
                             y - r, self.width - y - r]))

    def to_csv(self, path) -> Path:
        """Write the packing to ``path`` atomically.

        The file starts with ``# key=value`` lines (``length``, ``width``,
        ``seed``, ``packing_fraction``) followed by the header
        ``particle,x,y,radius,area`` and one row per disk, in SI units.

        Returns
        -------
        Path
            The path written.
        """
        path = Path(path)
        lines = ["# softpack packing (SI units)",
                 f"# length={self.length!r}",
                 f"# width={self.width!r}",
                 f"# seed={'' if self.seed is None else int(self.seed)}",
                 f"# packing_fraction={self.packing_fraction!r}",
                 CSV_COLUMNS]
        for i, (x, y), r, a in zip(self.ids, self.centres, self.radii,
                                   self.areas):
            lines.append(f"{i},{x!r},{y!r},{r!r},{a!r}")
        tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
        try:
            tmp.write_text("\n".join(lines) + "\n")
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)
        return path

    @classmethod
    def from_csv(cls, path) -> "Packing":
        """Read a packing written by :meth:`to_csv`."""
        meta, rows = {}, []
        with open(path) as f:
            for line in f:
                line = line.strip()
                if line.startswith("#"):
                    key, sep, value = line[1:].partition("=")
                    if sep:
                        meta[key.strip()] = value.strip()
                elif line and line != CSV_COLUMNS:
                    rows.append([float(v) for v in line.split(",")])
        missing = {"length", "width"} - meta.keys()
        if missing:
            raise ValueError(f"{path}: missing {sorted(missing)} header lines")
        data = np.array(rows, dtype=float).reshape(-1, 5)
        seed = meta.get("seed", "")
        disks = np.allclose(data[:, 4], np.pi * data[:, 3]**2, rtol=1e-12)
        return cls(centres=data[:, 1:3], radii=data[:, 3],
                   length=float(meta["length"]), width=float(meta["width"]),
                   seed=int(seed) if seed else None,
                   ids=data[:, 0].astype(int),
                   shape_areas=None if disks else data[:, 4])


def random_packing(seed: int, *, counts=PAPER_COUNTS,
                   diameters=PAPER_DIAMETERS, length: float = PAPER_LENGTH,
                   width: float = PAPER_WIDTH, gap: float = DEFAULT_GAP,
                   relax: bool = True, trials: int = 200,
                   max_sweeps: int = 20000) -> Packing:
    """Random non-overlapping disks of a few sizes in a box.

    Parameters
    ----------
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same
        packing.
    counts, diameters : sequence of int, sequence of float
        Number and diameter (m) of the disks of each species.  Particle ids
        follow this order (the paper's default: ids 0-69 have D1 = 20 mm,
        ids 70-99 have D2 = 30 mm).
    length, width : float
        Box dimensions (m); the box spans ``(0, 0)`` to ``(length, width)``.
    gap : float
        Minimum clearance between two disks and between a disk and a wall (m).
    relax : bool
        Relax overlaps when random trials find no free spot; without it the
        algorithm is plain random sequential addition.
    trials : int
        Random trial positions drawn for each disk.
    max_sweeps : int
        Limit on the relaxation sweeps after one insertion; the relaxation
        also stops when the largest overlap shrinks by less than 10 % in
        ``STALL_SWEEPS`` sweeps.

    Returns
    -------
    Packing

    Raises
    ------
    ValueError
        On inconsistent or non-physical arguments.
    PackingError
        When the disks cannot be placed.
    """
    radii = _check_arguments(seed, counts, diameters, length, width, gap,
                             trials, max_sweeps)
    centres = place(radii, (length, width), gap, np.random.default_rng(seed),
                    relax=relax, trials=trials, max_sweeps=max_sweeps)
    return Packing(centres=centres, radii=radii, length=length, width=width,
                   seed=seed)


def scene_packing(config, radii, areas=None) -> Packing:
    """The packing of a configuration's particles (body order).

    With ``[box] enabled`` the circles of ``radii`` placed by :func:`place`
    (seed and gap from ``[packing]``); without a box the scene holds one
    particle, at the origin (the configuration refuses more), and the
    packing's box is ``length = width = 0``.

    Parameters
    ----------
    config : Config
    radii : ndarray, shape (n,)
        Each particle's bounding radius (m), in body order.
    areas : ndarray, shape (n,), optional
        Each particle's area when the particles are not all disks.

    Raises
    ------
    PackingError
        When the particles cannot be placed; names the keys.
    """
    radii = np.asarray(radii, dtype=float)
    box, seed = config["box"], config["packing"]["seed"]
    if config["cell"]["enabled"]:
        return _cell_packing(config, radii, areas)
    if not box["enabled"]:
        return Packing(centres=np.zeros((1, 2)), radii=radii[:1],
                       length=0.0, width=0.0, shape_areas=None if areas is
                       None else np.asarray(areas)[:1])
    length, width, gap = box["length"], box["width"], config["packing"]["gap"]
    keys = ("([[species]] count, diameter and shape, [box] length and width,"
            " [packing] gap)")
    if radii.max() + _padded(gap) >= min(length, width) / 2:
        raise PackingError(
            f"a particle of bounding diameter {2 * radii.max():g} m does not"
            f" fit in the {length} x {width} m box {keys}")
    _check_requested_fraction(config, radii if areas is None else None,
                              areas)
    phi = ball_fraction(radii, (length, width))
    if phi >= HEXAGONAL_FRACTION:
        raise PackingError(
            f"the particles' bounding circles would fill {phi:.3f} of the box,"
            f" more than hexagonal disks ({HEXAGONAL_FRACTION:.3f}): they"
            f" cannot fit {keys}; placement uses bounding circles, so a"
            " non-disk shape needs a lower packing fraction")
    try:
        centres = place(radii, (length, width), gap,
                        np.random.default_rng(seed))
    except PackingError as err:
        raise PackingError(f"{err} {keys}") from None
    return Packing(centres=centres, radii=radii, length=length, width=width,
                   seed=seed, shape_areas=areas)


def _cell_packing(config, radii, areas) -> Packing:
    """:func:`scene_packing` in a periodic cell ([cell] enabled): the
    circles placed with periodic distances (its ``length`` and ``width``
    the cell's edges)."""
    length, width = cell_sides(config["cell"])
    gap, seed = config["packing"]["gap"], config["packing"]["seed"]
    keys = ("([[species]] count, diameter and shape, [cell] a1 and a2,"
            " [packing] gap)")
    phi = ball_fraction(radii, (length, width))
    if phi >= HEXAGONAL_FRACTION:
        raise PackingError(
            f"the particles' bounding circles would fill {phi:.3f} of the"
            f" cell, more than hexagonal disks ({HEXAGONAL_FRACTION:.3f})"
            f" {keys}")
    try:
        centres = place(radii, (length, width), gap,
                        np.random.default_rng(seed), periodic=True)
    except PackingError as err:
        raise PackingError(f"{err} {keys}") from None
    return Packing(centres=centres, radii=radii, length=length, width=width,
                   seed=seed, shape_areas=areas)


def cell_sides(cell) -> tuple:
    """The sides (length along x, width along y) of a rectangular initial
    cell ([cell] a1 along x, a2 along y).

    Raises
    ------
    PackingError
        When the cell is not rectangular (the placement needs it).
    """
    (a1x, a1y), (a2x, a2y) = cell["a1"], cell["a2"]
    if a1y != 0 or a2x != 0 or not (a1x > 0 and a2y > 0):
        raise PackingError(
            f"[cell] a1 = {list(cell['a1'])}, a2 = {list(cell['a2'])}: the"
            " random placement needs a rectangular initial cell, a1 = [L, 0]"
            " and a2 = [0, W] with L, W > 0")
    return float(a1x), float(a2y)


#: How far the box's packing fraction may be from [packing]
#: initial_packing_fraction (a box length typed to 0.01 mm is within).
REQUESTED_FRACTION_TOLERANCE = 1e-4


def _check_requested_fraction(config, radii, areas) -> None:
    """Refuse a [packing] initial_packing_fraction that the box does not
    give, naming the box length that does (the piston's start)."""
    requested = config["packing"].get("initial_packing_fraction", 0.0)
    if not requested:
        return
    box = config["box"]
    area = float(np.sum(np.pi * np.asarray(radii)**2 if areas is None
                        else areas))
    phi = area / (box["length"] * box["width"])
    if abs(phi - requested) > REQUESTED_FRACTION_TOLERANCE:
        raise PackingError(
            f"[packing] initial_packing_fraction = {requested!r}: the"
            f" particles ({area:.6g} m^2) fill {phi:.4f} of the [box]"
            f" {box['length']!r} x {box['width']!r} m; for {requested!r}"
            f" set [box] length = {area / (requested * box['width']):.10g}"
            " m (the piston's start), or leave initial_packing_fraction out")


def _check_arguments(seed, counts, diameters, length, width, gap, trials,
                     max_sweeps) -> np.ndarray:
    """Validate :func:`random_packing`'s arguments; return the radii."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) \
            or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    counts = np.asarray(counts)
    diameters = np.asarray(diameters, dtype=float)
    if counts.ndim != 1 or counts.shape != diameters.shape or not len(counts):
        raise ValueError("counts and diameters must be sequences of the same"
                         " non-zero length")
    if np.any(counts < 0) or np.any(counts != np.round(counts)) \
            or counts.sum() < 1:
        raise ValueError(f"counts must be non-negative integers, got {counts}")
    if not np.all(np.isfinite(diameters)) or np.any(diameters <= 0):
        raise ValueError(f"diameters must be positive, got {diameters}")
    for name, value in (("length", length), ("width", width)):
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be positive, got {value}")
    if not np.isfinite(gap) or gap < 0:
        raise ValueError(f"gap must be non-negative, got {gap}")
    if trials < 1 or max_sweeps < 1:
        raise ValueError("trials and max_sweeps must be at least 1")
    if diameters.max() + 2 * _padded(gap) >= min(length, width):
        raise ValueError(f"a disk of diameter {diameters.max()} m does not fit"
                         f" in a {length} x {width} m box")
    radii = np.repeat(diameters / 2, counts.astype(int))
    phi = ball_fraction(radii, (length, width))
    if phi >= HEXAGONAL_FRACTION:
        raise ValueError(
            f"packing fraction {phi:.3f} exceeds"
            f" that of hexagonal disks ({HEXAGONAL_FRACTION:.3f})")
    return radii


def _pair_clearance(centres, radii) -> np.ndarray:
    """Matrix of surface-to-surface distances between disks."""
    d = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=-1)
    return d - radii[:, None] - radii[None, :]
