"""The one CSV reader and writer of softpack.

Every CSV file of a run (``raw/steps.csv``, ``raw/particles.csv``,
``raw/contacts/*.csv``, ``series.csv``, ``particles.csv``) and of the
references (``force_*.csv``, ``profile_*.csv``) is a header line and rows of
numbers; this module reads them as ``{column: float array}`` and writes them
atomically, so that no other module parses or formats CSV itself.
"""

from __future__ import annotations

import csv
import io
import math
import os
import warnings
from pathlib import Path

import numpy as np

#: Words the driver writes in numeric columns, and their values.
WORDS = {"": math.nan, "nan": math.nan, "true": 1.0, "false": 0.0}


def read_table(path) -> dict:
    """A CSV file with a header as ``{column: float array}``.

    Empty fields become NaN; ``true``/``false`` become 1/0. A row shorter
    than the header (a writer whose header is ahead of its rows) is padded
    with NaN.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    dict of str -> ndarray of float, each of one length (the row count)

    Raises
    ------
    ValueError
        When the file has no header line, or a field is not a number.
    """
    with open(path, newline="") as f:
        header = next(csv.reader(f), None)
        if header is None:
            raise ValueError(f"{path}: empty file (no header)")
        text = f.read()
    names = [name.strip() for name in header]
    try:  # fast path: plain numbers in full rows
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = np.loadtxt(io.StringIO(text), delimiter=",", ndmin=2)
        data = data.reshape(-1, len(names))
    except ValueError:
        data = np.array([_row(row, len(names), path)
                         for row in csv.reader(io.StringIO(text)) if row],
                        dtype=float).reshape(-1, len(names))
    return {name: data[:, j] for j, name in enumerate(names)}


def _row(fields, width, path) -> list:
    """One row's numbers, padded with NaN to ``width``."""
    if len(fields) > width:
        raise ValueError(f"{path}: a row has {len(fields)} fields, the"
                         f" header {width}")
    values = []
    for text in fields:
        word = text.strip().lower()
        values.append(WORDS[word] if word in WORDS else float(word))
    return values + [math.nan] * (width - len(values))


def write_table(path, columns: dict, names=None) -> Path:
    """Write columns as CSV atomically (temporary file, then rename).

    Integral values are written as integers, others with 12 significant
    digits, NaN as ``nan`` (pandas reads it as missing).

    Parameters
    ----------
    path : path-like
    columns : dict of str -> array_like
        Columns of one length.
    names : sequence of str, optional
        The columns to write, in order (default: all, in dict order).

    Returns
    -------
    Path
    """
    path = Path(path)
    names = list(columns) if names is None else list(names)
    data = [np.asarray(columns[name]) for name in names]
    if len({len(d) for d in data}) > 1:
        raise ValueError(f"{path}: columns of different lengths "
                         f"{dict(zip(names, map(len, data)))}")
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        with open(tmp, "w") as f:
            f.write(",".join(names) + "\n")
            for row in zip(*data):
                f.write(",".join(_format(v) for v in row) + "\n")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def write_rows(path, rows, names) -> Path:
    """Write a summary table: one dict per row, the columns ``names`` in
    order, strings as they are and numbers to 6 significant digits (the
    tables of checks that docs/ show)."""
    lines = [",".join(names)]
    for row in rows:
        lines.append(",".join(
            row[k] if isinstance(row[k], str) else f"{row[k]:.6g}"
            for k in names))
    path = Path(path)
    path.write_text("\n".join(lines) + "\n")
    return path


def _format(value) -> str:
    """One CSV field."""
    value = float(value)
    if math.isfinite(value) and value == int(value) and abs(value) < 2**53:
        return str(int(value))
    return f"{value:.12g}"
