"""Issue 16 item 6: two ./softpack commands started together share one build.

``./softpack`` takes a lock on ``BUILD/.softpack.lock`` around configure and
build. The test holds that lock itself, starts ``./softpack build``, checks
that it waits (and says so) instead of building beside the holder, then
releases the lock and checks that the build completes.
"""

import fcntl
import os
import subprocess
import time

import pytest

from softpack import paths


def test_a_second_build_waits_for_the_lock():
    script = paths.ROOT / "softpack"
    if not (paths.BUILD / "CMakeCache.txt").is_file():
        pytest.skip("no configured build directory")
    env = dict(os.environ, SOFTPACK_BUILD_DIR=str(paths.BUILD))
    with open(paths.BUILD / ".softpack.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        proc = subprocess.Popen([str(script), "build"], env=env,
                                stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        try:
            time.sleep(3.0)
            assert proc.poll() is None, proc.communicate()
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
    _, err = proc.communicate(timeout=900)
    assert proc.returncode == 0, err
    assert "waiting for another softpack command to finish building" in err


@pytest.mark.parametrize("argv", [["plot", "--help"], ["plot-loading", "-h"],
                                  ["run", "--help"], ["bench", "--help"]])
def test_what_needs_no_build_does_not_build(argv, tmp_path):
    """Issue 37 item 5: the figures and a subcommand's --help run without
    configuring or building (an empty build directory stays empty)."""
    build = tmp_path / "build"
    build.mkdir()
    env = dict(os.environ, SOFTPACK_BUILD_DIR=str(build))
    result = subprocess.run([str(paths.ROOT / "softpack"), *argv], env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "usage: softpack" in result.stdout
    assert list(build.iterdir()) == []
