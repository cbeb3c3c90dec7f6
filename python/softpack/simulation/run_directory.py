"""A run's directory: what softpack writes there and nothing else (issue 16).

A run directory is marked by :data:`MARKER` (older runs: ``config.toml`` +
``driver.json``); in one, the outputs listed in :data:`RUN_OUTPUTS` are
replaced and nothing else is touched (:func:`prepare_directory`).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

#: What a run writes into its directory (removed by --force, nothing else).
RUN_OUTPUTS = ("series.csv", "particles.csv", "stress.csv", "raw",
               "fields.xdmf", "fields.h5", "mesh", "driver.json", "run.log",
               "config.toml", "raw.part", "resume-state.bin",
               "fields.part.xdmf", "fields.part.h5")
#: The file that marks a directory as softpack's run directory.
MARKER = ".softpack-run"


class RunError(RuntimeError):
    """A run that cannot go on; the message says why (exit status 1)."""


class UsageError(RunError):
    """A mistake on the command line, e.g. an unusable ``--out`` (exit 2)."""


def is_run_directory(out: Path) -> bool:
    """Whether ``out`` is softpack's: its marker, or an older run's files."""
    return (out / MARKER).is_file() or (
        (out / "config.toml").is_file() and (out / "driver.json").is_file())


def check_out_directory(out: Path) -> None:
    """Create ``out`` if needed and check that files can be written in it.

    Raises
    ------
    UsageError
        Naming ``--out`` and why: a file, not creatable, not writable.
    """
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {out}: is a file, not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".softpack-probe-", dir=out)
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        raise UsageError(f"--out {out}: cannot write there"
                         f" ({err.strerror or err})") from None


def prepare_directory(out: Path, force: bool) -> None:
    """Make ``out`` ready for a run; delete only what softpack wrote.

    A run directory (:func:`is_run_directory`): refused if it holds a
    complete run (``series.csv``) unless ``force``; its previous outputs
    (:data:`RUN_OUTPUTS`) are removed, series.csv first. Any other
    non-empty directory: refused unless ``force``, and then refused still
    if one of its entries has an output's name (it would be overwritten).

    Raises
    ------
    RunError
        A complete run without ``force``.
    UsageError
        An unusable or foreign directory.
    """
    check_out_directory(out)
    if is_run_directory(out):
        if (out / "series.csv").exists() and not force:
            raise RunError(f"{out} holds a complete run (series.csv); use"
                           " --force to overwrite it or --out for another"
                           " directory")
        for name in RUN_OUTPUTS:  # series.csv first: never a stale run
            target = out / name
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target)
            elif target.exists() or target.is_symlink():
                target.unlink()
    else:
        entries = sorted(p.name for p in out.iterdir())
        if entries and not force:
            shown = ", ".join(entries[:5]) + (", ..." if len(entries) > 5
                                               else "")
            raise UsageError(
                f"--out {out}: not empty and not a softpack run directory"
                f" ({shown}); softpack deletes nothing it did not write:"
                " choose a new or empty directory, or --force to write the"
                " run next to these files")
        clash = [name for name in RUN_OUTPUTS if name in entries]
        if clash:
            raise UsageError(
                f"--out {out}: {', '.join(clash)} would be overwritten and"
                " softpack did not write them (even with --force): choose"
                " another directory")
    (out / MARKER).write_text(
        "A softpack run directory: ./softpack run replaces its outputs"
        f" ({', '.join(RUN_OUTPUTS)}) and nothing else.\n")
