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


def start(driver_json, log, quiet=False) -> subprocess.Popen:
    """Start the driver on ``driver_json``; its output goes to ``log``.

    Parameters
    ----------
    driver_json : path-like
        The input; the driver runs in its directory.
    log : file object or None
        Receives stdout and stderr (None: discarded).
    quiet : bool
        Pass ``--quiet`` (no per-step lines).
    """
    driver_json = Path(driver_json).resolve()
    command = [str(executable()), str(driver_json)]
    if quiet:
        command.append("--quiet")
    return subprocess.Popen(
        command, cwd=driver_json.parent, stdin=subprocess.DEVNULL,
        stdout=log if log is not None else subprocess.DEVNULL,
        stderr=subprocess.STDOUT, process_group=0,
        preexec_fn=_die_with_parent(os.getpid()))


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


def simulate(driver_json, log_path, quiet=False) -> tuple[int, float]:
    """Run the driver to the end; exit status and peak memory (MB)."""
    with open(log_path, "a") as log:
        proc = start(driver_json, log, quiet)
        try:
            return wait(proc)
        except BaseException:
            stop(proc)
            raise
