"""Runs ``softpack-simulate`` (the C++ driver) on a driver.json.

The one place that starts the driver: ``./softpack run``, the single-disk
check and the benchmarks all go through :func:`start` and :func:`wait`.
The driver runs with the run directory as its working directory, its
output to a log file.
"""

from __future__ import annotations

import os
import subprocess
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
        stderr=subprocess.STDOUT)


def wait(proc: subprocess.Popen) -> tuple[int, float]:
    """Wait for the driver; return its exit status and peak memory (MB).

    ``os.wait4`` gives the child's own peak resident set size.
    """
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, usage.ru_maxrss / 1024.0


def stop(proc: subprocess.Popen) -> None:
    """Terminate a running driver (then kill it after 10 s)."""
    if proc.poll() is not None:
        return
    proc.terminate()
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def simulate(driver_json, log_path, quiet=False) -> tuple[int, float]:
    """Run the driver to the end; exit status and peak memory (MB)."""
    with open(log_path, "a") as log:
        proc = start(driver_json, log, quiet)
        try:
            return wait(proc)
        except BaseException:
            stop(proc)
            raise
