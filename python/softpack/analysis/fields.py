"""The one reader of a run's fields (the driver's field output).

The driver writes its fields in the layout of dolfinx's XDMFFile
(``driver/io/field_output.cpp``, from its own arrays: nodes in the DOF
order, cells as the mesh numbers them) and its own ``fields.xdmf`` (one temporal
collection, read by ParaView and ``meshio.xdmf.TimeSeriesReader``; this
module does not read it). ``fields.h5`` holds the mesh:

``/Mesh/<mesh>/geometry``
    reference node coordinates, shape ``(n, 2)`` (or ``(n, 3)``);
``/Mesh/<mesh>/topology``
    triangles, shape ``(m, 3)`` (a 3D scene's: tetrahedra, ``(m, 4)``, its
    coordinates and displacements then read with their three components);

and each written time has its own file, ``fields/<key>.h5`` (written whole
and renamed, so that a killed driver leaves no frame half written), holding

``/Function/<name>/<key>``
    a function at a time, the key being ``repr(time)`` with ``.`` written
    ``_``: ``displacement`` (nodal, ``(n, 3)``), ``Psi`` (strain energy per
    reference area of each cell, J/m^3 per unit length, ``(m, 1)``) and
    ``particle`` (the body id of each cell, ``(m, 1)``).

Function names are matched without regard to case. Every reader here takes
the path of ``fields.h5``.

Earlier versions wrote every frame inside ``fields.h5`` (as dolfinx does),
and runs they resumed kept the frames of their killed part in
``fields.part.h5`` beside it: these are read too (at a time stored twice,
the later file's: ``fields.part.h5``, ``fields.h5``, ``fields/``).
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
        Reference node coordinates (m); (n, 3) for tetrahedra.
    cells : ndarray of int, shape (m, 3)
        Triangles; (m, 4): tetrahedra.
    displacement : ndarray, shape (n, 2)
        (n, 3) for tetrahedra.
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
    """The files that may hold frames, earliest writer first:
    ``[fields.part.h5, fields.h5]`` (an earlier version's layout; the part
    only if it exists).

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
                      " part of a resumed run) are left out", stacklevel=4)
        return [path]
    return [part, path]


def _frame_files(path) -> dict:
    """``{time: file}`` of the one-frame files ``fields/<key>.h5`` beside
    ``fields.h5`` (their hidden temporary files left out)."""
    frames = Path(path).with_suffix("")
    if not frames.is_dir():
        return {}
    return {float(file.stem.replace("_", ".")): file
            for file in frames.glob("[!.]*.h5")}


def _index(path, name) -> dict:
    """``{stored time: (file, key)}`` of function ``name`` (later files win).

    Raises
    ------
    KeyError
        When no file holds the function.
    """
    index = {}
    for source in _sources(path):
        with _h5py().File(source, "r") as f:
            if "Function" in f or source != Path(path):
                group = _function_group(f, name, source)
                index.update((t, (source, key))
                             for t, key in _times(group).items())
    index.update((t, (file, file.stem))
                 for t, file in _frame_files(path).items())
    if not index:
        raise KeyError(f"{path}: no function {name!r} stored")
    return index


def _nearest(index: dict, time) -> float:
    """The stored time of ``index`` nearest ``time``."""
    return min(index, key=lambda t: abs(t - time))


def _times(group) -> dict:
    """``{stored time: key}`` of a function group."""
    return {float(key.replace("_", ".")): key for key in group}


def _read(file, name, key, dim=2) -> np.ndarray:
    """Values of function ``name`` at key ``key`` of a file: ``(n, dim)``
    for a vector function (2D: its in-plane part), ``(m,)`` for a cell
    function."""
    with _h5py().File(file, "r") as f:
        group = _function_group(f, name, file)
        if key not in group:
            raise KeyError(f"{file}: no {name!r} at {key}")
        values = np.asarray(group[key])
    return values[:, :dim] if values.shape[1] >= 2 else values.reshape(-1)


def read_mesh(path):
    """Reference node coordinates ``(n, 2)`` and triangles ``(m, 3)``; a
    mesh of tetrahedra ``(m, 4)``: coordinates ``(n, 3)``."""
    with _h5py().File(path, "r") as f:
        mesh = _mesh_group(f, path)
        cells = np.asarray(mesh["topology"]).astype(np.int64)
        return np.asarray(mesh["geometry"])[:, :cells.shape[1] - 1], cells


def stored_times(path, name=DISPLACEMENT) -> np.ndarray:
    """The times at which function ``name`` is stored, ascending."""
    return np.array(sorted(_index(path, name)))


def read_function(path, name, time):
    """Values of function ``name`` at the stored time nearest ``time``.

    Returns
    -------
    (ndarray, float)
        The values (``(n, 2)`` for a vector function, its in-plane part;
        ``(m,)`` for a cell function) and the stored time read.
    """
    index = _index(path, name)
    stored = _nearest(index, time)
    file, key = index[stored]
    return _read(file, name, key), stored


def read_snapshot(path, time) -> Snapshot:
    """Mesh, displacement, Psi and body ids at the stored time nearest ``time``.

    Raises
    ------
    KeyError
        When the file has no mesh or no displacement.
    """
    points, cells = read_mesh(path)
    index = _index(path, DISPLACEMENT)
    stored = _nearest(index, time)
    file, key = index[stored]
    u = _read(file, DISPLACEMENT, key, points.shape[1])
    optional = {}
    for name in (PSI, BODY):
        try:
            optional[name] = _read(file, name, key)
        except KeyError:
            optional[name] = None
    body = optional[BODY]
    return Snapshot(
        time=stored, points=points, cells=cells, displacement=u,
        psi=optional[PSI],
        body=None if body is None else np.rint(body).astype(np.int64))


def read_displacements(path, dim=2):
    """Every stored displacement, by time (``dim`` = 3: a tetrahedral
    mesh's three components).

    Returns
    -------
    list of (float, ndarray)
        ``(time, u (n, dim))`` in ascending time.
    """
    return [(t, _read(file, DISPLACEMENT, key, dim))
            for t, (file, key) in sorted(_index(path, DISPLACEMENT).items())]
