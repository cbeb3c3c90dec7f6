"""A run's directory: every path in it, and what softpack may replace there.

:class:`RunDirectory` names every file of a run (docs/contract.md sections
4-6): the inputs the Python stages write (``config.toml``, ``mesh/``,
``driver.json``), the driver's raw output (:class:`RawOutput`: ``raw/``),
its fields and the analysis' tables. No other module spells these names.

A run directory is marked by :data:`MARKER`, and only a marked one is
softpack's: a folder that merely holds files of a run's names
(``config.toml``, ``driver.json``) is the user's. In a run directory the
outputs listed in :data:`RUN_OUTPUTS` are replaced and nothing else is
touched (issues 16 and 42, :func:`prepare_directory`).
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import tempfile
from pathlib import Path

#: What a run writes into its directory (removed by --force, nothing else).
RUN_OUTPUTS = ("series.csv", "particles.csv", "stress.csv", "network.csv",
               "raw",
               "fields.xdmf", "fields.h5", "fields", "mesh", "driver.json", "run.log",
               "config.toml", "raw.part", "resume-state.bin",
               "fields.part.xdmf", "fields.part.h5")
#: The file that marks a directory as softpack's run directory.
MARKER = ".softpack-run"
#: The lock of a run directory (RunLock): one run or resume at a time.
LOCK = ".softpack-lock"


class RawOutput:
    """The driver's raw output directory (``DIR/raw``, or the killed part
    ``DIR/raw.part`` of a resumed run: the same layout)."""

    def __init__(self, path):
        self.path = Path(path)

    @property
    def steps_csv(self) -> Path:
        """One row per output step (docs/driver_io.md)."""
        return self.path / "steps.csv"

    @property
    def particles_csv(self) -> Path:
        """One row per particle and output step."""
        return self.path / "particles.csv"

    @property
    def contacts(self) -> Path:
        """``contacts/step_NNNNNNNN.csv``, one per output step."""
        return self.path / "contacts"

    def contact_file(self, step) -> Path:
        """``contacts/step_NNNNNNNN.csv`` of an output step."""
        return self.contacts / f"step_{int(step):08d}.csv"

    @property
    def step_dirs(self) -> tuple[Path, Path]:
        """The directories of per-step files ``step_NNNNNNNN.*``: the
        contacts and the unsolved contact problems (FCLIB)."""
        return self.contacts, self.path / "failed_contact_problems"

    @property
    def setup_json(self) -> Path:
        """Walls, bodies, species, parameters (written before step 0)."""
        return self.path / "setup.json"

    @property
    def state_bin(self) -> Path:
        """The state at the last output step (resume, --from-state)."""
        return self.path / "state.bin"

    @property
    def stage_record(self) -> Path:
        """The driver's stage record beside the state (runs with
        [[stages]])."""
        return self.path / "state.stage.json"

    @property
    def done_json(self) -> Path:
        """Written only when the driver reached a stopping criterion."""
        return self.path / "done.json"


class RunDirectory:
    """Every path of one run directory (see the module doc).

    Parameters
    ----------
    path : path-like
        The directory (it need not exist yet).
    """

    def __init__(self, path):
        self.path = Path(path)

    def __fspath__(self) -> str:
        return os.fspath(self.path)

    def __repr__(self) -> str:
        return f"RunDirectory({str(self.path)!r})"

    @property
    def marker(self) -> Path:
        return self.path / MARKER

    @property
    def config_toml(self) -> Path:
        """The resolved configuration, every key."""
        return self.path / "config.toml"

    @property
    def driver_json(self) -> Path:
        """The driver's input (simulation/driver_input.py)."""
        return self.path / "driver.json"

    @property
    def run_log(self) -> Path:
        """``./softpack run``'s log: its lines and the driver's output."""
        return self.path / "run.log"

    @property
    def driver_log(self) -> Path:
        """The driver's output when no run.log is kept (references,
        benchmarks)."""
        return self.path / "driver.log"

    def mesh_stem(self, name: str) -> Path:
        """``mesh/NAME``: the stem of the scene's mesh files."""
        return self.path / "mesh" / name

    @property
    def raw(self) -> RawOutput:
        """The driver's raw output."""
        return RawOutput(self.path / "raw")

    @property
    def raw_part(self) -> RawOutput:
        """The killed run's raw output while it is resumed."""
        return RawOutput(self.path / "raw.part")

    @property
    def resume_state(self) -> Path:
        """The state a resumed driver starts from."""
        return self.path / "resume-state.bin"

    @property
    def resume_stage_record(self) -> Path:
        """Its stage record (the driver's ``S.stage.json`` beside ``S.bin``)."""
        return self.path / "resume-state.stage.json"

    def fields(self, suffix: str) -> Path:
        """``fields.SUFFIX`` (``xdmf`` or ``h5``)."""
        return self.path / f"fields.{suffix}"

    @property
    def fields_h5(self) -> Path:
        """The P1 fields' mesh (analysis/fields.py reads the fields through
        it)."""
        return self.fields("h5")

    @property
    def field_frames(self) -> Path:
        """``fields/``: one HDF5 file per written time."""
        return self.path / "fields"

    @property
    def network_csv(self) -> Path:
        """The contact network per output step (analysis/network.py)."""
        return self.path / "network.csv"

    @property
    def series_csv(self) -> Path:
        """The observables per output step (written last: a complete run)."""
        return self.path / "series.csv"

    @property
    def particles_csv(self) -> Path:
        """The observables per particle and output step."""
        return self.path / "particles.csv"

    @property
    def stress_csv(self) -> Path:
        """The stress estimates per output step."""
        return self.path / "stress.csv"

    def done(self, error=None) -> dict:
        """``raw/done.json``; ``error`` (RunError by default) if missing."""
        path = self.raw.done_json
        if not path.is_file():
            raise (error or RunError)(
                f"{path} missing: the simulation did not finish, so its raw"
                " output is partial")
        return json.loads(path.read_text())


#: Exit statuses of ``./softpack run`` (README, "Exit statuses"): done;
#: failed (packing, driver, post-processing); bad configuration or command
#: line; finished but flagged (run_flags), its outputs all written. A run
#: stopped by signal N exits with 128 + N.
EXIT_DONE, EXIT_FAILED, EXIT_USAGE, EXIT_FLAGGED = 0, 1, 2, 3


def run_flags(done: dict) -> list:
    """What ``raw/done.json`` marks a finished run by, that its answers
    cannot be taken as they are (the one rule: the exit status and the API
    read it): a stage program that ended before its stop criterion, a
    Newton iteration or contact solve left unconverged, bodies overlapping
    by more than ``contact.alert_distance`` at an output step. Empty: none.
    """
    flags = []
    if done.get("complete", True) is False:
        flags.append(f"incomplete (stage {done.get('stage', '?')} ended by"
                     f" {done.get('reason', '?')})")
    if done.get("converged", True) is False:
        flags.append(f"not converged ({done.get('newton_unconverged_steps', '?')}"
                     " Newton and"
                     f" {done.get('nlgs_unconverged_steps', '?')} contact"
                     " solve steps unconverged)")
    if done.get("overlap_steps", 0):
        flags.append(f"overlapping ({done['overlap_steps']} output steps"
                     " beyond contact.alert_distance)")
    return flags


class RunError(RuntimeError):
    """A run that cannot go on; the message says why (exit status 1)."""


class UsageError(RunError):
    """A mistake on the command line, e.g. an unusable ``--out`` (exit 2)."""


class RunFlagged(RunError):
    """A run that finished, every output written, but flagged (run_flags;
    exit status 3). ``flags`` says why, ``directory`` is the run and
    ``series`` its series (as the API reads it)."""

    def __init__(self, directory, flags, series=None):
        super().__init__(f"{directory}: the run finished flagged: "
                         + "; ".join(flags) + " (raw/done.json)")
        self.directory, self.flags, self.series = directory, flags, series


class RunLock:
    """A run directory's lock, held in a ``with`` block: one run or resume
    works in a directory at a time (issue 42). ``./softpack run`` takes it
    before it changes the directory (:func:`prepare_directory`), a resume
    before it moves anything; a second one is refused, naming the process
    that holds it. An advisory ``flock`` on ``DIR/.softpack-lock``: the
    system releases it when its process ends, however it ends, so a killed
    run leaves no stale lock (the file stays, with the last holder's
    process id).

    Raises
    ------
    UsageError
        On entry, when another process holds it.
    """

    def __init__(self, out):
        self.path = Path(out) / LOCK
        self._file = None

    def __enter__(self):
        if self._file is not None:  # held already (prepare_directory's)
            return self
        f = open(self.path, "a+")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            f.seek(0)
            holder = f.read().strip() or "?"
            f.close()
            raise UsageError(
                f"{self.path.parent}: another softpack run or resume"
                f" (process {holder}) is working in it; wait for it to end"
                " or stop it, or choose another --out") from None
        f.seek(0)
        f.truncate()
        f.write(f"{os.getpid()}\n")
        f.flush()
        self._file = f
        return self

    def __exit__(self, *exc):
        if self._file is not None:
            fcntl.flock(self._file, fcntl.LOCK_UN)
            self._file.close()
            self._file = None
        return False


def is_run_directory(out: Path) -> bool:
    """Whether ``out`` is softpack's: it holds the marker softpack wrote
    (files of a run's names alone do not make it one)."""
    return RunDirectory(out).marker.is_file()


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


def prepare_directory(out: Path, force: bool) -> RunLock:
    """Make ``out`` ready for a run; delete only what softpack wrote; return
    its lock, held (the caller releases it when the run ends).

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
        An unusable or foreign directory, or one another run works in.
    """
    check_out_directory(out)
    if is_run_directory(out):
        lock = RunLock(out).__enter__()  # before the old run is touched
        try:
            _clear_run(out, force)
        except BaseException:
            lock.__exit__(None, None, None)
            raise
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
        lock = RunLock(out).__enter__()
    RunDirectory(out).marker.write_text(
        "A softpack run directory: ./softpack run replaces its outputs"
        f" ({', '.join(RUN_OUTPUTS)}) and nothing else.\n")
    return lock


def _clear_run(out: Path, force: bool) -> None:
    """Remove a run directory's outputs, series.csv first (never a stale
    run); RunError if it holds a complete run and not ``force``."""
    if RunDirectory(out).series_csv.exists() and not force:
        raise RunError(f"{out} holds a complete run (series.csv); use"
                       " --force to overwrite it or --out for another"
                       " directory")
    for name in RUN_OUTPUTS:
        target = out / name
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        elif target.exists() or target.is_symlink():
            target.unlink()
