"""Runs ``softpack-simulate`` (the C++ driver) on a driver.json.

The one place that starts the driver: ``./softpack run``, the single-disk
and plates checks and the benchmarks all go through :func:`launch` (write
driver.json, run the driver to the end, check that it finished), or
through :func:`start` and :func:`wait` to run several side by side. The
driver runs with the run directory as its working directory, its output
to a log file.

The driver never outlives the Python process that started it (issue 16):
it runs in its own process group (so that a terminal's Ctrl-C reaches
only the wrapper, which stops the driver and reports) and, on Linux, with
a parent-death signal (``prctl(PR_SET_PDEATHSIG, SIGKILL)``), so that even
a ``kill -9`` of the wrapper kills it. :func:`stop` signals the whole group.
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from softpack import paths
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.simulation.driver_input import write_driver_json

#: The executable's name under the build's bin directory.
DRIVER = "softpack-simulate"
#: Seconds between two looks at a running driver (``watch`` of
#: :func:`launch`).
POLL_SECONDS = 1.0


class DriverFailed(RunError):
    """The driver exited with a non-zero status (``status``)."""

    def __init__(self, message: str, status: int):
        super().__init__(message)
        self.status = status


@dataclass(frozen=True)
class Finished:
    """A driver run that reached its end (:func:`launch`)."""

    #: Peak resident memory (MB) of the driver (mpirun's largest child).
    peak_memory_mb: float
    #: ``raw/done.json``.
    done: dict


def executable() -> Path:
    """``$SOFTPACK_BIN/softpack-simulate``.

    Raises
    ------
    RunError
        When it is not built, saying how to build it.
    """
    try:
        return paths.executable(DRIVER)
    except FileNotFoundError as err:
        raise RunError(str(err)) from None


def check_ranks(ranks: int, config) -> None:
    """Refuse a number of MPI ranks outside 1..number of bodies (2D and 3D
    scenes alike).

    Raises
    ------
    ConfigError
        Naming ``--ranks``, the value and the allowed range.
    """
    from softpack.scene.config import ConfigError

    if ranks == 1:  # a valid config has a body
        return
    bodies = sum(int(s["count"]) for s in config["species"])
    if not 1 <= ranks <= bodies:
        raise ConfigError(
            f"--ranks {ranks}: must be between 1 and the number of bodies"
            f" ({bodies} in {config.source}): each rank owns at least one"
            " body")


def command(driver_json, quiet=False, ranks=1, threads=None,
            initial_only=False) -> list[str]:
    """The command line that runs the driver on ``ranks`` MPI ranks
    (``initial_only``: ``--initial-only``, the initial state written and
    no step).

    One rank: the executable itself (OpenMP uses the cores). Several:
    ``mpirun -np RANKS`` (``--oversubscribe``: more ranks than cores is
    allowed, e.g. to test; ``--allow-run-as-root`` when run as root), each
    rank with its share of the cores as OpenMP threads. ``threads``: that
    many OpenMP threads per rank instead.
    """
    cmd = [str(executable()), str(driver_json)]
    if quiet:
        cmd.append("--quiet")
    if initial_only:
        cmd.append("--initial-only")
    if threads is None and ranks > 1:
        threads = max(1, len(os.sched_getaffinity(0)) // ranks)
    if threads is not None:
        cmd += ["--threads", str(threads)]
    if ranks == 1:
        return cmd
    # Open MPI's (Debian's, dolfinx's): unaggregated help text, or an
    # MPI_Abort is reported as "ORTE_ERROR_LOG: Data unpack would read
    # past end of buffer" instead of its own message
    launcher = ["mpirun", "--oversubscribe", "--mca",
                "orte_base_help_aggregate", "0", "-np", str(ranks)]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        launcher.insert(1, "--allow-run-as-root")
    return launcher + cmd


def start(driver_json, log, quiet=False, ranks=1,
          threads=None, initial_only=False) -> subprocess.Popen:
    """Start the driver on ``driver_json``; its output goes to ``log``.

    Parameters
    ----------
    driver_json : path-like
        The input; the driver runs in its directory.
    log : file object or None
        Receives stdout and stderr (None: discarded).
    quiet : bool
        Pass ``--quiet`` (no per-step lines).
    ranks, threads : int
        MPI ranks and OpenMP threads per rank (:func:`command`); the
        caller checked the range.
    initial_only : bool
        As :func:`command`.
    """
    driver_json = Path(driver_json).resolve()
    return subprocess.Popen(
        command(driver_json, quiet, ranks, threads, initial_only),
        cwd=driver_json.parent,
        env=_launch_environment(), stdin=subprocess.DEVNULL,
        stdout=log if log is not None else subprocess.DEVNULL,
        stderr=subprocess.STDOUT, process_group=0,
        preexec_fn=_die_with_parent(os.getpid()))


#: Prefixes of the variables Open MPI's runtime sets in a process.
_MPI_RUNTIME = ("OMPI_", "PMIX_", "OPAL_", "ORTE_", "PRTE_")


def _launch_environment() -> dict:
    """This process's environment without Open MPI's runtime variables.

    A Python process that imported dolfinx (gmsh, mpi4py) is an MPI
    singleton: Open MPI set its own variables in the C environment, which a
    child inherits by default, and an ``mpirun`` started with them exits 1
    at once without a word. ``os.environ`` (read at start-up) is passed
    instead, without those variables.
    """
    return {k: v for k, v in os.environ.items()
            if not k.startswith(_MPI_RUNTIME)}


#: ``PR_SET_PDEATHSIG`` of <linux/prctl.h>.
_PR_SET_PDEATHSIG = 1


def _die_with_parent(parent: int):
    """A ``preexec_fn``: SIGKILL the child when ``parent`` dies (Linux).

    Runs in the forked child before exec: the parent-death signal survives
    exec. If the parent died between fork and prctl, the child is already
    an orphan (its parent id changed) and exits at once.
    """
    if not sys.platform.startswith("linux"):
        return None
    libc = ctypes.CDLL(None, use_errno=True)

    def preexec():
        if libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) != 0:
            os._exit(126)
        if os.getppid() != parent:
            os._exit(126)
    return preexec


def wait(proc: subprocess.Popen, watch=None) -> tuple[int, float]:
    """Wait for the driver; return its exit status and peak memory (MB).

    ``os.wait4`` gives the child's own peak resident set size. ``watch``:
    called with ``final=False`` every :data:`POLL_SECONDS` while the
    driver runs, then once with ``final=True``.
    """
    status, usage = wait_usage(proc, watch)
    return status, usage.ru_maxrss / 1024.0


def wait_usage(proc: subprocess.Popen, watch=None):
    """Wait for the driver (see :func:`wait`); exit status and its
    ``resource.struct_rusage``."""
    flags = 0 if watch is None else os.WNOHANG
    while True:
        pid, status, usage = os.wait4(proc.pid, flags)
        if pid:
            break
        time.sleep(POLL_SECONDS)
        watch(final=False)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if watch is not None:
        watch(final=True)
    return proc.returncode, usage


def stop(proc: subprocess.Popen, grace: float = 10.0) -> None:
    """Terminate a running driver's process group (SIGKILL after ``grace`` s).

    The driver writes ``raw/done.json`` only when it reaches a stopping
    criterion, so a stopped run never looks finished.
    """
    if proc.poll() is not None:
        return
    _signal_group(proc, signal.SIGTERM)
    try:
        proc.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        _signal_group(proc, signal.SIGKILL)
        proc.wait()


def _signal_group(proc: subprocess.Popen, sig) -> None:
    """Send ``sig`` to the driver's process group (the driver if gone)."""
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass
    except PermissionError:
        proc.send_signal(sig)


def launch(run: RunDirectory, config=None, scene=None, *,
           initial_state=None, log=None, quiet=False, ranks=1,
           threads=None, watch=None, initial_only=False) -> Finished:
    """Write driver.json, run the driver on it to the end, check it finished.

    Parameters
    ----------
    run : RunDirectory
        Where driver.json is and the driver writes.
    config, scene : Config and dict, optional
        The validated configuration and the scene's record
        (:meth:`Scene.record`): driver.json is written from them
        (:mod:`softpack.simulation.driver_input`, with ``initial_state``);
        without them the run's driver.json is run as it is (a resumption).
    log : file object or path-like, optional
        The driver's output: appended to an open file (e.g. run.log, shared
        with the caller), written afresh to a path, or discarded (None).
    quiet, ranks, threads, initial_only
        As :func:`command` (``initial_only``: no raw/done.json is
        required, ``Finished.done`` is None).
    watch : callable, optional
        Progress: see :func:`wait`.

    Raises
    ------
    RunError
        The driver is not built, failed (:class:`DriverFailed`, with the
        last lines of its log) or ended without ``raw/done.json``. Whatever
        interrupts the wait stops the driver's process group first.
    """
    executable()
    if config is not None:
        write_driver_json(config, scene, run.path, initial_state)
    how = (quiet, ranks, threads, watch, initial_only)
    if log is None or hasattr(log, "write"):
        return _launched(run, log, *how)
    with open(log, "w") as stream:
        return _launched(run, stream, *how)


def _launched(run, log, quiet, ranks, threads, watch,
              initial_only=False) -> Finished:
    """The driver started on ``run``'s driver.json, waited for, checked."""
    if log is not None:
        log.flush()
    proc = start(run.driver_json, log, quiet, ranks, threads, initial_only)
    try:
        status, peak_mb = wait(proc, watch)
    except BaseException:
        stop(proc)
        raise
    if status != 0:
        where = "" if log is None else (
            f"; last lines of {log.name}:\n" + _tail(log.name))
        raise DriverFailed(f"{DRIVER} failed (exit status {status}){where}",
                           status)
    return Finished(peak_memory_mb=peak_mb,
                    done=None if initial_only else run.done())


def _tail(path, lines: int = 20) -> str:
    """The last lines of a text file (a log)."""
    try:
        text = Path(path).read_text(errors="replace")
        return "\n".join(text.splitlines()[-lines:])
    except OSError:
        return "(no log)"
