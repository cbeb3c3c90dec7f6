"""The invariance comparison used by ./softpack bench --invariance."""

import numpy as np
import pytest

from softpack.bench import compare_series


def _series(scale_phi=1.0, shift_z=0.0):
    eps = np.linspace(0.0, 0.05, 11)
    phi = 0.75 * np.exp(eps) * scale_phi
    return {"eps": list(eps), "phi": list(phi),
            "E_over_WHLmu": list((phi - 0.74) ** 2),
            "z": list(3 + 10 * (phi - 0.75) + shift_z)}


def test_identical_runs_differ_by_nothing():
    d = compare_series(_series(), _series())
    assert d["phi_max_relative_difference"] == pytest.approx(0, abs=1e-15)
    assert d["energy_max_relative_difference"] == pytest.approx(0, abs=1e-12)
    assert d["z_max_difference"] == pytest.approx(0, abs=1e-12)
    assert d["eps_range"] == pytest.approx([0.0, 0.05])


def test_known_differences_are_measured():
    d = compare_series(_series(), _series(scale_phi=1.001, shift_z=0.03))
    assert d["phi_max_relative_difference"] == pytest.approx(1e-3, rel=1e-6)
    assert d["z_max_difference"] == pytest.approx(0.03, abs=2e-3)
