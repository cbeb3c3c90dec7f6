"""softpack from Python: configure, run, read and plot (docs/python_api.md).

The same stages as ``./softpack run`` and ``./softpack plot``, as functions
for scripted studies::

    import softpack

    config = softpack.load_config("examples/small.toml",
                                  {"contact.friction": 0.1})
    series = softpack.run(config, "runs/mu0.1")
    series["phi"][-1]

Tables come back as columns: a pandas DataFrame when pandas is importable,
else a dict of numpy arrays (one per column of the CSV file).
"""

from __future__ import annotations

import contextlib
import os
import re
from pathlib import Path

__all__ = ["load_config", "run", "resume", "read_run", "plot_runs",
           "plot_loading", "plot_shear", "plot_plane_strain",
           "plot_single_disk", "RunError",
           "RunFlagged"]

from softpack.contract.run_directory import (EXIT_FLAGGED,  # noqa: E402
                                             RunDirectory, RunError,
                                             RunFlagged, UsageError,
                                             is_run_directory, run_flags)


def load_config(path, overrides=None):
    """Read and validate a run's TOML file.

    Parameters
    ----------
    path : path-like
        The TOML configuration (e.g. ``examples/small.toml``).
    overrides : dict, optional
        ``{"section.key": value}``, as ``--set`` on the command line, e.g.
        ``{"contact.friction": 0.1, "species.0.count": 12}``.

    Returns
    -------
    Config
        Every key, defaults filled in; ``config["contact"]["friction"]``.

    Raises
    ------
    softpack.scene.config.ConfigError
        Naming the file (or the override) and the key.
    """
    from softpack.scene.config import load_config as load

    return load(path, overrides)


def run(config, out, force=False, initial_state=None, verbose=False,
        ranks=1, strict=True):
    """Run one compaction into ``out`` and return its series.

    Parameters
    ----------
    config : Config or path-like
        From :func:`load_config`, or the path of a TOML file.
    out : path-like
        The run directory (created; a foreign non-empty directory is
        refused, see ``./softpack run --help``).
    force : bool
        Replace a complete run in ``out``.
    initial_state : path-like, optional
        A ``raw/state.bin`` of a run on the same packing to start from.
    verbose : bool
        Print progress as ``./softpack run`` does (run.log has it always).
    ranks : int
        MPI ranks of the driver (1 to the number of bodies).
    strict : bool
        A run that finishes flagged (a solve left unconverged, bodies
        overlapping beyond ``contact.alert_distance``, a stage program ended
        before its criterion: the command line's exit status 3) raises
        :class:`RunFlagged`; False: its series is returned and a
        ``RuntimeWarning`` says why.

    Returns
    -------
    DataFrame or dict of numpy.ndarray
        ``series.csv`` (:func:`read_run`).

    Raises
    ------
    RunError
        The run failed; the message says why (``out/run.log`` has more).
    RunFlagged
        With ``strict``, a flagged run (a RunError; its ``flags``, and its
        ``series``: every output is written).
    """
    from softpack.simulation import run as runner

    config = _configuration(config)
    out = Path(os.path.abspath(out))
    with _api_terms():
        status = runner.run(config, out, force=force,
                            initial_state=initial_state, verbose=verbose,
                            ranks=ranks)
    return _series(out, status, strict)


#: The command line's options as the API's arguments name them: the
#: messages the two share speak of the options.
_ARGUMENTS = {"--from-state": "initial_state", "--resume": "directory",
              "--out": "out", "--ranks": "ranks", "--force": "force=True"}


@contextlib.contextmanager
def _api_terms():
    """Re-raise a run's error (RunError, ConfigError) with the command
    line's option names in its message turned into the API's arguments."""
    from softpack.scene.config import ConfigError

    try:
        yield
    except (RunError, ConfigError) as err:
        if isinstance(err, RunFlagged):
            raise
        text = re.sub(r"--(from-state|resume|out|ranks|force)\b",
                      lambda m: _ARGUMENTS[m.group(0)], str(err))
        if text == str(err):
            raise
        raise type(err)(text) from None


def _configuration(config):
    """A Config from ``config`` (a Config, or a TOML path); TypeError for
    anything else, before anything is written."""
    from softpack.scene.config import Config

    if isinstance(config, (str, os.PathLike)):  # a Path has a stem too
        return load_config(config)
    if not isinstance(config, Config):
        raise TypeError(
            f"softpack.run: config is a {type(config).__name__}; give"
            " softpack.load_config(PATH, overrides) or the path of a TOML"
            " file (a dict of TOML tables: softpack.scene.config.validate"
            "(data, name))")
    return config


def _series(out: Path, status: int, strict: bool):
    """The series of a finished run; RunFlagged (strict) or a warning when
    it finished flagged."""
    import warnings

    series = read_run(out)
    if status == EXIT_FLAGGED:
        flags = run_flags(RunDirectory(out).done())
        if strict:
            raise RunFlagged(out, flags, series)
        warnings.warn(str(RunFlagged(out, flags)), RuntimeWarning,
                      stacklevel=3)
    return series


def resume(directory, verbose=False, strict=True):
    """Finish a killed run from its last state (``./softpack run --resume``)
    and return its series.

    The run's own ``config.toml`` is used; the series is the one an
    uninterrupted run writes (bit for bit with ``time.full_newton = true``;
    with the default lagged iteration matrix, to the Newton tolerance).

    Raises
    ------
    RunError
        Not a killed run (complete, or no state written).
    RunFlagged
        With ``strict``, a flagged run (as :func:`run`).
    """
    from softpack.simulation import run as runner

    directory = Path(os.path.abspath(directory))
    if not is_run_directory(directory):
        raise UsageError(f"{directory}: not a softpack run directory")
    config = load_config(RunDirectory(directory).config_toml)
    with _api_terms():
        status = runner.resume(config, directory, verbose=verbose)
    return _series(directory, status, strict)


#: The tables of a run :func:`read_run` reads, and what each holds.
TABLES = {
    "series": "series.csv: one row per output step (eps, phi, energies, Z,"
              " ...; docs/observables.md)",
    "particles": "particles.csv: one row per particle and output step",
    "stress": "stress.csv: the box's strains and the wall, contact and"
              " finite-element stress estimates per output step (a box)",
    "network": "network.csv: the force-bearing contact pairs of every"
               " output step (forces, branch vectors; docs in"
               " softpack.analysis.network)",
    "steps": "raw/steps.csv: the driver's row per output step",
    "raw_particles": "raw/particles.csv: the driver's row per particle and"
                     " output step",
    "contacts": "raw/contacts/step_N.csv: the contacts of output step N"
                " (step=N)",
}


def read_run(directory, table="series", step=None):
    """A run's table as columns.

    Parameters
    ----------
    directory : path-like
        A run directory written by :func:`run` or ``./softpack run``.
    table : str
        One of :data:`TABLES`: ``"series"`` (default), ``"particles"``,
        ``"stress"``, ``"network"`` (written by the analysis of a finished
        run),
        ``"steps"``, ``"raw_particles"`` or ``"contacts"`` (the driver's,
        there as soon as it writes them).
    step : int, optional
        The output step of a ``"contacts"`` table (a value of the series'
        ``step`` column).

    Returns
    -------
    DataFrame or dict of numpy.ndarray

    Raises
    ------
    ValueError
        An unknown table, or ``step`` missing for (or given to another
        table than) ``"contacts"``.
    FileNotFoundError
        The table is not there (an analysis table of a run not finished,
        a step with no contact file).
    """
    from softpack.contract.tables import read_table

    if table not in TABLES:
        raise ValueError(f"table {table!r}: expected one of"
                         f" {', '.join(map(repr, TABLES))}")
    if (step is None) == (table == "contacts"):
        raise ValueError("step: the output step of table 'contacts', and"
                         " of no other table")
    run = RunDirectory(directory)
    path = {"series": lambda: run.series_csv,
            "particles": lambda: run.particles_csv,
            "stress": lambda: run.stress_csv,
            "network": lambda: run.network_csv,
            "steps": lambda: run.raw.steps_csv,
            "raw_particles": lambda: run.raw.particles_csv,
            "contacts": lambda: run.raw.contact_file(step)}[table]()
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file ({TABLES[table]};"
                                f" is {directory} a finished run?)")
    columns = read_table(path)
    try:
        import pandas
    except ImportError:
        return columns
    return pandas.DataFrame(columns)


def plot_loading(directory, out=None, estimate=None, rest=None,
                 stage=None) -> dict:
    """The loading figures of a run in a box (``./softpack plot-loading``):
    pressure against Phi with the compaction law fitted, Z, the stress
    estimates, and the shear of a stage.

    Parameters
    ----------
    directory : path-like
        A finished run directory.
    out : path-like, optional
        Figure directory (default: ``directory/figures/loading``).
    estimate : {"fe", "contact", "wall"}, optional
        The stress estimate the law is fitted to (default: as
        ``./softpack plot-loading``).
    rest : float, optional
        Fit the rows whose kinetic energy is at most ``rest`` x the strain
        energy (default: 1e-3 with stages, every row without).
    stage : int, optional
        The stage of the shear figure (default: the last).

    Returns
    -------
    dict
        The summary also written to ``loading.json`` (the fit, the last
        row's estimates, the figures' paths).
    """
    from softpack.plots import loading

    run = RunDirectory(directory)
    if not run.raw.steps_csv.is_file():
        raise RunError(f"directory {directory}: no raw/steps.csv (not a run"
                       " directory)")
    out = Path(out) if out is not None else run.path / "figures" / "loading"
    return loading.write_figures(run.path, out, estimate, rest, stage)


def plot_shear(directories, out=None, window=0.5) -> dict:
    """The steady state of shear runs in a periodic cell (``./softpack
    plot-shear``): mu*, Phi and I against gamma, and per run each
    quantity's mean, fluctuation, standard error and stationarity over the
    last ``window`` of its shear; mu* compared between every pair of runs.

    Parameters
    ----------
    directories : list of path-like
        Finished runs whose last stage is a shear.
    out : path-like, optional
        Output directory (default: ``figures/shear`` of the first run).
    window : float, optional
        The steady window's fraction of the last stage's shear (0, 1].

    Returns
    -------
    dict
        The summary also written to ``steady.json`` (``steady.md``: its
        table).
    """
    from softpack.plots import shear

    directories = [Path(d) for d in directories]
    if not directories:
        raise RunError("plot_shear: no run directory given")
    if not 0 < window <= 1:
        raise ValueError(f"window must be in (0, 1], not {window}")
    out = Path(out) if out is not None else \
        directories[0] / "figures" / "shear"
    return shear.write_outputs(directories, out, window)


def plot_plane_strain(runs, out, phis=None, eps=None) -> list[str]:
    """Plane-strain 2D runs against 3D runs of standing cylinders
    (``./softpack plot-plane-strain``): Phi(eps), F/H, E/H and Z against
    Phi in ``plane_strain.png``/``.pdf``, a table at ``phis`` in
    ``plane_strain.md`` (and the same at equal ``eps``).

    Parameters
    ----------
    runs : list of (str, path-like)
        Labels and run directories (2D or 3D) or per-seed CSVs of
        docs/paper/seeds; the first is the ratios' reference.
    out : path-like
        Output directory.
    phis : list of float, optional
        The table's packing fractions (default 0.76 to 0.88 by 0.02).
    eps : list of float, optional
        The strains of the table at equal piston travel (default 0.05 to
        0.20 by 0.05).

    Returns
    -------
    list of str
        ``plane_strain.md``'s lines.
    """
    from softpack.plots import plane_strain

    try:
        return plane_strain.write_outputs(
            list(runs), out,
            plane_strain.TABLE_PHIS if phis is None else phis,
            plane_strain.TABLE_EPS if eps is None else eps)
    except plane_strain.PlaneStrainError as err:
        raise RunError(str(err)) from None


def plot_runs(directories, out=None) -> list[Path]:
    """The paper's figures (Figs. 4, 6-9) from one or several runs.

    Parameters
    ----------
    directories : iterable of path-like
        Run directories; grouped by friction, averaged over seeds.
    out : path-like, optional
        Figure directory (default: the first run's ``figures/``).

    Returns
    -------
    list of Path
        The files in ``out`` after drawing.

    Raises
    ------
    RunError
        No complete run among ``directories``.
    """
    from softpack.plots import paper

    directories = [Path(d) for d in directories]
    out = Path(out) if out is not None else directories[0] / "figures"
    if paper.main([*map(str, directories), "--out", str(out)]) != 0:
        raise RunError(f"no complete run to plot in {directories}")
    return sorted(out.iterdir())


def plot_single_disk(directory) -> list[Path]:
    """Figs. 2-3 (``fig2_force.png``, ``fig3_profile.png``) into a
    ``./softpack single-disk`` run directory; returns the files written."""
    from softpack.plots import single_disk

    if single_disk.main([str(directory)]) != 0:
        raise RunError(f"plot-single-disk {directory}: no single-disk CSV"
                       " files")
    return [p for p in (Path(directory) / "fig2_force.png",
                        Path(directory) / "fig3_profile.png") if p.is_file()]
