"""The paper's observables from what the driver wrote.

Reads a run directory (``docs/contract.md`` sections 5-6): ``raw/setup.json``
(through :mod:`softpack.analysis.setup`), ``raw/steps.csv``,
``raw/particles.csv``, ``raw/contacts/step_NNNNNNNN.csv`` and the
``[observables]`` rules of ``config.toml``, and writes

``series.csv``
    one row per output step (columns in :data:`SERIES_COLUMNS`);
``particles.csv``
    one row per (output step, particle) (columns in
    :data:`PARTICLE_COLUMNS`).

Definitions (paper Secs. IV-VII, METHOD.md section 4). Forces and energies of
the 2D model are per unit length; the CSV files give them times the
thickness H (N and J, comparable with the experiment). Psi_p is in J/m^3.
The box is the walls ``left``, ``right``, ``bottom``, ``top``; the piston is
``right`` (:data:`softpack.analysis.setup.PISTON`).

eps
    ``-ln(1 - delta / L0)``, delta = L0 - L(t) the piston displacement, L(t)
    the distance between the walls ``left`` and ``right`` (Eq. 11,
    :mod:`softpack.analysis.strain`).
Phi
    ``raw/steps.csv`` ``phi``; where empty, sum of current particle areas
    over the current box area.
E/(W H L mu)
    ``E = H x strain_energy``, with the set-up's constant W, H, L (the
    initial box) and the shear modulus mu; i.e. ``strain_energy / (W L mu)``.
Psi_p, c_v(Psi_p)
    ``Psi_p = E_p / V_p0`` = particle strain energy over its reference area;
    ``c_v = sqrt(<Psi_p^2> - <Psi_p>^2) / <Psi_p>`` (Eq. 16, population
    standard deviation). ``cv_psi`` averages over all particles, as the paper
    does ("the particles of the system"); ``cv_psi_retained`` over the
    particles retained for Z. NaN where no particle is strained (<Psi_p> =
    0: at rest, e.g. row 0 of a run from rest): c_v is 0/0 there, not 0.
energy_residual_relative
    ``energy_residual / (|wall_work| + |external_work|)``; NaN while nothing
    has been supplied (row 0 of a run from rest: 0/0), when the residual is
    0 by construction.
Z, rattlers, unbalanced particles
    :mod:`softpack.analysis.connectivity`. ``z`` is NaN where no particle is
    retained (``retained`` = 0) and where the output step has no contacts
    file (``contacts_file`` = 0, and the contact columns NaN); the column
    ``z_undefined`` says why, as a code of
    :data:`softpack.analysis.connectivity.Z_UNDEFINED` (0: Z defined; 1: no
    contacts file; 2: every particle a rattler; 3: every particle
    unbalanced; 4: every particle unbalanced or a rattler), and
    :func:`z_report` counts each.
piston force
    ``-(f . n)`` of the wall ``right``, f the force it receives, n its
    inward normal: positive in compression.
fabric_xx, fabric_yy, fabric_xy, fabric_anisotropy, fabric_angle
    The fabric tensor of the particle-particle contact normals (unit branch
    vectors of network.csv's pairs) and its anisotropy and major direction:
    :func:`softpack.analysis.network.fabric`.
species, rigid (particles.csv)
    The index of the particle's species in ``[[species]]`` and whether its
    material is rigid (1) or not (0).
centroid_x, centroid_y, rotation (particles.csv)
    The area centroid of the particle's deformed boundary (m) and its
    rotation from the reference configuration (rad, counter-clockwise, in
    (-pi, pi]: the least-squares rotation of its boundary nodes about
    their centroid), from the driver (``driver/bodies/placement.h``).
pressure (particles.csv)
    The particle's mean pressure ``-tr(sigma) / d`` averaged over its
    current area (3D: volume; Pa, compression positive), from the integral
    of its Cauchy stress (``raw/particles.csv``); NaN for a rigid particle,
    whose finite elements carry no stress.

3D runs (``scene.model.dimension = 3``; docs/bodies_3d.md, "Observables of
3D runs") have the same files from the same functions, d = 3: forces and
energies are the driver's N and J (no thickness factor); ``phi`` is the
volume fraction and ``phi_base`` (after it) the bottom faces' area fraction
of the base, both from ``raw/steps.csv``; ``E_over_WHLmu`` is ``E / (W H L
mu)`` with H the model's thickness (``[model] thickness``: the standing
cylinders' height), so that it compares with the 2D model's; Z counts the
node-to-face contacts by the same rule (a body pair is in contact when at
least two distinct nodes carry force between them, a body touches one of
the six planes when two of its nodes do; ``z_without_base`` and
``retained_without_base``, 3D only: the same with the base and the lid
counted as no contacts, :func:`planar_z`); the fabric is 3 x 3
(:data:`softpack.analysis.network.FABRIC_COLUMNS_3D`); particles.csv has
``centroid_z`` in place of ``rotation``; network.csv ``fz`` and
``branch_z``; stress.csv the 3 x 3 estimates (:mod:`softpack.analysis.stress`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softpack.analysis.connectivity import (Z_UNDEFINED, contact_network,
                                            read_contacts,
                                            z_undefined_code)
from softpack.analysis.setup import (PISTON, RunSetup, read_rules,
                                     read_setup)
from softpack.analysis.network import (FABRIC_COLUMNS, fabric,
                                       fabric_columns, network_table,
                                       write_network)
from softpack.analysis.strain import cumulative_strain
from softpack.analysis.tensors import axes
from softpack.analysis.stress import write_stress
from softpack.analysis.cell import write_cell_stress
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table, write_table

ENERGY_COLUMNS = ("strain_energy", "kinetic_energy", "wall_work",
                  "external_work", "cell_work", "rewrap", "damping",
                  "friction", "contact_normal", "cohesion", "bond",
                  "viscous", "numerical", "energy_residual")
#: Copied from ``raw/steps.csv`` when the driver wrote them (NaN otherwise):
#: steps since the previous row whose Newton iterations or contact solves
#: did not converge, and the overlap depth measured from the deformed
#: boundaries, independently of the contact detection (m).
CHECK_COLUMNS = ("newton_unconverged_steps", "nlgs_unconverged_steps",
                 "max_overlap_depth")
#: Copied from ``raw/steps.csv`` (0 for a run written before it): the
#: intact bonds of the bonded law at the row's step (docs/contact_laws.md).
BOND_COLUMNS = ("intact_bonds",)
SERIES_COLUMNS = (
    "step", "time", "piston_displacement", "eps", "phi", "E_over_WHLmu",
    "z", "z_without_walls", "z_undefined", "retained", "rattlers",
    "unbalanced", "cv_psi",
    "cv_psi_retained", "piston_force", *ENERGY_COLUMNS,
    "energy_residual_relative", "newton_iterations", "nlgs_iterations",
    "nlgs_error", "nlgs_converged", "contacts", "active_contacts",
    "max_penetration", "seconds", "contacts_file", *CHECK_COLUMNS,
    *BOND_COLUMNS, *FABRIC_COLUMNS)
PARTICLE_COLUMNS = (
    "step", "time", "phi", "particle", "radius", "reference_area", "area",
    "psi_p", "contacts", "wall_contacts", "z_contacts", "resultant_force",
    "unbalanced", "rattler", "species", "rigid", "centroid_x", "centroid_y",
    "rotation", "pressure")
#: The columns of ``raw/particles.csv`` read per particle (NaN when an older
#: driver did not write them).
RAW_PARTICLE_COLUMNS = ("reference_area", "area", "strain_energy",
                        "cauchy_xx", "cauchy_yy", "cauchy_zz", "centroid_x",
                        "centroid_y", "centroid_z", "rotation")
DRIVER_COLUMNS = ("newton_iterations", "nlgs_iterations", "nlgs_error",
                  "nlgs_converged", "contacts", "active_contacts",
                  "max_penetration", "seconds")
#: A 3D run's Z without the base and the lid (:func:`planar_z`).
PLANAR_Z_COLUMNS = ("z_without_base", "retained_without_base")
#: The planes that are out of the 2D model's plane.
OUT_OF_PLANE = ("base", "lid")


def series_columns(dimension: int) -> tuple:
    """The columns of ``series.csv``: :data:`SERIES_COLUMNS` in 2D; in 3D
    with ``phi_base`` after ``phi``, :data:`PLANAR_Z_COLUMNS` after
    ``z_without_walls`` and the 3D fabric columns."""
    if dimension != 3:
        return SERIES_COLUMNS
    out = list(SERIES_COLUMNS[:-len(FABRIC_COLUMNS)])
    out.insert(out.index("phi") + 1, "phi_base")
    k = out.index("z_without_walls") + 1
    out[k:k] = PLANAR_Z_COLUMNS
    return (*out, *fabric_columns(3))


def particle_columns(dimension: int) -> tuple:
    """The columns of ``particles.csv``: :data:`PARTICLE_COLUMNS` in 2D; in
    3D ``centroid_z`` in place of ``rotation`` (the driver writes none)."""
    if dimension != 3:
        return PARTICLE_COLUMNS
    return tuple("centroid_z" if c == "rotation" else c
                 for c in PARTICLE_COLUMNS)


def force_scale(setup: RunSetup) -> float:
    """What turns the driver's forces and energies into N and J: the 2D
    model's thickness H (they are per unit length), 1 in 3D."""
    return setup.thickness if setup.dimension == 2 else 1.0


# -- pure functions on arrays ------------------------------------------------

def normalised_energy(strain_energy, width, length, shear_modulus):
    """``E / (W H L mu)`` from the 2D strain energy per unit length.

    ``E = H x strain_energy``, so H cancels.
    """
    return np.asarray(strain_energy, dtype=float) / (width * length
                                                     * shear_modulus)


def coefficient_of_variation(values) -> float:
    """``sqrt(<x^2> - <x>^2) / <x>`` (paper Eq. 16); NaN if empty or zero."""
    x = np.asarray(values, dtype=float)
    if x.size == 0 or x.mean() == 0.0:
        return float("nan")
    return float(x.std() / x.mean())


# -- per-step observables and the output files --------------------------------

def box_dimensions(steps: dict, setup: RunSetup):
    """Current box length (x) and width (y) of every output row.

    NaN when the scene has no box.
    """
    if not setup.has_box:
        nan = np.full(len(steps["step"]), np.nan)
        return nan, nan.copy()
    return (steps["right_x"] - steps["left_x"],
            steps["top_y"] - steps["bottom_y"])


def piston_force(steps: dict, setup: RunSetup):
    """Force on the piston, ``-(f . n)`` per unit length (N/m; N in 3D);
    NaN if none."""
    if PISTON not in setup.walls:
        return np.full(len(steps["step"]), np.nan)
    normal = setup.walls[PISTON].normal
    return -sum(steps[f"{PISTON}_f{a}"] * normal[i]
                for i, a in enumerate(axes(setup.dimension)))


def series_from_steps(steps: dict, setup: RunSetup) -> dict:
    """The ``series.csv`` columns that need only ``raw/steps.csv``.

    The contact-based columns (Z, rattlers, unbalanced, c_v) are NaN;
    ``phi`` is NaN where the driver left it empty.
    """
    h = force_scale(setup)
    length, _ = box_dimensions(steps, setup)
    delta = setup.length - length
    series = {name: np.full(len(length), np.nan)
              for name in series_columns(setup.dimension)}
    # 3D: the strain energy (J) per unit height H, the model's thickness
    # (the standing cylinders' height), as the 2D model's per unit length
    energy = (steps["strain_energy"] if setup.dimension == 2
              else steps["strain_energy"] / setup.thickness)
    series.update(step=steps["step"], time=steps["time"],
                  piston_displacement=delta,
                  eps=cumulative_strain(delta, setup.length),
                  E_over_WHLmu=normalised_energy(
                      energy, setup.width, setup.length,
                      setup.shear_modulus),
                  piston_force=h * piston_force(steps, setup))
    for name in ("phi", "phi_base"):
        if name in steps and name in series:
            series[name] = np.array(steps[name], dtype=float)
    for name in ENERGY_COLUMNS:
        # (a run written before the cohesion, bond or viscous account had
        # none: 0)
        series[name] = h * (steps[name] if name in steps
                            else np.zeros(len(steps["step"])))
    supplied = np.abs(steps["wall_work"]) + np.abs(steps["external_work"])
    for name in ("cell_work", "rewrap"):  # a periodic cell's supplies
        if name in steps:
            supplied = supplied + np.abs(steps[name])
    series["energy_residual_relative"] = np.divide(
        steps["energy_residual"], supplied,
        out=np.full(len(supplied), np.nan), where=supplied > 0)
    for name in DRIVER_COLUMNS:
        series[name] = steps[name]
    for name in CHECK_COLUMNS:
        if name in steps:
            series[name] = steps[name]
    for name in BOND_COLUMNS:
        series[name] = (steps[name] if name in steps
                        else np.zeros(len(steps["step"]), dtype=int))
    return series


def series_and_particles(steps: dict, particles: dict, contacts_of,
                         setup: RunSetup, rules):
    """Compute ``series.csv`` and ``particles.csv`` columns.

    Parameters
    ----------
    steps, particles : dict of arrays
        ``raw/steps.csv`` and ``raw/particles.csv``.
    contacts_of : callable
        ``step -> dict of contact arrays``, or ``None`` when missing.
    setup : RunSetup
    rules : softpack.analysis.setup.Rules

    Returns
    -------
    (dict, dict)
        Columns of :data:`SERIES_COLUMNS` and :data:`PARTICLE_COLUMNS`.
    """
    n = setup.count
    series = series_from_steps(steps, setup)
    length, width = box_dimensions(steps, setup)
    force = piston_force(steps, setup)
    rows = []
    weight = setup.body_weight
    for k, step in enumerate(steps["step"]):
        raw = _per_particle(particles, step, n)
        ref, area = raw["reference_area"], raw["area"]
        psi = raw["strain_energy"] / ref
        if not np.isfinite(series["phi"][k]):
            series["phi"][k] = area.sum() / (length[k] * width[k])
        series["cv_psi"][k] = coefficient_of_variation(psi)
        contacts = contacts_of(step)
        series["contacts_file"][k] = contacts is not None
        net = None if contacts is None else contact_network(
            contacts, n, force[k], rules, weight)
        series["z_undefined"][k] = z_undefined_code(net)
        if net is not None:
            series["z"][k], series["z_without_walls"][k] = \
                net.z, net.z_without_walls
            series["retained"][k] = net.retained.sum()
            series["rattlers"][k] = net.rattler.sum()
            series["unbalanced"][k] = net.unbalanced.sum()
            series["cv_psi_retained"][k] = coefficient_of_variation(
                psi[net.retained])
        if net is not None and setup.dimension == 3:
            planar_z(series, k, contacts, force[k], setup, rules)
        rows.append(_particle_rows(step, steps["time"][k], series["phi"][k],
                                   setup, raw, psi, net))
    table = {name: np.concatenate([r[name] for r in rows]) if rows
             else np.zeros(0) for name in particle_columns(setup.dimension)}
    return series, table


def planar_z(series: dict, k: int, contacts: dict, piston: float,
             setup: RunSetup, rules) -> None:
    """Row k of :data:`PLANAR_Z_COLUMNS` of a 3D run: Z and the particles
    it counts when the contacts with the base and the lid are no contacts
    (their forces still in the resultants): the 2D model's Z of standing
    cylinders, whose every body touches the base, out of its plane; a
    cylinder touching the base only is then a rattler."""
    names = list(setup.walls)
    net = contact_network(contacts, setup.count, piston, rules,
                          setup.body_weight,
                          [names.index(w) for w in OUT_OF_PLANE])
    series["z_without_base"][k] = net.z
    series["retained_without_base"][k] = net.retained.sum()


def z_report(series: dict) -> str:
    """Why ``z`` is NaN where it is, in one line ("" when it never is).

    Parameters
    ----------
    series : dict of arrays
        Columns of :data:`SERIES_COLUMNS`.
    """
    undefined = ~np.isfinite(np.asarray(series["z"], dtype=float))
    if not undefined.any():
        return ""
    codes = np.asarray(series["z_undefined"], dtype=float)[undefined]
    reasons = [f"{int(np.sum(codes == code))} {text}"
               for code, text in Z_UNDEFINED.items() if np.any(codes == code)]
    return (f"Z undefined at {int(undefined.sum())} of {len(undefined)}"
            f" output steps: {'; '.join(reasons)} (series.csv z_undefined)")


def retained_report(series: dict) -> str:
    """A warning when Z of the last row counts fewer than half of the
    particles because most are unbalanced ("" otherwise): the exclusion
    rule is the paper's for a quasi-static compaction, and an assembly
    that is not at rest (fast loading, heavy mass damping) leaves Z over a
    few particles, a number that is not the assembly's."""
    if not len(series.get("step", ())):
        return ""
    retained = float(series["retained"][-1])
    unbalanced = float(series["unbalanced"][-1])
    count = retained + unbalanced + float(series["rattlers"][-1])
    if not count or retained >= 0.5 * count or unbalanced <= retained:
        return ""
    return (f"WARNING: Z of the last row counts {retained:.0f} of"
            f" {count:.0f} particles: {unbalanced:.0f} are unbalanced (net"
            " contact force above [observables] unbalanced_threshold x the"
            " reference force; the assembly is not at rest). Read Z(Phi)"
            " with care; a larger unbalanced_threshold (./softpack run"
            " --observables-only --out RUN --set"
            " observables.unbalanced_threshold=...)"
            " counts them (series.csv retained, unbalanced)")


def _per_particle(particles, step, n) -> dict:
    """The columns :data:`RAW_PARTICLE_COLUMNS` of each particle at a step."""
    mine = particles["step"] == step
    ids = particles["particle"][mine].astype(np.int64)
    out = {}
    for name in RAW_PARTICLE_COLUMNS:
        values = np.full(n, np.nan)
        if name in particles:
            values[ids] = particles[name][mine]
        out[name] = values
    return out


def _particle_rows(step, time, phi, setup, raw, psi, net) -> dict:
    """Columns of ``particles.csv`` for one output step."""
    n = setup.count
    missing = np.full(n, np.nan)
    rigid = (np.zeros(n, bool) if setup.body_rigid is None
             else np.asarray(setup.body_rigid, bool))
    # The body's mean Cauchy stress from its integral (tension positive) as
    # a pressure; a rigid body's finite elements carry none.
    # p = -tr(sigma) / d
    d = setup.dimension
    trace = sum(raw[f"cauchy_{a}{a}"] for a in axes(d))
    pressure = -trace / (d * raw["area"])
    pressure[rigid] = np.nan
    h = force_scale(setup)
    return {
        "step": np.full(n, step), "time": np.full(n, time),
        "phi": np.full(n, phi), "particle": np.arange(n),
        "radius": setup.radii, "reference_area": raw["reference_area"],
        "area": raw["area"], "psi_p": psi,
        "contacts": missing if net is None else net.contacts,
        "wall_contacts": missing if net is None else net.wall_contacts,
        "z_contacts": missing if net is None else net.z_contacts,
        "resultant_force": missing if net is None else h * net.resultant,
        "unbalanced": missing if net is None else net.unbalanced,
        "rattler": missing if net is None else net.rattler,
        "species": setup.body_species, "rigid": rigid.astype(float),
        "centroid_x": raw["centroid_x"], "centroid_y": raw["centroid_y"],
        "rotation": raw["rotation"], "centroid_z": raw["centroid_z"],
        "pressure": pressure}


def process_run(run_dir, setup: RunSetup | None = None,
                rules=None) -> tuple[Path, Path]:
    """Write ``particles.csv``, ``network.csv``, ``stress.csv`` (a box) then
    ``series.csv``.

    ``series.csv`` is renamed into place last, so its presence means the
    post-processing finished.

    Parameters
    ----------
    run_dir : path-like
    setup : RunSetup, optional
        Default: :func:`softpack.analysis.setup.read_setup` of the run.
    rules : softpack.analysis.setup.Rules, optional
        Default: :func:`softpack.analysis.setup.read_rules` of the run.

    Returns
    -------
    (Path, Path)
        The series and particles files.
    """
    run = RunDirectory(run_dir)
    setup = setup or read_setup(run_dir)
    rules = rules or read_rules(run_dir)
    steps = read_table(run.raw.steps_csv)
    particles = read_table(run.raw.particles_csv)

    def contacts_of(step):
        """The step's contacts, None when its file is missing."""
        path = run.raw.contact_file(step)
        return read_contacts(path) if path.is_file() else None

    series, table = series_and_particles(steps, particles, contacts_of,
                                         setup, rules)
    particles_csv = write_table(run.particles_csv, table,
                                particle_columns(setup.dimension))
    network = network_table(run_dir, setup, steps, particles)
    write_network(run_dir, network)
    series.update(fabric(network, series["step"]))
    if setup.has_box:
        # The assembly's stress (wall and Love-Weber estimates, P, q) in its
        # own table, before series.csv whose presence means "finished".
        write_stress(run_dir)
    elif setup.cell:
        write_cell_stress(run_dir, setup)
    series_csv = write_table(run.series_csv, series,
                             series_columns(setup.dimension))
    return series_csv, particles_csv
