"""Under ./softpack test a skip not on the allow-list fails the run (issue
43: a green suite without a build reported every physics test skipped)."""

import os
import subprocess
import sys
from pathlib import Path

import strict_skips

HERE = Path(__file__).resolve().parent


def test_a_skip_off_the_allow_list_is_unexpected():
    skipped = [("a.py::t", "softpack-simulate is not built"),
               ("b.py::u", "no gmsh here")]
    assert strict_skips.unexpected(skipped, {}) == skipped
    assert strict_skips.unexpected(skipped, {"no gmsh": "why"}) == [
        skipped[0]]


def test_a_strict_run_with_a_skip_fails(tmp_path):
    (tmp_path / "test_one.py").write_text(
        "import pytest\n\ndef test_skips():\n    pytest.skip('not here')\n")
    env = dict(os.environ, PYTHONPATH=str(HERE))
    command = [sys.executable, "-m", "pytest", "-q", "-p", "strict_skips",
               "-p", "no:cacheprovider", str(tmp_path)]
    lenient = subprocess.run(command, env=dict(env, SOFTPACK_STRICT_SKIPS=""),
                             capture_output=True, text=True, cwd=tmp_path)
    strict = subprocess.run(command, env=dict(env, SOFTPACK_STRICT_SKIPS="1"),
                            capture_output=True, text=True, cwd=tmp_path)
    assert lenient.returncode == 0, lenient.stdout
    assert strict.returncode == 1, strict.stdout
    assert "not on the allow-list" in strict.stdout
    assert "test_one.py::test_skips: Skipped: not here" in strict.stdout
