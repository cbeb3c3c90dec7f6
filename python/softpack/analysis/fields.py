"""The one reader of ``fields.h5`` (the driver's field output).

The driver writes ``fields.h5`` in the layout of dolfinx's XDMFFile
(``driver/io/field_output.cpp``, from its own arrays: nodes in the DOF
order, cells as the mesh numbers them) and its own ``fields.xdmf`` (one temporal
collection, read by ParaView and ``meshio.xdmf.TimeSeriesReader``; this
module does not read it); in the HDF5 file:

``/Mesh/<mesh>/geometry``
    reference node coordinates, shape ``(n, 2)`` (or ``(n, 3)``);
``/Mesh/<mesh>/topology``
    triangles, shape ``(m, 3)``;
``/Function/<name>/<time>``
    a function at a time, the key being ``repr(time)`` with ``.`` written
    ``_``: ``displacement`` (nodal, ``(n, 3)``), ``Psi`` (strain energy per
    reference area of each cell, J/m^3 per unit length, ``(m, 1)``) and
    ``particle`` (the body id of each cell, ``(m, 1)``).

Function names are matched without regard to case.

A resumed run (``./softpack run --resume``, :mod:`softpack.simulation.resume`)
continues its ``fields.h5``. Runs resumed by earlier versions kept the
frames of their killed part in ``fields.part.h5`` beside it; every reader
here takes the path of ``fields.h5`` and reads the frames of both (at a time
stored in both, the resumed driver's).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DISPLACEMENT, PSI, BODY = "displacement", "Psi", "particle"


@dataclass(frozen=True)
class Snapshot:
    """The fields of one stored time.

    Attributes
    ----------
    time : float
        The stored time read (s).
    points : ndarray, shape (n, 2)
        Reference node coordinates (m).
    cells : ndarray of int, shape (m, 3)
    displacement : ndarray, shape (n, 2)
    psi : ndarray, shape (m,) or None
        Strain energy per reference area of each cell (J/m^3); None when
        the file has no ``Psi``.
    body : ndarray of int, shape (m,) or None
        Body (particle) id of each cell; None when the file has none.
    """

    time: float
    points: np.ndarray
    cells: np.ndarray
    displacement: np.ndarray
    psi: np.ndarray | None
    body: np.ndarray | None

    @property
    def current(self) -> np.ndarray:
        """Current node positions ``points + displacement``."""
        return self.points + self.displacement


def _h5py():
    """h5py, imported when a file is read (the package loads without it)."""
    import h5py
    return h5py


def _mesh_group(f, path):
    """The first group under ``/Mesh`` (dolfinx names it after the mesh)."""
    if "Mesh" not in f or not len(f["Mesh"]):
        raise KeyError(f"{path}: no /Mesh group")
    return f["Mesh"][next(iter(f["Mesh"]))]


def _function_group(f, name, path):
    """The group ``/Function/<name>`` (case-insensitive), or KeyError."""
    names = {key.lower(): key for key in f.get("Function", {})}
    if name.lower() not in names:
        raise KeyError(f"{path}: no function {name!r}, has"
                       f" {sorted(names.values())}")
    return f["Function"][names[name.lower()]]


def _sources(path) -> list[Path]:
    """``[fields.part.h5, fields.h5]`` of a resumed run, else ``[path]``.

    A killed part that HDF5 cannot open (written by a driver that did not
    flush its frames) is left out with a warning: the resumed frames are
    still read.
    """
    path = Path(path)
    part = path.with_name(f"{path.stem}.part{path.suffix}")
    if not (part.is_file() and path.is_file()):
        return [path]
    try:
        _h5py().File(part, "r").close()
    except OSError as err:
        warnings.warn(f"{part}: unreadable ({err}); its frames (the killed"
                      " part of a resumed run) are left out", stacklevel=3)
        return [path]
    return [part, path]


def _source_of(path, name, time) -> tuple[Path, float]:
    """The file holding function ``name`` at the stored time nearest
    ``time`` over :func:`_sources`, and that time."""
    best = None
    for source in _sources(path):
        with _h5py().File(source, "r") as f:
            for t in _times(_function_group(f, name, source)):
                if best is None or abs(t - time) <= abs(best[1] - time):
                    best = (source, t)  # later files win a tie
    return best


def _times(group) -> dict:
    """``{stored time: key}`` of a function group."""
    return {float(key.replace("_", ".")): key for key in group}


def read_mesh(path):
    """Reference node coordinates ``(n, 2)`` and triangles ``(m, 3)``."""
    with _h5py().File(path, "r") as f:
        mesh = _mesh_group(f, path)
        return (np.asarray(mesh["geometry"])[:, :2],
                np.asarray(mesh["topology"]).astype(np.int64))


def stored_times(path, name=DISPLACEMENT) -> np.ndarray:
    """The times at which function ``name`` is stored, ascending."""
    times = set()
    for source in _sources(path):
        with _h5py().File(source, "r") as f:
            times.update(_times(_function_group(f, name, source)))
    return np.array(sorted(times))


def read_function(path, name, time):
    """Values of function ``name`` at the stored time nearest ``time``.

    Returns
    -------
    (ndarray, float)
        The values (``(n, 2)`` for a vector function, its in-plane part;
        ``(m,)`` for a cell function) and the stored time read.
    """
    source, stored = _source_of(path, name, time)
    with _h5py().File(source, "r") as f:
        return _read_at(_function_group(f, name, source), stored)


def _read_at(group, time):
    """Values of a function group at its stored time nearest ``time``."""
    times = _times(group)
    stored = min(times, key=lambda t: abs(t - time))
    values = np.asarray(group[times[stored]])
    values = values[:, :2] if values.shape[1] >= 2 else values.reshape(-1)
    return values, stored


def read_snapshot(path, time) -> Snapshot:
    """Mesh, displacement, Psi and body ids at the stored time nearest ``time``.

    Raises
    ------
    KeyError
        When the file has no mesh or no displacement.
    """
    path, time = _source_of(path, DISPLACEMENT, time)
    with _h5py().File(path, "r") as f:
        mesh = _mesh_group(f, path)
        u, stored = _read_at(_function_group(f, DISPLACEMENT, path), time)
        optional = {}
        for name in (PSI, BODY):
            try:
                optional[name] = _read_at(_function_group(f, name, path),
                                          stored)[0]
            except KeyError:
                optional[name] = None
        body = optional[BODY]
        return Snapshot(
            time=stored, points=np.asarray(mesh["geometry"])[:, :2],
            cells=np.asarray(mesh["topology"]).astype(np.int64),
            displacement=u, psi=optional[PSI],
            body=None if body is None else np.rint(body).astype(np.int64))


def read_displacements(path):
    """Every stored displacement, by time.

    Returns
    -------
    list of (float, ndarray)
        ``(time, u (n, 2))`` in ascending time.
    """
    frames = {}
    for source in _sources(path):  # the resumed driver's frames last
        with _h5py().File(source, "r") as f:
            group = _function_group(f, DISPLACEMENT, source)
            frames.update((t, np.asarray(group[key])[:, :2])
                          for t, key in _times(group).items())
    return sorted(frames.items(), key=lambda item: item[0])
