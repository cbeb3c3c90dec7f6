"""Runs ``softpack-simulate`` (the C++ driver) on a driver.json.

The one place that starts the driver: ``./softpack run``, the single-disk
check and the benchmarks all go through :func:`start` and :func:`wait`.
The driver runs with the run directory as its working directory, its
output to a log file.

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
from pathlib import Path

from softpack import paths

#: The executable's name under the build's bin directory.
DRIVER = "softpack-simulate"


class DriverError(RuntimeError):
    """The driver is missing or failed; the message says why."""


def executable() -> Path:
    """``$SOFTPACK_BIN/softpack-simulate`` (raises DriverError if absent)."""
    try:
        return paths.executable(DRIVER)
    except FileNotFoundError as err:
        raise DriverError(str(err)) from None


def check_ranks(ranks: int, config) -> None:
    """Refuse a number of MPI ranks outside 1..number of bodies.

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


def command(driver_json, quiet=False, ranks=1, threads=None) -> list[str]:
    """The command line that runs the driver on ``ranks`` MPI ranks.

    One rank: the executable itself (OpenMP uses the cores). Several:
    ``mpirun -np RANKS`` (``--oversubscribe``: more ranks than cores is
    allowed, e.g. to test; ``--allow-run-as-root`` when run as root), each
    rank with its share of the cores as OpenMP threads. ``threads``: that
    many OpenMP threads per rank instead.
    """
    cmd = [str(executable()), str(driver_json)]
    if quiet:
        cmd.append("--quiet")
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


def start(driver_json, log, quiet=False, ranks=1) -> subprocess.Popen:
    """Start the driver on ``driver_json``; its output goes to ``log``.

    Parameters
    ----------
    driver_json : path-like
        The input; the driver runs in its directory.
    log : file object or None
        Receives stdout and stderr (None: discarded).
    quiet : bool
        Pass ``--quiet`` (no per-step lines).
    ranks : int
        MPI ranks (:func:`command`); the caller checked the range.
    """
    driver_json = Path(driver_json).resolve()
    return subprocess.Popen(
        command(driver_json, quiet, ranks), cwd=driver_json.parent,
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


def wait(proc: subprocess.Popen) -> tuple[int, float]:
    """Wait for the driver; return its exit status and peak memory (MB).

    ``os.wait4`` gives the child's own peak resident set size.
    """
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, usage.ru_maxrss / 1024.0


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


def simulate(driver_json, log_path, quiet=False,
             ranks=1) -> tuple[int, float]:
    """Run the driver to the end; exit status and peak memory (MB).

    With several ranks the memory is the largest of mpirun's children's
    (``os.wait4`` reports the peak of the largest descendant waited for).
    """
    with open(log_path, "a") as log:
        proc = start(driver_json, log, quiet, ranks)
        try:
            return wait(proc)
        except BaseException:
            stop(proc)
            raise
