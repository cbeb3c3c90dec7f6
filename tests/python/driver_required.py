"""The one skip of the tests that run softpack-simulate."""

import pytest


def require_driver():
    """softpack-simulate's path; skips the calling test (or fixture) when
    it is not built: ``./softpack test`` builds it first."""
    from softpack.contract.run_directory import RunError
    from softpack.simulation import driver
    try:
        return driver.executable()
    except RunError:
        pytest.skip("softpack-simulate is not built (run ./softpack test)")
