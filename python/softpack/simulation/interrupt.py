"""Stopping a run cleanly: signals, a closed output (issue 16).

``./softpack run`` turns SIGTERM and SIGHUP (and Ctrl-C's SIGINT, as
KeyboardInterrupt) into an exception that unwinds to its ``main``, stopping
the driver on the way (:func:`softpack.simulation.run._simulate`); a
closed standard output (``| head``) does the same through :func:`echo`.
"""

from __future__ import annotations

import os
import signal
import sys
import threading

#: Signals that stop a run cleanly (the driver with it).
STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


class Stopped(BaseException):
    """The run was stopped by a signal or a closed output.

    A BaseException, like KeyboardInterrupt: nothing between the signal and
    ``softpack.simulation.run.main`` may swallow it.
    """

    def __init__(self, signum: int, why: str):
        super().__init__(why)
        self.signum = signum


def stop_on_signals() -> dict:
    """Turn SIGTERM and SIGHUP into :class:`Stopped`; previous handlers.

    Only the main thread may install handlers: elsewhere (the Python API in
    a worker thread) nothing is installed.
    """
    def stop(signum, frame):
        raise Stopped(signum, signal.Signals(signum).name)

    previous = {}
    try:
        for signum in STOP_SIGNALS:
            previous[signum] = signal.signal(signum, stop)
    except ValueError:  # not the main thread
        pass
    return previous


def reclaim_signals() -> None:
    """Give the signals back to Python after the mesher's imports.

    PETSc (imported with dolfinx) installs C handlers, e.g. for SIGPIPE,
    that exit at once (status 59) without stopping the driver. Python's own
    record of the handlers is unchanged, so installing it again restores
    them: SIGPIPE ignored (a closed output raises BrokenPipeError),
    SIGINT, SIGTERM, SIGHUP as set by :func:`stop_on_signals`.
    """
    if threading.current_thread() is not threading.main_thread():
        return
    for signum in (signal.SIGINT, signal.SIGPIPE, *STOP_SIGNALS):
        handler = signal.getsignal(signum)
        if handler is not None:
            signal.signal(signum, handler)


def why(err) -> str:
    """What stopped the run, for the message."""
    return "Ctrl-C" if isinstance(err, KeyboardInterrupt) else str(err)


def silence_stdout() -> None:
    """Point a closed standard output at /dev/null (no flush error at exit)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


def echo(text="", end="\n") -> None:
    """Print to standard output; a closed output stops the run.

    Raises
    ------
    Stopped
        With SIGPIPE when the reader has gone (``./softpack run | head``).
    """
    try:
        print(text, end=end, flush=True)
    except BrokenPipeError:
        raise Stopped(signal.SIGPIPE, "standard output closed") from None
