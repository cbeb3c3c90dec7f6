"""Run a command that must refuse its input: pass only if it exits with
the given status, its standard error matches the pattern and the file it
would have written does not exist.

usage: expect_refusal.py STATUS PATTERN ABSENT_FILE -- COMMAND...

(CTest's PASS_REGULAR_EXPRESSION alone would pass a command that prints
the message and still exits 0, or writes its output anyway.)
"""

import re
import subprocess
import sys
from pathlib import Path


def main(argv: list[str]) -> int:
    if len(argv) < 6 or argv[4] != "--":
        print(__doc__, file=sys.stderr)
        return 2
    status, pattern, absent = int(argv[1]), argv[2], Path(argv[3])
    absent.unlink(missing_ok=True)
    p = subprocess.run(argv[5:], capture_output=True, text=True, timeout=120)
    sys.stdout.write(p.stdout)
    sys.stderr.write(p.stderr)
    failures = []
    if p.returncode != status:
        failures.append(f"exit status {p.returncode}, expected {status}")
    if not re.search(pattern, p.stderr):
        failures.append(f"standard error does not match {pattern!r}")
    if absent.exists():
        failures.append(f"{absent} was written")
    for failure in failures:
        print(f"expect_refusal: {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
