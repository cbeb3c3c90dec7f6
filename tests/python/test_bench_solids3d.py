"""./softpack bench --solids3d (softpack.bench.solids3d): its report's
structure on the smallest scene it accepts, in seconds. Not a timed test:
nothing is asserted about speed, only that the numbers are there, positive
and consistent with one another."""

import json
import math

import numpy as np
import pytest

from softpack.bench import solids3d
from softpack.paths import executable


def _built() -> bool:
    try:
        return (executable("softpack-simulate").exists()
                and executable("softpack-bench-nlgs").exists())
    except Exception:
        return False


pytestmark = pytest.mark.skipif(not _built(), reason="driver not built")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    # 7.5 mm: the coarsest the example's scene accepts (8 elements around
    # the 20 mm cylinders); a few steps from phi_base 0.69
    work = tmp_path_factory.mktemp("solids3d")
    return solids3d.bench_solids3d(sizes=[7.5e-3, 7.0e-3], steps=3, warm=2,
                                   compact_to=0.69, work=work)


def test_report_has_one_row_per_size_with_its_mesh(report):
    rows = report["rows"]
    assert [r["element_size"] for r in rows] == [7.5e-3, 7.0e-3]
    for r in rows:
        assert r["bodies"] == 14
        assert r["tetrahedra"] > r["nodes"] > 0
        assert r["compaction_steps"] > 0
        assert r["compaction_reason"] == "base_area_fraction"
    # the finer mesh has more tetrahedra
    assert rows[1]["tetrahedra"] > rows[0]["tetrahedra"]
    json.dumps(report)  # what ./softpack bench writes


def test_timed_steps_start_compacted_and_are_split_by_part(report):
    for r in report["rows"]:
        assert r["first_step"] == r["compaction_steps"]
        assert r["steps"] == 3
        assert r["phi_base_start"] >= 0.69
        assert r["phi_base_end"] > r["phi_base_start"]
        assert r["contacts"] >= r["active_contacts"] > 0
        assert r["sweeps_per_step"] > 0 and r["newton_per_step"] >= 1
        assert r["ms_per_step"] == pytest.approx(
            1e3 * r["seconds"] / r["steps"])
        parts = [r[f"ms_{p}"] for p in solids3d.PARTS]
        assert all(p >= 0 for p in parts)
        assert r["ms_nlgs"] > 0 and r["ms_delassus"] > 0
        # the parts are inside the step's wall time, the rest is "other"
        assert r["ms_other"] >= 0
        assert sum(parts) + r["ms_other"] == pytest.approx(r["ms_per_step"])
        assert r["ms_per_sweep"] == pytest.approx(
            r["ms_nlgs"] / r["sweeps_per_step"])
        assert r["peak_memory_mb"] > 0
        assert 0 < r["ms_per_step_median"] <= r["ms_per_step_max"]
        assert 0 <= r["refactorizations"] <= r["steps"]
        assert r["converged"] == (r["newton_unconverged_steps"]
                                  + r["nlgs_unconverged_steps"] == 0)


def test_yardstick_and_exponents(report):
    for key in ("nlgs_yardstick_before", "nlgs_yardstick_after",
                "nlgs_yardstick"):
        assert report[key] > 0
    exps = report["exponents"]
    assert {"ms_per_step", "ms_per_sweep", "peak_memory_mb",
            "contacts"} <= set(exps)
    assert all(math.isfinite(v) for v in exps.values()
               if not isinstance(v, dict))
    assert solids3d.table(report)


def test_power_fit_recovers_a_known_exponent():
    n = np.array([1e3, 4e3, 2e4, 1e5])
    assert solids3d.power_fit(n, 3.0 * n**1.1) == pytest.approx(1.1)


def test_timed_cost_skips_the_warm_steps():
    rows = {"step": np.array([59, 60, 62, 64, 65]),
            "seconds": np.array([1.0, 2.0, 2.5, 3.0, 3.25]),
            "contacts": np.array([0, 10, 12, 14, 16]),
            "active_contacts": np.array([0, 1, 2, 3, 4]),
            "nlgs_iterations": np.array([0, 5, 6, 7, 8]),
            "newton_iterations": np.array([0, 2, 2, 2, 2]),
            # a state's carried counts (1) and one of this run's steps
            "newton_unconverged_steps": np.array([1, 1, 1, 2, 2]),
            "nlgs_unconverged_steps": np.array([0, 0, 0, 0, 0]),
            "refactorized": np.array([0, 1, 0, 1, 0]),
            "phi_base": np.array([0.7, 0.71, 0.72, 0.73, 0.74])}
    for part in solids3d.PARTS:
        rows[f"seconds_{part}"] = rows["seconds"] / 10
    out = solids3d.timed_cost(rows, warm=2)
    # from step 62 (the first row >= 59 + 2) to 65
    assert out["steps"] == 3
    assert out["ms_per_step"] == pytest.approx(1e3 * 0.75 / 3)
    assert out["ms_nlgs"] == pytest.approx(1e3 * 0.075 / 3)
    assert out["contacts"] == pytest.approx(15)
    assert out["phi_base_start"] == pytest.approx(0.72)
    assert out["newton_unconverged_steps"] == 1
    assert out["refactorizations"] == 1  # step 64's, after 62
    # 0.5 s over 2 steps, then 0.25 s over 1
    assert out["ms_per_step_median"] == pytest.approx(250)
    assert out["ms_per_step_max"] == pytest.approx(250)
    assert out["nlgs_unconverged_steps"] == 0
    with pytest.raises(ValueError):
        solids3d.timed_cost(rows, warm=10)
