"""Turn a run stopped by ``stop.steps`` into what a kill at that step
leaves, for the tests of ``--resume``: raw/ up to the cut with its state,
none of a complete run's files, and config.toml's ``[stop] steps`` the
whole run's again."""

import re
from pathlib import Path

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
