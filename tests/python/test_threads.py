"""Issue 18: the driver's OpenMP threads wait passively unless told otherwise.

libgomp reads OMP_WAIT_POLICY when the program loads, so the driver sets it
and re-executes itself (driver/apps/threads.h). To see the environment the
running driver really has, its driver.json is a named pipe: the driver blocks
opening it, its /proc/PID/environ is read once it has opened the pipe (after any
re-execution), then the pipe gets a document the driver refuses.
"""

import errno
import os
import subprocess
import time
from pathlib import Path

from driver_required import require_driver


def _open_for_writing(fifo: Path, proc, timeout: float) -> int:
    """Open the named pipe for writing once a reader has it open (the
    driver, reading its driver.json after any re-execution): the file
    descriptor."""
    deadline = time.time() + timeout
    while True:
        try:
            return os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
        except OSError as error:  # ENXIO: no reader yet
            if error.errno != errno.ENXIO:
                raise
        assert proc.poll() is None, (
            f"the driver exited ({proc.returncode}) before reading "
            f"{fifo.name}: {proc.stderr.read()}")
        assert time.time() < deadline, f"the driver never opened {fifo.name}"
        time.sleep(0.05)


def _driver_environment(tmp_path: Path, env: dict) -> dict:
    """The environment of a softpack-simulate blocked reading its
    driver.json: read once it has opened the pipe, i.e. in the image that
    runs (a re-execution happens before), not the environment passed in."""
    exe = require_driver()
    fifo = tmp_path / "driver.json"
    os.mkfifo(fifo)
    proc = subprocess.Popen([str(exe), str(fifo), "--quiet"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)
    try:
        fd = _open_for_writing(fifo, proc, timeout=30)
        environ = Path(f"/proc/{proc.pid}/environ").read_bytes()
        with os.fdopen(fd, "w") as f:  # unblock: an empty object is refused
            f.write("{}")
        assert proc.wait(timeout=30) == 1
        assert "schema_version" in proc.stderr.read()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return dict(item.split("=", 1) for item in
                environ.decode().split("\0") if "=" in item)


def test_driver_waits_passively_by_default(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    assert _driver_environment(tmp_path, env)["OMP_WAIT_POLICY"] == "PASSIVE"


def test_a_users_wait_policy_is_kept(tmp_path):
    env = dict(os.environ, OMP_WAIT_POLICY="ACTIVE")
    assert _driver_environment(tmp_path, env)["OMP_WAIT_POLICY"] == "ACTIVE"


def test_negative_thread_count_is_refused(tmp_path):
    exe = require_driver()
    result = subprocess.run([str(exe), "--threads", "-1", "x.json"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1
    assert "--threads -1: must be >= 0" in result.stderr
