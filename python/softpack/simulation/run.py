"""``./softpack run [CONFIG] [--out DIR]``: one run, start to finish.

1. Validate CONFIG (default ``examples/paper.toml``,
   :mod:`softpack.scene.config`) with the command-line overrides
   (``--seed`` = ``packing.seed``, ``--friction`` = ``contact.friction``,
   ``--set SECTION.KEY=VALUE``); on error print the message and exit with
   status 2 before writing anything.
2. Write into DIR (default ``runs/<config stem>-seed<seed>``, with
   ``-mu<friction>`` appended when ``--friction`` is given):
   ``config.toml`` (the resolved configuration, every key), the scene
   (:func:`softpack.scene.build.build_scene`:
   ``mesh/packing.{xdmf,h5,bodies.csv,packing.csv}``) and ``driver.json``
   (:mod:`softpack.simulation.driver_input`, docs/contract.md section 4).
3. Run the driver (:mod:`softpack.simulation.driver`) in DIR; its output
   goes to ``DIR/run.log``, and the terminal shows progress (percent, Phi,
   ETA) read from ``raw/steps.csv`` as the driver writes it.
4. Post-process (:func:`softpack.analysis.observables.process_run`) into
   ``particles.csv`` and then ``series.csv``.

softpack deletes only what it wrote (issues 16, 42). A run directory is
marked by ``.softpack-run``, and only a marked one is softpack's; in one,
the outputs listed in
:data:`~softpack.contract.run_directory.RUN_OUTPUTS` are replaced and nothing
else is touched. A directory with ``series.csv`` holds a complete run: it
is not overwritten without ``--force``. A non-empty directory that is not
a run directory is refused; with ``--force`` the run is written next to
its files, unless one of them has the name of an output. A crashed or
interrupted run leaves no ``series.csv`` (a stale one is deleted before
anything starts), and ``raw/done.json`` only if the driver finished.

The driver dies with this process (:mod:`softpack.simulation.driver`):
SIGINT, SIGTERM, SIGHUP and a closed standard output (``| head``) stop it
and exit with 128 + the signal number
(:mod:`softpack.simulation.interrupt`).

``--resume DIR`` finishes a killed run from its last state
(:mod:`softpack.simulation.resume`). ``--observables-only`` recomputes
``series.csv`` and ``particles.csv`` of a finished simulation from its raw
output and its own ``config.toml`` (edit its [observables] section to
change the rules).

Exit status (:data:`~softpack.contract.run_directory.EXIT_DONE` ...): 0
done, 1 failure (packing, driver, post-processing), 2 bad configuration or
command line (including an unusable ``--out``), 3 finished but flagged
(:func:`~softpack.contract.run_directory.run_flags`: a stage program ended
before its criterion, a solve left unconverged, bodies overlapping beyond
``contact.alert_distance``; every output written), 128 + N stopped by
signal N (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP, 141 closed output).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time
import tomllib
from pathlib import Path

from softpack.paths import ROOT
from softpack.scene.config import (ConfigError,
                                   load_config, to_toml)
from softpack.simulation import driver
from softpack.simulation.driver import DRIVER, DriverFailed
from softpack.simulation.interrupt import (Stopped, echo, reclaim_signals,
                                           silence_stdout, stop_on_signals,
                                           why)
from softpack.simulation.postprocess import postprocess, postprocess_3d
from softpack.simulation.progress import Progress, duration as _duration
from softpack.contract.run_directory import (EXIT_DONE, EXIT_FAILED,
                                             EXIT_USAGE, RunDirectory,
                                             RunError, RunLock, UsageError,
                                             is_run_directory,
                                             prepare_directory)


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack run``."""
    p = argparse.ArgumentParser(
        prog="softpack run",
        description="Run the assembly a TOML file describes: particles of"
        " any shape and material (soft or rigid), walls driven by velocity,"
        " pressure or force, loading stages (default: examples/paper.toml,"
        " the paper's 100 soft disks compressed by a piston to Phi = 0.88);"
        " write the raw output, series.csv, particles.csv, network.csv and"
        " (in a box) stress.csv into the run directory.")
    p.add_argument("config", nargs="?", type=Path,
                   help="TOML configuration (default: examples/paper.toml)")
    p.add_argument("--out", type=Path, metavar="DIR",
                   help="run directory (default: runs/<config stem>-seed"
                   "<seed>[-mu<friction>])")
    p.add_argument("--seed", type=int,
                   help="override [packing] seed (random packing)")
    p.add_argument("--friction", type=float,
                   help="override [contact] friction (mu_f)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   dest="settings",
                   help="override any key, e.g. --set time.time_step=3.6e-5"
                   " (VALUE in TOML syntax; repeatable)")
    p.add_argument("--force", action="store_true",
                   help="overwrite a complete run in DIR")
    p.add_argument("--from-state", type=Path, metavar="FILE",
                   help="start from a state another run wrote"
                   " (DIR/raw/state.bin: its last output step) instead of"
                   " from rest; the config must give the same packing and"
                   " mesh (sizes are checked), other settings may differ")
    p.add_argument("--resume", type=Path, metavar="DIR",
                   help="finish the killed run in DIR from its last state"
                   " (DIR/raw/state.bin, written at every output step)"
                   " with DIR's own config.toml; the series is the one an"
                   " uninterrupted run would have written")
    p.add_argument("--ranks", type=int, default=1, metavar="N",
                   help="MPI ranks (mpirun -np N): the bodies split by"
                   " space, each rank computing its own (1 to the number"
                   " of bodies; default 1)")
    p.add_argument("--initial-only", action="store_true",
                   help="build the scene and let the driver read, check and"
                   " write the initial state (raw/setup.json, the fields at"
                   " t = 0) and stop before the first step: no series.csv;"
                   " a 3D scene's only run until the 3D time step is built"
                   " (docs/bodies_3d.md)")
    p.add_argument("--observables-only", action="store_true",
                   help="only recompute series.csv, particles.csv,"
                   " network.csv and stress.csv of the run in --out DIR from"
                   " its raw output"
                   " and the [observables] rules of DIR/config.toml, which"
                   " --set observables.KEY=VALUE changes first")
    return p


def main(argv=None) -> int:
    """Entry point of ``./softpack run``; returns the exit status."""
    args = _parser().parse_args(argv)
    if args.resume is not None:
        if args.config or args.out or args.settings or args.from_state:
            print("softpack run: --resume DIR takes DIR's own config.toml:"
                  " no CONFIG, --out, --set or --from-state with it",
                  file=sys.stderr)
            return 2
        if not is_run_directory(args.resume):
            print(f"softpack run: --resume {args.resume}: not a softpack"
                  " run directory", file=sys.stderr)
            return 2
        args.out = args.resume
        args.config = RunDirectory(args.resume).config_toml
    if args.observables_only:
        return _observables_only(args)
    path = args.config or _default_config()
    overrides = {}
    if args.seed is not None:
        overrides["packing.seed"] = args.seed
    if args.friction is not None:
        overrides["contact.friction"] = args.friction
    try:
        overrides.update(_parse_settings(args.settings))
        config = load_config(path, overrides)
    except ConfigError as err:
        print(f"softpack run: {err}", file=sys.stderr)
        return 2
    # Absolute: the driver runs with the run directory as its cwd.
    out = Path(os.path.abspath(
        args.out or default_out_dir(config, args.friction is not None)))
    previous = stop_on_signals()
    try:
        if args.resume is not None:
            return resume(config, out, ranks=args.ranks)
        return run(config, out, force=args.force,
                   initial_state=args.from_state, ranks=args.ranks,
                   initial_only=args.initial_only)
    except RunError as err:
        return _said(err)
    except (KeyboardInterrupt, Stopped) as err:
        signum = getattr(err, "signum", signal.SIGINT)
        if signum == signal.SIGPIPE:  # nowhere to print; no exit traceback
            silence_stdout()
        print(f"\nsoftpack run: stopped ({why(err)}); the driver was"
              " stopped and no series.csv written", file=sys.stderr)
        return 128 + int(signum)
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _observables_only(args) -> int:
    """``--observables-only --out DIR [--set observables.KEY=VALUE ...]``:
    the analysis of DIR again; the changed rules are written to
    DIR/config.toml first (the analysis reads its rules there, and the
    configuration stays the one the tables were made with)."""
    def refuse(text) -> int:
        print(f"softpack run: --observables-only: {text}", file=sys.stderr)
        return 2
    given = [flag for flag, value in (
        ("CONFIG", args.config), ("--seed", args.seed),
        ("--friction", args.friction), ("--from-state", args.from_state),
        ("--force", args.force)) if value]
    if given:
        return refuse(f"no {', '.join(given)} with it: it takes the run's"
                      " own config.toml (--out DIR, --set observables.*)")
    if args.out is None or not is_run_directory(args.out):
        return refuse(f"--out {args.out}: not a softpack run directory"
                      if args.out else "which run? (--out DIR)")
    out = Path(os.path.abspath(args.out))
    try:
        settings = _parse_settings(args.settings)
        other = sorted(k for k in settings if not k.startswith("observables."))
        if other:
            return refuse(f"--set {', '.join(other)}: only [observables]"
                          " rules change without a new run")
        run_dir = RunDirectory(out)
        with RunLock(out):
            if settings:
                config = load_config(run_dir.config_toml, settings)
                tmp = run_dir.path / ".config.toml.tmp"
                tmp.write_text(to_toml(config))
                tmp.replace(run_dir.config_toml)
            if load_config(run_dir.config_toml)["model"]["dimension"] == 3:
                return postprocess_3d(out, None)
            return postprocess(out, None)
    except ConfigError as err:
        return refuse(str(err))
    except RunError as err:
        return _said(err)


def _said(err) -> int:
    """Say a UsageError (exit status 2) or another RunError (1); the status."""
    print(f"softpack run: {err}", file=sys.stderr)
    return EXIT_USAGE if isinstance(err, UsageError) else EXIT_FAILED


def _parse_settings(settings) -> dict:
    """``["time.time_step=3.6e-5", ...]`` -> ``{"time.time_step": 3.6e-5}``."""
    overrides = {}
    for item in settings:
        key, sep, value = item.partition("=")
        if not sep or "." not in key:
            raise ConfigError(f"--set {item!r}: expected SECTION.KEY=VALUE")
        try:
            overrides[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            raise ConfigError(f"--set {item!r}: {value!r} is not a TOML"
                              " value (strings need quotes)") from None
    return overrides


def _default_config() -> Path:
    """``examples/paper.toml`` of the working directory or of the repo."""
    local = Path("examples/paper.toml")
    return local if local.is_file() else ROOT / "examples" / "paper.toml"


def default_out_dir(config, with_friction=False) -> Path:
    """``runs/<stem>-seed<seed>``, plus ``-mu<friction>`` if asked."""
    name = f"{config.stem}-seed{config['packing']['seed']}"
    if with_friction:
        name += f"-mu{config['contact']['friction']:g}"
    return Path("runs") / name


def run(config, out: Path, force=False, initial_state: Path | None = None,
        verbose=True, ranks=1, initial_only=False) -> int:
    """Packing, mesh, driver, observables into ``out``; returns EXIT_DONE,
    or EXIT_FLAGGED when the finished run is flagged (run_flags).

    Parameters
    ----------
    config : Config
        From :func:`softpack.scene.config.load_config`.
    out : Path
        The run directory (see :func:`prepare_directory`).
    force : bool
        Replace a complete run; write into a foreign non-empty directory.
    initial_state : Path, optional
        A state file (``raw/state.bin`` of a run on the same packing) to
        start from instead of rest.
    verbose : bool
        Print the log lines and the progress (always written to run.log).
    ranks : int
        MPI ranks of the driver (:func:`driver.check_ranks`).
    initial_only : bool
        The driver writes the initial state and stops before the first
        step (``--initial-only``); no observables.

    Raises
    ------
    RunError
        UsageError for an unusable ``out``.
    Stopped, KeyboardInterrupt
        The driver was stopped; logged in run.log.
    """
    out = Path(os.path.abspath(out))
    driver.executable()
    _check_ranks(ranks, config)
    if initial_state is not None:
        initial_state = Path(initial_state).resolve()
        if not initial_state.is_file():
            raise UsageError(f"--from-state: {initial_state}: no such file")
        _check_state(initial_state)
        if initial_state.is_relative_to(out.resolve()):
            raise RunError(f"--from-state: {initial_state} is inside the"
                           f" run directory {out}, which is cleared first;"
                           " copy it elsewhere")
    known = _check_user_shapes(config)
    with prepare_directory(out, force):  # the directory's lock, held
        return _run_locked(config, out, initial_state, verbose, ranks, known,
                           initial_only)


def _run_locked(config, out, initial_state, verbose, ranks, known,
                initial_only=False) -> int:
    """:func:`run` in its prepared, locked directory."""
    RunDirectory(out).config_toml.write_text(to_toml(config))
    with open(RunDirectory(out).run_log, "a", buffering=1) as log:
        say = _reporter(log, verbose)
        try:
            say.ranks = ranks
            return _run_logged(config, out, initial_state, log, say, known,
                               initial_only)
        except (KeyboardInterrupt, Stopped) as err:
            log.write(f"[softpack run {time.strftime('%H:%M:%S')}] stopped"
                      f" ({why(err)}): the driver was stopped; no"
                      " series.csv\n")
            raise


def resume(config, out: Path, verbose=True, ranks=1) -> int:
    """Finish the killed run in ``out`` (:mod:`softpack.simulation.resume`).

    Raises
    ------
    RunError
        UsageError when ``out`` is not a run directory, or another run
        works in it.
    """
    out = Path(os.path.abspath(out))
    if not is_run_directory(out):
        raise UsageError(f"--resume {out}: not a softpack run directory")
    driver.executable()
    _check_ranks(ranks, config)
    with RunLock(out):
        return _resume_locked(config, out, verbose, ranks)


def _resume_locked(config, out, verbose, ranks) -> int:
    """:func:`resume` with the directory's lock held."""
    from softpack.simulation.resume import finish_resume, prepare_resume

    step, added = prepare_resume(out, config, RunError)
    with open(RunDirectory(out).run_log, "a", buffering=1) as log:
        say = _reporter(log, verbose)
        try:
            say.ranks = ranks
            say(f"resuming {out} from its state at step {step}")
            if added:
                say("driver.json completed with the keys added to the"
                    f" schema since the run was made: {', '.join(added)}")
            _drive(config, out, log, say, resumed=True)
            finish_resume(out)
            if config["model"]["dimension"] == 3:
                return postprocess_3d(out, say)
            return postprocess(out, say)
        except (KeyboardInterrupt, Stopped) as err:
            log.write(f"[softpack run {time.strftime('%H:%M:%S')}] stopped"
                      f" ({why(err)}): the driver was stopped; no"
                      " series.csv (resume again)\n")
            raise


def _check_state(path: Path) -> None:
    """UsageError unless the driver reads ``path`` as a state file (before
    the packing, the mesh and the driver start)."""
    from softpack.simulation.resume import state_step

    try:
        state_step(path)
    except ValueError as err:
        raise UsageError(f"--from-state: {err}") from None


def _check_user_shapes(config) -> dict:
    """UsageError for a user's shape file that is missing or cannot be
    meshed (before anything is written); the user shapes' templates."""
    from softpack.scene.build import check_user_shapes
    from softpack.scene.shapes import ShapeError

    try:
        return check_user_shapes(config)
    except ShapeError as err:
        raise UsageError(f"{config.source}: {err}") from None


def _check_ranks(ranks, config) -> None:
    """UsageError unless 1 <= ranks <= bodies (before anything is written)."""
    try:
        driver.check_ranks(ranks, config)
    except ConfigError as err:
        raise UsageError(str(err)) from None


def _drive(config, out, log, say, scene=None, initial_state=None,
           initial_only=False, resumed=False) -> None:
    """Run the driver on ``out/driver.json`` (written first from ``scene``
    if given), its output to the log, progress shown (``resumed``: from the
    killed part's rows on); RunError if it fails."""
    run = RunDirectory(out)
    ranks = getattr(say, "ranks", 1)
    say(f"{DRIVER} {run.driver_json}"
        + (f" on {ranks} MPI ranks" if ranks > 1 else ""))
    started = time.time()
    progress = Progress(config, run.raw.steps_csv,
                        echo if say.verbose else None,
                        run.raw_part.steps_csv if resumed else None)
    try:
        driver.launch(run, config if scene is not None else None, scene,
                      initial_state=initial_state, log=log, ranks=ranks,
                      watch=lambda final: progress.update(log, final=final),
                      initial_only=initial_only)
    except DriverFailed as err:
        say(f"{DRIVER} failed with exit status {err.status}")
        raise
    say(f"{DRIVER} done in {_duration(time.time() - started)}")


def _run_logged(config, out, initial_state, log, say, known=None,
                initial_only=False) -> int:
    """The body of :func:`run` once run.log is open."""
    from softpack.scene.build import build_scene
    from softpack.scene.packing import PackingError

    say(f"{config.source} -> {out}")
    try:
        scene = build_scene(config, RunDirectory(out).mesh_stem("packing"),
                            known)
    except PackingError as err:
        # the scene's messages name the keys; the file is the run's config
        # (said once: the caller prints the error, the log keeps it)
        log.write(f"[softpack run {time.strftime('%H:%M:%S')}] scene"
                  f" failed: {err}\n")
        raise RunError(f"{config.source}: {err}") from None
    reclaim_signals()
    if config["model"]["dimension"] == 3:
        from softpack.analysis.solids import scene_summary

        say(scene_summary(scene.mesh.xdmf, scene.packing.extent,
                          config["packing"]["seed"]))
    else:
        phi0 = scene.packing.packing_fraction
        say(f"packing: {scene.packing.n_particles} particles, seed"
            f" {config['packing']['seed']}, Phi0 = {phi0:.4f}; mesh:"
            f" {scene.mesh.n_triangles} triangles")
    if initial_state is not None:
        say(f"starting from {initial_state}")
    _drive(config, out, log, say, scene.record(), initial_state,
           initial_only)
    if initial_only:
        say(f"initial state written ({RunDirectory(out).raw.setup_json},"
            " fields.xdmf); --initial-only: no step, no series.csv")
        return EXIT_DONE
    if config["model"]["dimension"] == 3:
        return postprocess_3d(out, say)
    return postprocess(out, say)


def _reporter(log, verbose=True):
    """``say(text)``: print a line (if ``verbose``), append it to the log."""
    def say(text):
        if verbose:
            echo(f"softpack run: {text}")
        log.write(f"[softpack run {time.strftime('%H:%M:%S')}] {text}\n")
        log.flush()
    say.verbose = verbose
    return say
