"""A pytest plugin: under ``./softpack test`` (``SOFTPACK_STRICT_SKIPS=1``)
a skipped test fails the run unless its reason is on the allow-list below,
so that a green suite never hides a physics test that did not run (a
missing driver, a missing package). The skips and their reasons are listed
at the end of every run (``-rs``).
"""

import os

#: Skip reasons that do not fail ``./softpack test`` (a substring of the
#: reason, and why it may skip): none today; every test runs on the
#: project's machine.
ALLOWED_SKIPS: dict = {}

_skipped = []


def pytest_runtest_logreport(report):
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) \
            else str(report.longrepr)
        _skipped.append((report.nodeid, reason))


def unexpected(skipped, allowed=None) -> list:
    """The (test, reason) of the skips no allowed reason covers."""
    allowed = ALLOWED_SKIPS if allowed is None else allowed
    return [(node, reason) for node, reason in skipped
            if not any(key in reason for key in allowed)]


def pytest_sessionfinish(session, exitstatus):
    if os.environ.get("SOFTPACK_STRICT_SKIPS") != "1":
        return
    bad = unexpected(_skipped)
    if bad:
        print(f"\n{len(bad)} test(s) skipped for a reason not on the"
              " allow-list (tests/python/strict_skips.py): under"
              " ./softpack test a skip is a failure")
        for node, reason in bad:
            print(f"  {node}: {reason}")
        session.exitstatus = 1
