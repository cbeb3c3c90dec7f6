"""Turn a run stopped by ``stop.steps`` into what a kill at that step
leaves, for the tests of ``--resume``: raw/ up to the cut with its state,
none of a complete run's files, and config.toml's ``[stop] steps`` the
whole run's again; and the comparison of the resumed run's rows with the
uninterrupted run's."""

import re
from pathlib import Path

import numpy as np

#: The files only a complete run has.
COMPLETE = ("raw/done.json", "series.csv", "particles.csv", "network.csv",
            "stress.csv")


def as_killed(out: Path, cut: int, steps: int) -> None:
    """Make ``out`` (a run stopped after ``cut`` steps) a run of ``steps``
    steps killed at step ``cut``."""
    for name in COMPLETE:
        (out / name).unlink(missing_ok=True)
    toml = out / "config.toml"
    text, n = re.subn(rf"^steps = {cut}\b", f"steps = {steps}",
                      toml.read_text(), flags=re.M)
    assert n == 1, f"{toml}: no single [stop] steps = {cut}"
    toml.write_text(text)


def assert_same_rows(a, b, first=None):
    """Every column but the wall-clock seconds* equal, bit for bit, over
    the rows of ``a`` after step ``first`` (all rows if None)."""
    assert a.keys() == b.keys()
    rows = a["step"] > first if first is not None else slice(None)
    for column in a:
        if not column.startswith("seconds"):
            np.testing.assert_array_equal(a[column][rows], b[column],
                                          err_msg=column)
