"""Assembly-scale checks (issue 43 item 2) on the three runs of
assembly_cases.py: a 26-disk compaction, a staged servo run and a
rigid+soft mixture.

Each run is checked (a) against invariants that do not depend on how the
run got there, at every output row, at about ten times what was measured
(2026-12-03, these runs): the energy balance, the penetration, the packing
fraction recomputed from the displacement field, and, where the assembly is
at rest, the stress estimates against each other and the servo walls'
target; and (b) against its committed reference series
(tests/python/reference/, assembly_cases.py rewrites it) to round-off.
"""

import numpy as np
import pytest

from assembly_cases import CASES, read_reference, run_case, series
from driver_required import require_driver
from softpack.analysis import fields
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table

pytestmark = pytest.mark.usefixtures("registry")

#: Largest |energy_residual| of any row (J), measured: compaction 5.1e-6,
#: servo 1.8e-6, mixed 2.4e-6 (of final wall works 0.23, 0.14, 0.027 J).
ENERGY_RESIDUAL = {"compaction": 5e-5, "servo": 2e-5, "mixed": 2.5e-5}
#: Largest penetration of any row (m), measured 5.7e-11, 5.2e-11, 4.8e-11.
PENETRATION = 6e-10
#: Phi from the deformed mesh's area against series.csv's Phi, measured
#: 5.1e-13, 4.4e-12, 5.0e-13 at most (round-off of the two sums).
PHI = 5e-11
#: Relative difference to the reference at any row: the same build gives
#: the same bits; this allows round-off only.
ROUND_OFF = 1e-10


_RUNS: dict = {}


def _run(name, tmp_path_factory):
    """The run directory of a case, run once per session."""
    require_driver()
    if name not in _RUNS:
        _RUNS[name] = run_case(name, tmp_path_factory.mktemp(name) / "run")
    return _RUNS[name]


@pytest.fixture(params=sorted(CASES))
def case(request, tmp_path_factory):
    """``(name, run directory)`` of each case."""
    return request.param, _run(request.param, tmp_path_factory)


def test_the_energy_balance_closes_at_every_row(case):
    name, out = case
    s = read_table(RunDirectory(out).series_csv)
    assert s["wall_work"][-1] > 0
    assert np.max(np.abs(s["energy_residual"])) < ENERGY_RESIDUAL[name]


def test_contacts_do_not_penetrate_at_any_row(case):
    _, out = case
    s = read_table(RunDirectory(out).series_csv)
    assert np.nanmax(s["max_penetration"]) < PENETRATION


def test_phi_is_the_deformed_particles_area_over_the_box(case):
    """The driver's Phi (particles' areas from its own integration) against
    the area of the deformed triangles of fields.h5 over the box's."""
    _, out = case
    run = RunDirectory(out)
    s, stress = read_table(run.series_csv), read_table(run.stress_csv)
    points, cells = fields.read_mesh(run.fields_h5)
    frames = fields.read_displacements(run.fields_h5)
    assert len(frames) == len(s["phi"])
    for (t, u), box, phi, time in zip(frames, stress["area"], s["phi"],
                                      s["time"]):
        assert t == pytest.approx(time, rel=1e-12)
        x = (points + u)[cells]
        a, b = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum()
        assert abs(area / box - phi) < PHI


def test_at_rest_the_stress_estimates_agree(tmp_path_factory):
    """At the end of the servo run's consolidation (kinetic energy 1.6e-4
    of the strain energy): contacts (Love-Weber) against the finite
    elements, measured 0.11 %; the servo walls against their 4 kPa
    target, measured 0.51 % (right) and 0.70 % (top)."""
    out = _run("servo", tmp_path_factory)
    run = RunDirectory(out)
    stage = read_table(run.raw.steps_csv)["stage"]
    stress = read_table(run.stress_csv)
    rest = int(np.flatnonzero(np.diff(stage))[0])
    assert abs(stress["difference_contact_fe"][rest]) < 1.1e-2
    for wall in ("right", "top"):
        assert stress[f"{wall}_stress"][rest] == pytest.approx(4000.0,
                                                               rel=7e-2)


def test_the_series_is_the_reference_to_round_off(case):
    name, out = case
    got, want = series(out), read_reference(name)
    assert list(got) == list(want)
    for column, values in want.items():
        np.testing.assert_allclose(
            got[column], values, rtol=ROUND_OFF,
            atol=ROUND_OFF * np.max(np.abs(values)),
            err_msg=f"{name}: {column} moved from the reference"
                    " (tests/python/assembly_cases.py rewrites it)")


def test_the_summary_names_each_stage_and_its_state(tmp_path_factory):
    """The end-of-run summary (issue 37 item 1): a line per stage naming
    the criterion that ended it, with Phi, P, q, the box's strains and Z
    over the particles it counts at the stage's last row."""
    from softpack.analysis.summary import summary_lines

    out = _run("servo", tmp_path_factory)
    run = RunDirectory(out)
    s, stress = read_table(run.series_csv), read_table(run.stress_csv)
    stage = read_table(run.raw.steps_csv)["stage"]
    lines = summary_lines(out)
    assert [line.split(":")[0] for line in lines] == [
        'stage 0 "consolidate"', 'stage 1 "axial"']
    assert "ended by equilibrium" in lines[0]
    assert "ended by strain" in lines[1]
    for k, line in enumerate(lines):
        last = int(np.flatnonzero(stage == k)[-1])
        assert f"Phi = {s['phi'][last]:.4f}" in line
        assert f"P = {stress['contact_P'][last] / 1e3:.4g} kPa" in line
        assert f"eps_v = {stress['eps_v'][last]:.4f}" in line
        total = sum(s[c][last] for c in ("retained", "rattlers",
                                         "unbalanced"))
        assert f"over {s['retained'][last]:.0f} of {total:.0f}" in line
    assert total == 14
    (line,) = summary_lines(_run("compaction", tmp_path_factory))
    assert line.startswith("stopped by packing_fraction after 473 steps")


def test_particles_csv_places_and_loads_each_particle(tmp_path_factory):
    """particles.csv's species, rigid flag, centroid, rotation and
    pressure (issue 37 item 2) on the rigid+soft run: the centroids and
    rotations against the deformed mesh of the fields (area centroids of
    the triangles; a rigid particle's rotation is that of all its nodes,
    least squares), the pressures summed against the finite elements'
    box pressure, and none inside a rigid particle."""
    out = _run("mixed", tmp_path_factory)
    run = RunDirectory(out)
    table, stress = read_table(run.particles_csv), read_table(run.stress_csv)
    species = np.array([0] * 5 + [1] * 5 + [2] * 2 + [3] * 2)  # the example
    rigid = np.isin(species, (1, 3))
    points, cells = fields.read_mesh(run.fields_h5)
    for (t, u), step, box, fe_p in zip(fields.read_displacements(
            run.fields_h5), stress["step"], stress["area"], stress["fe_P"]):
        rows = table["step"] == step
        np.testing.assert_array_equal(table["species"][rows], species)
        np.testing.assert_array_equal(table["rigid"][rows], rigid)
        pressure = table["pressure"][rows]
        assert np.isnan(pressure[rigid]).all()
        assert np.isfinite(pressure[~rigid]).all()
        area = table["area"][rows]
        assert np.sum(pressure[~rigid] * area[~rigid]) / box == \
            pytest.approx(fe_p, rel=1e-9, abs=1e-9)
        snap = fields.read_snapshot(run.fields_h5, t)
        x = (points + u)[cells]
        a, b = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        tri = 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        centre = x.mean(axis=1)
        for p in range(len(species)):
            mine = snap.body == p
            c = (tri[mine, None] * centre[mine]).sum(0) / tri[mine].sum()
            assert table["centroid_x"][rows][p] == pytest.approx(c[0],
                                                                 abs=1e-12)
            assert table["centroid_y"][rows][p] == pytest.approx(c[1],
                                                                 abs=1e-12)
            if rigid[p]:
                nodes = np.unique(cells[mine])
                r0 = points[nodes] - points[nodes].mean(0)
                r = (points + u)[nodes] - (points + u)[nodes].mean(0)
                angle = np.arctan2(np.sum(r0[:, 0] * r[:, 1] - r0[:, 1]
                                          * r[:, 0]), np.sum(r0 * r))
                assert table["rotation"][rows][p] == pytest.approx(
                    angle, abs=1e-12)


@pytest.mark.parametrize("name", ["mixed", "servo"])
def test_the_network_carries_each_particles_and_walls_forces(
        name, tmp_path_factory):
    """network.csv (issue 37 item 2) against what the driver and the
    analysis wrote independently of it, at every output step: the pair
    forces on each particle sum to its resultant (particles.csv, from the
    nodal contacts), those on a wall to the force the wall received
    (raw/steps.csv); walls press (fn > 0) and their branch vectors run
    along their normals (measured agreement: 3e-10 of the step's largest
    pair force, raw/contacts' 10 digits summed)."""
    out = _run(name, tmp_path_factory)
    run = RunDirectory(out)
    net, table = read_table(run.network_csv), read_table(run.particles_csv)
    steps = read_table(run.raw.steps_csv)
    walls = [w for w in ("left", "right", "bottom", "top")]
    thickness = 0.015  # the examples' [model] thickness
    assert len(net["step"]) > 0
    for k, step in enumerate(steps["step"]):
        rows = net["step"] == step
        a, b = net["a"][rows].astype(int), net["b"][rows].astype(int)
        force = np.column_stack((net["fx"][rows], net["fy"][rows]))
        count = int(np.sum(table["step"] == step))
        total = np.zeros((count, 2))
        np.add.at(total, a, force)
        np.add.at(total, b[b >= 0], -force[b >= 0])
        scale = max(np.abs(force).max(initial=0.0), 1e-30)
        resultant = table["resultant_force"][table["step"] == step]
        np.testing.assert_allclose(np.hypot(*total.T), resultant, rtol=0,
                                   atol=3e-9 * scale)
        for w, wall in enumerate(walls):
            on_wall = -force[b == -1 - w].sum(axis=0) / thickness
            np.testing.assert_allclose(
                on_wall, [steps[f"{wall}_fx"][k], steps[f"{wall}_fy"][k]],
                rtol=0, atol=3e-9 * scale / thickness)
        to_walls = b < 0
        assert (net["fn"][rows][to_walls] > 0).all()
        horizontal = np.isin(b, (-1, -2))  # left, right: branch along x
        assert (net["branch_y"][rows][horizontal] == 0).all()
        assert (net["branch_x"][rows][np.isin(b, (-3, -4))] == 0).all()


def test_snapshots_draw_the_walls_where_they_are(tmp_path_factory,
                                                 tmp_path):
    """``./softpack plot RUN --at stage=0 --at last`` on the staged servo
    run (issue 37 item 3): PNG and PDF written; in each panel the four
    walls are drawn at their positions of raw/steps.csv at the frame
    drawn (the servo walls moved: a box [0, L - delta] x [0, W] would not
    be)."""
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    from softpack.plots import paper, snapshots

    out = _run("servo", tmp_path_factory)
    figures = tmp_path / "fig"
    assert paper.main([str(out), "--at", "stage=0", "--at", "last",
                       "--out", str(figures)]) == 0
    for name in ("snapshots.png", "snapshots.pdf"):
        assert (figures / name).stat().st_size > 10_000
    steps = read_table(RunDirectory(out).raw.steps_csv)
    stage_end = int(np.flatnonzero(np.diff(steps["stage"]))[0])
    fig = snapshots.snapshot_figure(out, [("stage", 0.0), ("last", np.nan)])
    for ax, k in zip(fig.axes, (stage_end, len(steps["step"]) - 1)):
        walls = {line.get_gid(): line for line in ax.lines
                 if (line.get_gid() or "").startswith("wall:")}
        assert sorted(walls) == ["wall:bottom", "wall:left", "wall:right",
                                 "wall:top"]
        x0, x1 = steps["left_x"][k], steps["right_x"][k]
        y0, y1 = steps["bottom_y"][k], steps["top_y"][k]
        assert list(walls["wall:right"].get_xdata()) == [x1, x1]
        assert list(walls["wall:top"].get_ydata()) == [y1, y1]
        assert list(walls["wall:left"].get_ydata()) == [y0, y1]
        assert list(walls["wall:bottom"].get_xdata()) == [x0, x1]
    assert steps["right_x"][stage_end] != steps["right_x"][-1]
    with pytest.raises(RunError, match="stage=5"):
        snapshots.snapshot_figure(out, [("stage", 5.0)])
