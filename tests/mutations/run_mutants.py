#!/usr/bin/python3
"""The mutation check (issue 43, item 5): every listed defect must fail a test.

Each mutant of ``tests/mutations/mutants.toml`` is a realistic single defect
(one line or expression of the driver or of the analysis). This script

1. makes one scratch copy of the repository's HEAD (``git worktree add
   --detach`` into a new temporary directory, with ``<tmp>/shared`` ->
   the repository's ``../shared`` beside it, which tests read data from),
2. builds it (``./softpack build``) and, unless ``--no-baseline``, runs the
   whole suite once unmutated: it must pass,
3. for each mutant: replaces its ``original`` text (which must occur exactly
   once) by its ``replacement``, rebuilds if the file is not under
   ``python/``, runs the suite until the first failure (a C++ mutant:
   ``ctest --stop-on-failure`` then ``pytest -x``; a Python mutant: ``pytest
   -x`` then ``ctest``; with ``--all`` the whole suite) and records killed
   or survived, the first failing test(s) (every one with ``--all``) and
   the wall time; then writes the file back (and rebuilds),
4. prints a markdown table (mutant, description, killed by, seconds) and
   removes the scratch copy.

The suite is the one of ``./softpack test``: CTest in ``build/`` and
``pytest -q -rs tests/python`` with ``SOFTPACK_STRICT_SKIPS=1``, under the
environment of ``./softpack env``. A test that hangs fails the suite, so
a hang counts as a kill: each CTest test is stopped after
``--test-timeout`` seconds (default 120; unmutated, the longest takes
under 2 s) and each half of the suite after ``--timeout`` seconds (default
1800; pytest has no per-test timeout here). On SIGTERM or Ctrl-C the
running tests are stopped and the scratch copy removed.

Usage (from the repository root; stdlib only; not part of CI: about 13
minutes on two cores, of which the build 1-2, the unmutated suite 4 and a
mutant 5 s to 2 min)::

    export CMAKE_CXX_COMPILER_LAUNCHER=ccache   # optional: cached builds
    /usr/bin/python3 tests/mutations/run_mutants.py [--only ID]...
        [--all] [--no-baseline] [--keep] [--jobs N] [--timeout S]
        [--test-timeout S] [--table FILE] [--list]

Only committed files are used: the copy is of HEAD (the script says so
when the work tree has changes). With ``CMAKE_CXX_COMPILER_LAUNCHER`` set
(ccache), ``CCACHE_BASEDIR`` is set to the temporary directory, so that the
objects of one run are found again by the next one.

Exit status: 0 when the unmutated copy builds and passes and every mutant
is killed; 1 when a mutant survives or cannot be applied (its text is not
found exactly once, or it does not compile: a mutant must build to count);
2 when the unmutated copy does not build or its suite fails.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
MUTANTS = HERE / "mutants.toml"


@dataclass
class Mutant:
    """One entry of mutants.toml."""

    id: str
    description: str
    file: str
    original: str
    replacement: str

    @property
    def python(self) -> bool:
        """A change under python/: nothing to rebuild, pytest first."""
        return self.file.startswith("python/")


@dataclass
class Outcome:
    """What the suite said about one mutant (or the unmutated copy)."""

    status: str                 # killed, survived, not applied, build failed
    killed_by: list = field(default_factory=list)
    seconds: float = 0.0
    note: str = ""


def load_mutants(path: Path = MUTANTS) -> list[Mutant]:
    """The mutants of ``path``, their ids checked unique."""
    with open(path, "rb") as f:
        entries = tomllib.load(f)["mutant"]
    mutants = [Mutant(**e) for e in entries]
    ids = [m.id for m in mutants]
    if len(set(ids)) != len(ids):
        sys.exit(f"run_mutants: duplicate ids in {path}")
    return mutants


def log(message: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {message}", file=sys.stderr,
          flush=True)


class Scratch:
    """A detached worktree of HEAD in a temporary directory."""

    def __init__(self, jobs: int, timeout: float, test_timeout: float,
                 keep: bool):
        self.jobs, self.timeout, self.keep = jobs, timeout, keep
        self.test_timeout = test_timeout
        self.tmp = Path(tempfile.mkdtemp(prefix="softpack-mutants-"))
        self.root = self.tmp / "repo"
        self.commit = git("rev-parse", "HEAD").strip()
        git("worktree", "add", "--detach", "--quiet", str(self.root),
            self.commit)
        shared = REPO.parent / "shared"
        if shared.exists():
            (self.tmp / "shared").symlink_to(shared.resolve())
        self.env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1",
                        SOFTPACK_JOBS=str(jobs), SOFTPACK_STRICT_SKIPS="1")
        if "CMAKE_CXX_COMPILER_LAUNCHER" in self.env:
            self.env["CCACHE_BASEDIR"] = str(self.tmp)
        self.junit = self.tmp / "junit"
        self.junit.mkdir()
        self.built_clean = True

    def remove(self) -> None:
        if self.keep:
            log(f"kept the scratch copy {self.root}")
            return
        git("worktree", "remove", "--force", str(self.root))
        git("worktree", "prune")
        shutil.rmtree(self.tmp, ignore_errors=True)

    def build(self) -> bool:
        """``./softpack build``; False (the log's tail shown) on failure."""
        status, out = self._spawn(["./softpack", "build"])
        if status != 0:
            log("build failed:\n" + out[-3000:])
        return status == 0

    def _run(self, command: list[str], cwd: Path) -> tuple[int | None, str]:
        """Run ``command`` in ``cwd`` under ``./softpack env``."""
        script = 'eval "$(./softpack env)" && cd "$0" && exec "$@"'
        return self._spawn(["bash", "-c", script, str(cwd), *command])

    def _spawn(self, command: list[str]) -> tuple[int | None, str]:
        """Run ``command`` in the copy in its own process group; (status,
        output), status None on timeout. On a timeout or an exception
        (SIGTERM, Ctrl-C) the whole group is killed."""
        proc = subprocess.Popen(
            command, cwd=self.root, env=self.env, stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT, text=True, start_new_session=True)
        try:
            out, _ = proc.communicate(timeout=self.timeout)
            return proc.returncode, out
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, _ = proc.communicate()
            return None, out
        except BaseException:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            raise

    def ctest(self, stop_early: bool) -> tuple[bool | None, list[str], str]:
        """CTest; (passed, failing test names, output); passed None on a
        timeout."""
        report = self.junit / "ctest.xml"
        report.unlink(missing_ok=True)
        command = ["ctest", "-j", str(self.jobs), "--timeout",
                   str(self.test_timeout), "--output-junit", str(report)]
        if stop_early:
            command.append("--stop-on-failure")
        status, out = self._run(command, self.root / "build")
        # A test past --test-timeout: "Test #N: NAME ....***Timeout"
        failed = [f"{name} (hung: stopped at {self.test_timeout:.0f} s)"
                  if re.search(re.escape(name) + r"[ .]*\*\*\*Timeout", out)
                  else name for name in junit_failures(report)]
        if status is None:
            return None, failed or ["timeout (ctest)"], out
        if status != 0 and not failed:
            failed = ["ctest: " + last_lines(out)]
        return status == 0, failed, out

    def pytest(self, stop_early: bool) -> tuple[bool | None, list[str], str]:
        """pytest over tests/python as ./softpack test runs it."""
        report = self.junit / "pytest.xml"
        report.unlink(missing_ok=True)
        command = ["/usr/bin/python3", "-m", "pytest", "-q", "-rs",
                   "-p", "no:cacheprovider", f"--junitxml={report}",
                   str(self.root / "tests" / "python")]
        if stop_early:
            command.insert(3, "-x")
        status, out = self._run(command, self.root)
        failed = junit_failures(report)
        if status is None:
            return None, failed or ["timeout (pytest)"], out
        if status != 0 and not failed:
            failed = ["pytest: " + last_lines(out)]
        return status == 0, failed, out

    def suite(self, python_first: bool, stop_early: bool):
        """Both halves of the suite; stop at the first failing half when
        ``stop_early``. Returns (passed, failing tests, output of the
        failing half)."""
        halves = [self.pytest, self.ctest]
        if not python_first:
            halves.reverse()
        failed, output, passed = [], "", True
        for half in halves:
            ok, names, out = half(stop_early)
            if not ok:
                passed = False
                failed += names if ok is False else names + ["(timeout)"]
                output += out
                if stop_early:
                    break
        return passed, failed, output


def git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=REPO, check=True,
                          stdout=subprocess.PIPE, text=True).stdout


def junit_failures(path: Path) -> list[str]:
    """Names of the failed or erroring test cases of a JUnit XML report."""
    if not path.is_file():
        return []
    try:
        tree = ET.parse(path)
    except ET.ParseError:
        return []
    names = []
    for case in tree.iter("testcase"):
        bad = case.get("status") == "fail" or any(
            child.tag in ("failure", "error") for child in case)
        if bad:
            cls = case.get("classname", "")
            # A value-parametrized GoogleTest's name ends in "  # GetParam()
            # = <bytes>": the name without it
            name = case.get("name", "").split("  # GetParam()")[0]
            names.append(f"{cls}::{name}" if cls and cls != name else name)
    return names


def last_lines(text: str, n: int = 3) -> str:
    return " / ".join(line.strip() for line in text.strip().splitlines()[-n:])


def apply(root: Path, mutant: Mutant) -> str | None:
    """Write the mutant into the scratch copy; return the original file's
    text, or None when ``original`` does not occur exactly once."""
    path = root / mutant.file
    text = path.read_text()
    if text.count(mutant.original) != 1:
        return None
    path.write_text(text.replace(mutant.original, mutant.replacement))
    return text


def run_mutant(scratch: Scratch, mutant: Mutant, every: bool) -> Outcome:
    """Apply, build, run the suite (to its first failing half, or all of it
    with ``every``), revert."""
    start = time.monotonic()
    original = apply(scratch.root, mutant)
    if original is None:
        return Outcome("not applied", note="original text not found once")
    try:
        if not mutant.python:
            if not scratch.build():
                return Outcome("build failed",
                               seconds=time.monotonic() - start)
        passed, failed, _ = scratch.suite(python_first=mutant.python,
                                          stop_early=not every)
        seconds = time.monotonic() - start
        return Outcome("survived" if passed else "killed", failed, seconds)
    finally:
        (scratch.root / mutant.file).write_text(original)
        if not mutant.python and not scratch.build():
            sys.exit("run_mutants: the reverted copy does not build")


def table(mutants: list[Mutant], outcomes: dict[str, Outcome]) -> str:
    rows = ["| mutant | description | killed by (first failing test) |"
            " time (s) |", "| --- | --- | --- | --- |"]
    for m in mutants:
        if m.id not in outcomes:
            continue
        o = outcomes[m.id]
        if o.status == "killed":
            shown = o.killed_by[:4]
            by = "<br>".join(f"`{name}`" for name in shown)
            if len(o.killed_by) > len(shown):
                by += f"<br>and {len(o.killed_by) - len(shown)} more"
        else:
            by = f"**{o.status.upper()}** {o.note}".strip()
        rows.append(f"| `{m.id}` | {m.description} | {by} |"
                    f" {o.seconds:.0f} |")
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", action="append", metavar="ID",
                        help="run this mutant only (repeatable)")
    parser.add_argument("--list", action="store_true",
                        help="list the mutants and check each one's text"
                             " occurs once in HEAD; build nothing")
    parser.add_argument("--all", action="store_true",
                        help="run the whole suite on each mutant and list"
                             " every failing test (slow: 5-20 min a mutant)")
    parser.add_argument("--no-baseline", action="store_true",
                        help="skip the unmutated suite (the build is still"
                             " checked)")
    parser.add_argument("--keep", action="store_true",
                        help="keep the scratch copy (its path is printed)")
    parser.add_argument("--jobs", type=int,
                        default=int(os.environ.get("SOFTPACK_JOBS",
                                                   os.cpu_count() or 1)),
                        help="build and ctest jobs (default: SOFTPACK_JOBS"
                             " or the number of cores)")
    parser.add_argument("--timeout", type=float, default=1800,
                        help="seconds for one half of the suite (default"
                             " 1800); past it the half counts as failed")
    parser.add_argument("--test-timeout", type=float, default=120,
                        help="seconds for one CTest test (default 120)")
    parser.add_argument("--table", type=Path,
                        help="also write the markdown table to this file")
    args = parser.parse_args(argv)

    mutants = load_mutants()
    if args.only:
        unknown = set(args.only) - {m.id for m in mutants}
        if unknown:
            parser.error(f"unknown mutant(s): {', '.join(sorted(unknown))}")
        mutants = [m for m in mutants if m.id in args.only]
    if args.list:
        bad = 0
        for m in mutants:
            text = git("show", f"HEAD:{m.file}")
            found = text.count(m.original)
            bad += found != 1
            print(f"{m.id:28s} {m.file:42s} found {found}x  {m.description}")
        return 1 if bad else 0

    if git("status", "--porcelain", "--untracked-files=no").strip():
        log("note: the work tree has uncommitted changes; the copy is of"
            " HEAD without them")
    begin = time.monotonic()
    # SIGTERM as Ctrl-C: the tests stopped, the copy removed (finally).
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(128 + signal.SIGTERM))
    scratch = Scratch(args.jobs, args.timeout, args.test_timeout, args.keep)
    outcomes: dict[str, Outcome] = {}
    try:
        log(f"scratch copy of {scratch.commit[:10]} in {scratch.root};"
            " building")
        t0 = time.monotonic()
        if not scratch.build():
            log("the unmutated copy does not build")
            return 2
        log(f"built in {time.monotonic() - t0:.0f} s")
        if not args.no_baseline:
            t0 = time.monotonic()
            passed, failed, output = scratch.suite(python_first=False,
                                                   stop_early=False)
            log(f"unmutated suite: {'passed' if passed else 'FAILED'} in"
                f" {time.monotonic() - t0:.0f} s")
            if not passed:
                print(output[-5000:], file=sys.stderr)
                log("failing unmutated: " + ", ".join(failed))
                return 2
        for m in mutants:
            log(f"mutant {m.id} ({m.file})")
            o = outcomes[m.id] = run_mutant(scratch, m, args.all)
            log(f"  {o.status} in {o.seconds:.0f} s"
                + (f" by {', '.join(o.killed_by)}" if o.killed_by else ""))
    finally:
        scratch.remove()
    text = table(mutants, outcomes)
    total = time.monotonic() - begin
    footer = (f"\n{sum(o.status == 'killed' for o in outcomes.values())} of"
              f" {len(outcomes)} mutants killed; commit {scratch.commit[:10]},"
              f" {time.strftime('%Y-%m-%d')}, {total / 60:.0f} min in all")
    print(text + "\n" + footer)
    if args.table:
        args.table.write_text(text + "\n" + footer + "\n")
    return 0 if all(o.status == "killed" for o in outcomes.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
