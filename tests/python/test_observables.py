"""The paper's observables on small hand-built raw outputs (no C++ needed)."""

import json
import math

import numpy as np
import pytest

from fake_runs import write_rules, write_setup
from softpack.analysis import connectivity as net_
from softpack.contract.run_directory import RunDirectory
from softpack.analysis import observables as obs
from softpack.analysis.setup import Rules, read_setup
from softpack.analysis.strain import cumulative_strain
from softpack.contract.tables import read_table

# the hand-built contacts below exercise the piston-force reading with the
# excluded particles' contacts dropped (test_exclusion_rule.py: all readings)
RULES = Rules(force_threshold=1e-4, unbalanced_threshold=1e-3,
              rule="loaded_nodes", unbalanced_reference="piston_force",
              excluded_contacts="dropped")

F = 1000.0   # piston force (N/m), two nodes of F/2 at each end of the chain
G = 100.0    # per-node force of an unbalanced particle on the bottom wall
EPS_G = 0.4  # per-node force of a particle resting on the unbalanced one


def contacts(rows):
    """Contact columns from rows (candidate, node, antagonist, wall, fn,
    ft, fx, fy)."""
    data = np.array(rows, dtype=float).reshape(-1, 8)
    table = {name: data[:, j] for j, name in enumerate(net_.CONTACT_COLUMNS)}
    for name in ("candidate", "node", "antagonist", "wall"):
        table[name] = table[name].astype(np.int64)
    return table


def chain_contacts():
    """Five particles (walls 0 left, 1 piston, 2 bottom, 3 top):

    left | 0 | 1 | piston, balanced, each contact on two nodes;
    2 touches 1 with one node and a force under f_p* (rattler);
    3 pressed on the bottom wall by 2 x G (unbalanced);
    4 rests on 3 only, with two small active nodes (rattler once 3 goes).
    """
    h = F / 2
    return contacts([
        (0, 10, -1, 0, h, 0, h, 0), (0, 11, -1, 0, h, 0, h, 0),
        (0, 20, 1, -1, h, 0, -h, 0), (0, 21, 1, -1, h, 0, -h, 0),
        (1, 30, -1, 1, h, 0, -h, 0), (1, 31, -1, 1, h, 0, -h, 0),
        (2, 40, 1, -1, 0.2, 0, 0, -0.2),
        (3, 50, -1, 2, G, 0, 0, G), (3, 51, -1, 2, G, 0, 0, G),
        (4, 60, 3, -1, EPS_G, 0, EPS_G, 0), (4, 61, 3, -1, EPS_G, 0, EPS_G, 0),
        (2, 41, 0, -1, 0.0, 0, 0, 0),  # an open contact: fn = 0
    ])


def test_cumulative_strain_is_eq_11():
    assert cumulative_strain(0.0, 0.286) == 0.0
    delta = 0.286 * (1 - math.exp(-0.1))
    assert cumulative_strain(delta, 0.286) == pytest.approx(0.1)


def test_normalised_energy_is_E_over_WHLmu():
    w, length, h, mu = 0.202, 0.286, 0.015, 0.15e6
    per_length = 0.02 * w * length * mu  # J/m
    e = h * per_length
    assert obs.normalised_energy(per_length, w, length, mu) == \
        pytest.approx(e / (w * h * length * mu))


def test_coefficient_of_variation():
    assert obs.coefficient_of_variation([1.0, 2.0, 3.0]) == \
        pytest.approx(math.sqrt(2 / 3) / 2)
    assert obs.coefficient_of_variation([2.0, 2.0]) == 0.0
    assert math.isnan(obs.coefficient_of_variation([]))
    assert math.isnan(obs.coefficient_of_variation([0.0, 0.0]))


def test_active_mask_is_relative_to_largest_force():
    mask = net_.active_mask([1.0, 1e-5, 0.0, 2e-4, 5e-5], 1e-4)
    assert mask.tolist() == [True, False, False, True, False]


@pytest.mark.parametrize("rule, expected", [
    ("loaded_nodes", [(0, 1), (0, 3), (1, 2)]),
    ("candidate_nodes", [(0, 3)]),
])
def test_two_node_rule(rule, expected):
    c = contacts([
        (0, 1, 1, -1, 1, 0, 0, 0), (0, 2, 1, -1, 1, 0, 0, 0),  # 2 nodes, 0->1
        (1, 5, 2, -1, 1, 0, 0, 0), (2, 7, 1, -1, 1, 0, 0, 0),  # 1 each way
        (2, 8, 3, -1, 1, 0, 0, 0),                             # 1 node only
        (2, 8, 3, -1, 1, 0, 0, 0),                             # same node
        (0, 3, 3, -1, 1, 0, 0, 0), (0, 4, 3, -1, 1, 0, 0, 0),  # 2 + 2 nodes
        (3, 9, 0, -1, 1, 0, 0, 0), (3, 10, 0, -1, 1, 0, 0, 0),
        (1, 6, 3, -1, 1e-9, 0, 0, 0), (1, 7, 3, -1, 1e-9, 0, 0, 0),  # ~0
    ])
    active = net_.active_mask(c["fn"], 1e-4)
    pairs = net_.force_bearing_pairs(c["candidate"], c["node"],
                                    c["antagonist"], active, rule)
    assert [tuple(p) for p in pairs] == expected


def test_wall_needs_two_nodes():
    c = contacts([
        (0, 1, -1, 2, 1, 0, 0, 1), (0, 2, -1, 2, 1, 0, 0, 1),
        (1, 3, -1, 0, 1, 0, 1, 0), (1, 3, -1, 0, 1, 0, 1, 0),  # one node
        (1, 4, -1, 3, 1, 0, 0, -1), (1, 5, -1, 1, 1, 0, -1, 0),  # two walls
    ])
    walls = net_.force_bearing_walls(c["candidate"], c["node"], c["wall"],
                                    np.ones(6, bool))
    assert [tuple(w) for w in walls] == [(0, 2)]


def test_resultant_forces_are_opposite_on_antagonist():
    c = chain_contacts()
    total = net_.resultant_forces(c["candidate"], c["antagonist"], c["fx"],
                                 c["fy"], 5)
    assert np.allclose(total[0], 0) and np.allclose(total[1], [0, 0.2])
    assert np.allclose(total[2], [0, -0.2])
    assert np.allclose(total[3], [-2 * EPS_G, 2 * G])
    assert np.allclose(total[4], [2 * EPS_G, 0])


def test_connectivity_rattlers_and_unbalanced():
    net = net_.contact_network(chain_contacts(), 5, F, RULES)
    assert [tuple(p) for p in net.pairs] == [(0, 1), (3, 4)]
    assert [tuple(w) for w in net.walls] == [(0, 0), (1, 1), (3, 2)]
    assert net.unbalanced.tolist() == [False, False, False, True, False]
    # 2 has no force-bearing contact; 4 only one with the unbalanced 3
    assert net.rattler.tolist() == [False, False, True, False, True]
    assert net.retained.tolist() == [True, True, False, False, False]
    assert net.contacts.tolist() == [2, 2, 0, 2, 1]
    assert net.wall_contacts.tolist() == [1, 1, 0, 1, 0]
    assert net.z_contacts.tolist() == [2, 2, 0, 0, 0]
    assert net.z == 2.0              # (2 x 1 pair + 2 walls) / 2 particles
    assert net.z_without_walls == 1.0


def test_unbalanced_threshold_is_relative_to_piston_force():
    # f_p* = 0.5 x F keeps particle 3 (resultant ~ 2 G = 0.2 F): 3 and 4 in
    net = net_.contact_network(chain_contacts(), 5, F, Rules(
        force_threshold=1e-4, unbalanced_threshold=0.5, rule="loaded_nodes",
        unbalanced_reference="piston_force"))
    assert not net.unbalanced.any()
    assert net.retained.tolist() == [True, True, False, True, True]
    assert net.z == pytest.approx((2 * 2 + 3) / 4)
    assert net.z_without_walls == pytest.approx(2 * 2 / 4)


def hanging_contacts(w=3.0):
    """Particle 0 hangs from the top wall (3) by two tensile nodal contacts
    of -w each (a cohesive or bonded contact pulls the candidate towards
    the wall, +y); particle 1 hangs from 0 by two of -w/2 (0 pulled down
    by 1): every force is tensile."""
    return contacts([
        (0, 10, -1, 3, -w, 0, 0, w), (0, 11, -1, 3, -w, 0, 0, w),
        (1, 20, 0, -1, -w / 2, 0, 0, w / 2),
        (1, 21, 0, -1, -w / 2, 0, 0, w / 2),
    ])


def test_tensile_contacts_bear_load_by_default():
    # The weights (body forces) balance the tensile contacts: 0 carries
    # its own and 1's (-2 w + w), 1 its own (-w)
    w = 3.0
    weights = [(0.0, -w), (0.0, -w)]
    bearing = net_.contact_network(hanging_contacts(w), 2, 0.0, Rules(
        force_threshold=1e-4, unbalanced_threshold=1e-3,
        rule="loaded_nodes"), weights)
    assert [tuple(p) for p in bearing.pairs] == [(0, 1)]
    assert [tuple(p) for p in bearing.walls] == [(0, 3)]
    assert not bearing.unbalanced.any() and bearing.retained.all()
    assert bearing.z == pytest.approx(3 / 2)  # (2 x 1 pair + 1 wall) / 2
    ignored = net_.contact_network(hanging_contacts(w), 2, 0.0, Rules(
        force_threshold=1e-4, unbalanced_threshold=1e-3,
        rule="loaded_nodes", tensile_contacts="ignored"), weights)
    assert len(ignored.pairs) == 0 and ignored.rattler.all()
    assert math.isnan(ignored.z)
    # f of total_normal_force: the sum of |fn| when tensile forces bear
    assert net_.reference_force(hanging_contacts(w), 0.0,
                                "total_normal_force", "bearing") == 3 * w
    with pytest.raises(ValueError, match="tensile_contacts must be one of"):
        net_.active_mask([1.0], 1e-4, "both")


@pytest.mark.parametrize("tensile", ["bearing", "ignored"])
def test_without_tensile_forces_both_readings_agree(tensile):
    net = net_.contact_network(chain_contacts(), 5, F, Rules(
        force_threshold=1e-4, unbalanced_threshold=1e-3,
        rule="loaded_nodes", unbalanced_reference="piston_force",
        excluded_contacts="dropped", tensile_contacts=tensile))
    reference = net_.contact_network(chain_contacts(), 5, F, RULES)
    assert net.z == reference.z
    assert net.rattler.tolist() == reference.rattler.tolist()
    assert [tuple(p) for p in net.pairs] == [tuple(p) for p in
                                             reference.pairs]


def test_no_contacts_gives_nan_z():
    net = net_.contact_network(contacts([]), 3, 0.0, RULES)
    assert math.isnan(net.z) and net.rattler.all()


# -- a whole fake run directory -------------------------------------------------

LENGTH, WIDTH, THICKNESS, MU = 0.10, 0.05, 0.015, 0.15e6
RADIUS = 0.008


def write_fake_run(run_dir, n_steps=3):
    """A run directory with raw output of 5 particles and ``n_steps`` rows.

    Step k: piston at x = LENGTH - 1e-3 k, strain energy 1e-3 k (J/m),
    particle p's energy (p + 1) 1e-5 k, the chain contacts at every step.
    """
    write_setup(run_dir, length=LENGTH, width=WIDTH, thickness=THICKNESS,
                diameters=(2 * RADIUS,), species=[0] * 5, shear_modulus=MU)
    write_rules(run_dir)
    with open(run_dir / "config.toml", "a") as f:  # RULES' readings
        f.write('unbalanced_reference = "piston_force"\n'
                'excluded_contacts = "dropped"\n')
    (run_dir / "raw" / "contacts").mkdir(parents=True)
    ref = math.pi * RADIUS**2
    walls = ["left", "right", "bottom", "top"]
    head = ("step,time,newton_iterations,nlgs_iterations,nlgs_error,"
            "nlgs_converged,contacts,active_contacts,max_penetration,"
            + "".join(f"{w}_x,{w}_y,{w}_fx,{w}_fy," for w in walls)
            + "phi," + ",".join(obs.ENERGY_COLUMNS) + ",seconds\n")
    steps, parts = [head], ["step,particle,area,strain_energy,reference_area\n"]
    for k in range(n_steps):
        step = 10 * k
        x = LENGTH - 1e-3 * k
        phi = "" if k == 0 else repr(5 * ref / (x * WIDTH))
        energies = {"strain_energy": 1e-3 * k, "wall_work": 2e-3 * k,
                    "damping": 5e-4 * k, "friction": 4e-4 * k,
                    "energy_residual": 1e-4 * k}
        energies = [energies.get(name, 0) for name in obs.ENERGY_COLUMNS]
        steps.append(
            f"{step},{1e-4 * step},2,7,1e-7,true,12,11,1e-6,"
            f"0,0,-{F},0,{x},0,{F},0,0,0,0,{2 * G},0,{WIDTH},0,0,{phi},"
            + ",".join(map(repr, energies)) + f",{0.5 * k}\n")
        parts += [f"{step},{p},{ref},{(p + 1) * 1e-5 * k},{ref}\n"
                  for p in range(5)]
        c = chain_contacts()
        lines = [",".join(net_.CONTACT_COLUMNS) + "\n"] + [
            ",".join(repr(float(c[n][i])) if n in ("fn", "ft", "fx", "fy")
                     else str(int(c[n][i])) for n in net_.CONTACT_COLUMNS)
            + "\n" for i in range(len(c["fn"]))]
        RunDirectory(run_dir).raw.contact_file(step).write_text("".join(lines))
    (run_dir / "raw" / "steps.csv").write_text("".join(steps))
    (run_dir / "raw" / "particles.csv").write_text("".join(parts))


@pytest.mark.parametrize("column", ["cohesion", "bond", "viscous"])
def test_a_run_without_a_law_column_reads_it_as_zero(tmp_path, column):
    # raw/steps.csv of a driver older than the cohesive (bonded) law
    write_fake_run(tmp_path)
    path = tmp_path / "raw" / "steps.csv"
    rows = [line.split(",") for line in path.read_text().splitlines()]
    drop = rows[0].index(column)
    path.write_text("".join(",".join(r[:drop] + r[drop + 1:]) + "\n"
                            for r in rows))
    s = read_table(obs.process_run(tmp_path)[0])
    assert s[column].tolist() == [0.0] * 3
    assert s["intact_bonds"].tolist() == [0] * 3
    assert np.allclose(s["energy_residual_relative"][1:], 0.05)


def test_process_run(tmp_path):
    write_fake_run(tmp_path)
    series_csv, particles_csv = obs.process_run(tmp_path)
    s = read_table(series_csv)
    assert list(s) == list(obs.SERIES_COLUMNS)
    assert s["step"].tolist() == [0, 10, 20]
    delta = np.array([0, 1e-3, 2e-3])
    assert np.allclose(s["piston_displacement"], delta)
    assert np.allclose(s["eps"], -np.log(1 - delta / LENGTH))
    # row 0 has an empty phi: computed from areas and the box
    ref = math.pi * RADIUS**2
    assert np.allclose(s["phi"], 5 * ref / ((LENGTH - delta) * WIDTH))
    assert np.allclose(s["E_over_WHLmu"],
                       1e-3 * np.arange(3) / (WIDTH * LENGTH * MU))
    assert np.allclose(s["piston_force"], F * THICKNESS)
    assert np.allclose(s["strain_energy"], THICKNESS * 1e-3 * np.arange(3))
    assert np.allclose(s["energy_residual_relative"][1:], 0.05)
    assert s["z"].tolist() == [2.0] * 3
    assert s["z_without_walls"].tolist() == [1.0] * 3
    assert s["rattlers"].tolist() == [2] * 3
    assert s["unbalanced"].tolist() == [1] * 3
    psi = np.arange(1, 6) * 1e-5 / ref
    assert math.isnan(s["cv_psi"][0])  # all Psi_p = 0 at step 0
    assert s["cv_psi"][1] == pytest.approx(psi.std() / psi.mean(), rel=1e-9)
    assert s["cv_psi_retained"][2] == pytest.approx(
        psi[:2].std() / psi[:2].mean(), rel=1e-9)
    p = read_table(particles_csv)
    assert list(p) == list(obs.PARTICLE_COLUMNS)
    assert len(p["step"]) == 15
    last = p["step"] == 20
    assert p["contacts"][last].tolist() == [2, 2, 0, 2, 1]
    assert p["rattler"][last].tolist() == [0, 0, 1, 0, 1]
    assert np.allclose(p["psi_p"][last], 2 * psi)
    assert np.allclose(p["radius"], RADIUS)


def test_missing_contacts_file_gives_nan(tmp_path):
    write_fake_run(tmp_path, n_steps=2)
    RunDirectory(tmp_path).raw.contact_file(10).unlink()
    series_csv, _ = obs.process_run(tmp_path)
    s = read_table(series_csv)
    assert s["z"][0] == 2.0 and math.isnan(s["z"][1])
    assert not math.isnan(s["phi"][1])


def test_why_z_is_undefined_is_written(tmp_path):
    """No silent NaN: contacts_file and retained say why, z_report counts."""
    write_fake_run(tmp_path, n_steps=3)
    RunDirectory(tmp_path).raw.contact_file(10).unlink()
    # step 20: only the open contact is left -> every particle a rattler
    RunDirectory(tmp_path).raw.contact_file(20).write_text(
        ",".join(net_.CONTACT_COLUMNS) + "\n2,41,0,-1,0,0,0,0\n")
    series_csv, _ = obs.process_run(tmp_path)
    s = read_table(series_csv)
    assert s["contacts_file"].tolist() == [1, 0, 1]
    assert math.isnan(s["retained"][1]) and s["retained"][2] == 0
    assert s["rattlers"][2] == 5 and math.isnan(s["z"][2])
    assert s["z_undefined"].tolist() == [0, 1, 2]
    assert obs.z_report(s) == (
        "Z undefined at 2 of 3 output steps: 1 no raw/contacts file for this"
        " output step; 1 no force-bearing contact: every particle floats (a"
        " rattler) (series.csv z_undefined)")
    assert obs.z_report({"z": [2.0], "z_undefined": [0]}) == ""


def test_a_z_over_a_few_retained_particles_is_flagged():
    """The biaxial run's axial stage (mass damping 300 1/s): 79 of 100
    particles unbalanced, Z over 21; the summary must say so."""
    row = {"step": [8370], "retained": [21.0], "unbalanced": [79.0],
           "rattlers": [0.0]}
    assert "counts 21 of 100 particles: 79 are unbalanced" in \
        obs.retained_report(row)
    for retained, unbalanced, rattlers in ((60, 40, 0), (30, 10, 60)):
        assert obs.retained_report(
            {"step": [1], "retained": [retained], "unbalanced": [unbalanced],
             "rattlers": [rattlers]}) == ""


def test_no_box_leaves_box_columns_nan(tmp_path):
    """A scene without left/right walls: eps, Phi of the box, piston NaN."""
    write_fake_run(tmp_path, n_steps=2)
    write_setup(tmp_path, length=LENGTH, width=WIDTH, thickness=THICKNESS,
                diameters=(2 * RADIUS,), species=[0] * 5, shear_modulus=MU,
                box=False)
    # its contacts name the four walls of the box: not this scene's
    with pytest.raises(ValueError, match="wall 2, the run has 2 walls"):
        obs.process_run(tmp_path)
    import shutil
    shutil.rmtree(RunDirectory(tmp_path).raw.contacts)
    s = read_table(obs.process_run(tmp_path)[0])
    assert np.isnan(s["eps"]).all() and np.isnan(s["piston_force"]).all()
    assert np.isnan(s["phi"][0]) and not np.isnan(s["phi"][1])  # driver's
    assert np.allclose(s["strain_energy"], THICKNESS * 1e-3 * np.arange(2))


def test_seed_csvs_regenerate_the_paper_tables(tmp_path):
    """docs/paper's pipeline: run -> per-seed CSV -> figures and tables."""
    import matplotlib
    matplotlib.use("Agg")
    from softpack.plots import paper_seeds

    run = tmp_path / "phi078-seed0"
    run.mkdir()
    write_fake_run(run, n_steps=3)
    obs.process_run(run)
    paper_seeds.export_seeds([run], tmp_path / "seeds")
    s = read_table(tmp_path / "seeds" / "phi078-seed0.csv")
    series = read_table(run / "series.csv")
    assert np.allclose(s["z"], series["z"], rtol=1e-6, equal_nan=True)
    # every reading's Z is the network's under that reading
    for reference, excluded in paper_seeds.READINGS:
        for threshold in paper_seeds.THRESHOLDS:
            rules = Rules(1e-4, threshold, "loaded_nodes", reference,
                          excluded)
            z = net_.contact_network(chain_contacts(), 5, F, rules).z
            column = paper_seeds.reading_column(reference, excluded,
                                                threshold)
            assert s[column][1:] == pytest.approx([z, z], rel=1e-6)
    groups = paper_seeds.load_seeds(tmp_path / "seeds")
    (label, seeds), = groups.items()
    assert seeds[0].seed == read_setup(run).seed
    assert seeds[0].length == LENGTH
    written = paper_seeds.regenerate(tmp_path / "seeds", tmp_path / "out")
    names = {p.name for p in written}
    assert {"summary.md", "exclusion_table.md", "fig8_connectivity.png",
            "fig6_energy.png"} <= names
    table = (tmp_path / "out" / "exclusion_table.md").read_text()
    assert table.count("| piston_force |") == 2


def test_seed_groups_separate_element_sizes_and_read_old_indexes(tmp_path):
    """A mesh study (same Phi0, two element sizes) gives two groups; an
    index written before element_size was a column reads as the paper's
    mesh, and exporting into it fills the column in."""
    from softpack.plots import paper_seeds

    default = paper_seeds.default_element_size()
    runs = []
    for name, h in (("coarse", default), ("fine", default / np.sqrt(2))):
        run = tmp_path / name
        run.mkdir()
        write_fake_run(run, n_steps=3)
        doc = json.loads((run / "raw" / "setup.json").read_text())
        doc["scene"]["mesh"]["element_size"] = h
        (run / "raw" / "setup.json").write_text(json.dumps(doc))
        obs.process_run(run)
        runs.append(run)
    seeds = tmp_path / "seeds"
    paper_seeds.export_seeds(runs, seeds)
    labels = sorted(paper_seeds.load_seeds(seeds))
    phi0 = labels[0]
    assert labels == [phi0, f"{phi0}, h = {default / np.sqrt(2) * 1e3:.3g} mm"]
    index = seeds / "runs.csv"
    lines = index.read_text().splitlines()
    old = [",".join(line.split(",")[:-2]) for line in lines]
    index.write_text("\n".join(old) + "\n")  # the 8-column layout
    assert {s.element_size for g in paper_seeds.load_seeds(seeds).values()
            for s in g} == {default}
    paper_seeds.export_seeds(runs[1:], seeds)
    assert all(len(line.split(",")) == len(paper_seeds.RUN_COLUMNS)
               for line in index.read_text().splitlines())
    assert len(paper_seeds.load_seeds(seeds)) == 2


def test_seed_groups_separate_preparation_protocols(tmp_path):
    """A run whose first stage compacts with another friction than the
    run's (examples/paper_prepared.toml) is its own group, named by it; a
    stage list at the run's friction is no preparation."""
    from softpack.plots import paper_seeds

    runs = []
    for name, frictions in (("random", None), ("prepared", (1.0, None)),
                            ("staged", (None, None))):
        run = tmp_path / name
        run.mkdir()
        write_fake_run(run, n_steps=3)
        if frictions:
            own = read_setup(run).friction  # None: the run's own
            frictions = [own if mu is None else mu for mu in frictions]
            doc = json.loads((run / "raw" / "setup.json").read_text())
            doc["stages"] = [
                {"name": f"s{k}", "contact": {"friction": mu},
                 "stop": {"packing_fraction": phi}}
                for k, (mu, phi) in enumerate(zip(frictions, (0.78, 0.88)))]
            (run / "raw" / "setup.json").write_text(json.dumps(doc))
        obs.process_run(run)
        runs.append(run)
    assert [paper_seeds.protocol(read_setup(r)) for r in runs] == [
        "", "mu_f 1 to Phi 0.78", ""]
    paper_seeds.export_seeds(runs, tmp_path / "seeds")
    groups = paper_seeds.load_seeds(tmp_path / "seeds")
    phi0 = min(groups, key=len)
    assert sorted(groups) == [phi0, f"{phi0}, prepared: mu_f 1 to Phi 0.78"]
    assert sorted(s.name for s in groups[phi0]) == ["random", "staged"]
