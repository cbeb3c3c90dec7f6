"""``./softpack run [CONFIG] [--out DIR]``: one compaction, start to finish.

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

A directory with ``series.csv`` holds a complete run: it is not overwritten
without ``--force``. A crashed or interrupted run leaves no ``series.csv``
(a stale one is deleted before anything starts). ``--observables-only``
recomputes ``series.csv`` and ``particles.csv`` of a finished simulation
from its raw output and its own ``config.toml`` (edit its [observables]
section to change the rules).

Exit status: 0 done, 1 failure (packing, driver, post-processing), 2 bad
configuration or command line, 130 interrupted.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
import tomllib
from pathlib import Path

from softpack.paths import ROOT
from softpack.scene.config import (ConfigError, initial_packing_fraction,
                                   load_config, to_toml)
from softpack.simulation import driver
from softpack.simulation.driver import DRIVER, DriverError
from softpack.simulation.driver_input import write_driver_json

#: What a run writes into its directory (removed by --force, nothing else).
RUN_OUTPUTS = ("series.csv", "particles.csv", "raw", "fields.xdmf",
               "fields.h5", "mesh", "driver.json", "run.log", "config.toml")
POLL_SECONDS = 1.0


class RunError(RuntimeError):
    """A run that cannot go on; the message says why."""


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack run``."""
    p = argparse.ArgumentParser(
        prog="softpack run",
        description="Compress an assembly of soft disks with the piston up"
        " to the target packing fraction; write raw output, series.csv and"
        " particles.csv into the run directory.")
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
    p.add_argument("--observables-only", action="store_true",
                   help="only recompute series.csv and particles.csv from"
                   " DIR's raw output and DIR/config.toml")
    return p


def main(argv=None) -> int:
    """Entry point of ``./softpack run``; returns the exit status."""
    args = _parser().parse_args(argv)
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
    out = (args.out or default_out_dir(config, args.friction is not None)).resolve()
    try:
        if args.observables_only:
            return _postprocess(out, None)
        return run(config, out, force=args.force,
                   initial_state=args.from_state)
    except RunError as err:
        print(f"softpack run: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("\nsoftpack run: interrupted; no series.csv written",
              file=sys.stderr)
        return 130


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


def driver_executable() -> Path:
    """The driver's executable (raises RunError when it is not built)."""
    try:
        return driver.executable()
    except DriverError as err:
        raise RunError(str(err)) from None


def prepare_directory(out: Path, force: bool) -> None:
    """Refuse a complete run unless ``force``; remove previous outputs."""
    if (out / "series.csv").exists() and not force:
        raise RunError(f"{out} holds a complete run (series.csv); use"
                       " --force to overwrite it or --out for another"
                       " directory")
    for name in RUN_OUTPUTS:  # series.csv first: never a stale complete run
        target = out / name
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        elif target.exists() or target.is_symlink():
            target.unlink()
    out.mkdir(parents=True, exist_ok=True)


def run(config, out: Path, force=False, initial_state: Path | None = None,
        ) -> int:
    """Packing, mesh, driver, observables into ``out``; returns 0.

    ``initial_state``: a state file (``raw/state.bin`` of a run on the same
    packing) to start from instead of rest.

    Raises
    ------
    RunError
    """
    from softpack.scene.build import build_scene
    from softpack.scene.packing import PackingError

    driver_executable()
    if initial_state is not None:
        initial_state = Path(initial_state).resolve()
        if not initial_state.is_file():
            raise RunError(f"--from-state: {initial_state}: no such file")
        if initial_state.is_relative_to(out.resolve()):
            raise RunError(f"--from-state: {initial_state} is inside the"
                           f" run directory {out}, which is cleared first;"
                           " copy it elsewhere")
    prepare_directory(out, force)
    (out / "config.toml").write_text(to_toml(config))
    with open(out / "run.log", "a", buffering=1) as log:
        say = _reporter(log)
        say(f"{config.source} -> {out}")
        try:
            scene = build_scene(config, out / "mesh" / "packing")
        except PackingError as err:
            raise RunError(f"packing: {err}") from None
        phi0 = scene.packing.packing_fraction
        say(f"packing: {scene.packing.n_particles} particles, seed"
            f" {config['packing']['seed']}, Phi0 = {phi0:.4f}; mesh:"
            f" {scene.mesh.n_triangles} triangles")
        write_driver_json(config, scene.record(), out, initial_state)
        if initial_state is not None:
            say(f"starting from {initial_state}")
        say(f"{DRIVER} {out / 'driver.json'}")
        started = time.time()
        status = _simulate(out, config, log)
        if status != 0:
            say(f"{DRIVER} failed with exit status {status}")
            raise RunError(f"{DRIVER} failed (exit status {status});"
                           f" last lines of {out / 'run.log'}:\n"
                           + _tail(out / "run.log"))
        say(f"{DRIVER} done in {_duration(time.time() - started)}")
        return _postprocess(out, say)


def _reporter(log):
    """``say(text)``: print a line and append it to the log."""
    def say(text):
        print(f"softpack run: {text}", flush=True)
        log.write(f"[softpack run {time.strftime('%H:%M:%S')}] {text}\n")
        log.flush()
    return say


def _simulate(out, config, log) -> int:
    """Run the driver, its output to the log; show progress; exit status."""
    progress = Progress(config, out / "raw" / "steps.csv")
    log.flush()
    proc = driver.start(out / "driver.json", log)
    try:
        while proc.poll() is None:
            time.sleep(POLL_SECONDS)
            progress.update(log)
    except BaseException:
        driver.stop(proc)
        raise
    progress.update(log, final=True)
    return proc.returncode


class Progress:
    """Progress of a running driver from the rows of ``raw/steps.csv``.

    The fraction done is the largest of ``(Phi - Phi0) / (target - Phi0)``,
    ``time / max_time`` and ``steps / stop.steps`` (the stopping criteria);
    the ETA assumes the rest goes at the same pace.
    """

    def __init__(self, config, steps_csv: Path):
        self.steps_csv = steps_csv
        self.phi0 = initial_packing_fraction(config)
        self.target = config["stop"]["packing_fraction"]
        self.max_time = config["stop"]["max_time"]
        self.max_steps = config["stop"]["steps"]
        self.first_step = None
        self.started = time.time()
        self.tty = sys.stdout.isatty()
        self.logged = -1  # last 5 % mark written to the log / non-tty

    def fraction(self, row) -> float:
        """Fraction of the run done, in [0, 1]."""
        phi, t = row.get("phi", float("nan")), row["time"]
        done = t / self.max_time
        if self.target > 0 and phi == phi:
            done = max(done, (phi - self.phi0) / (self.target - self.phi0))
        if self.max_steps > 0:
            if self.first_step is None:
                self.first_step = row["step"]
            done = max(done, (row["step"] - self.first_step) / self.max_steps)
        return min(max(done, 0.0), 1.0)

    def line(self, row) -> str:
        """One progress line from the last row of ``steps.csv``."""
        t, phi = row["time"], row.get("phi", float("nan"))
        done = self.fraction(row)
        elapsed = time.time() - self.started
        eta = elapsed * (1 - done) / done if done > 0 else float("nan")
        return (f"{100 * done:5.1f} %  step {int(row['step'])}  t = {t:.4g}"
                f" s  Phi = {phi:.4f}  elapsed {_duration(elapsed)}  ETA"
                f" {_duration(eta)}")

    def update(self, log, final=False) -> None:
        """Show the latest row: a live line on a terminal, 5 % marks else."""
        row = _last_row(self.steps_csv)
        if row is None:
            return
        text = self.line(row)
        mark = int(20 * self.fraction(row))
        if self.tty:
            print(f"\r{text}", end="\n" if final else "", flush=True)
        if mark > self.logged or final:
            self.logged = mark
            if not self.tty:
                print(text, flush=True)
            log.write(f"[progress] {text}\n")
            log.flush()


def _last_row(path: Path):
    """The last complete row of a growing CSV file as a dict, or None."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    if len(lines) < 2:
        return None
    header = lines[0].split(",")
    for line in reversed(lines[1:]):
        values = line.split(",")
        if len(values) == len(header):
            return {k: float(v) if v else float("nan")
                    for k, v in zip(header, values)
                    if v not in ("true", "false")}
    return None


def _duration(seconds) -> str:
    """``1h02m03s`` style; ``?`` when unknown."""
    if seconds != seconds or seconds == float("inf"):
        return "?"
    s = int(round(seconds))
    h, m = s // 3600, s // 60 % 60
    return f"{h}h{m:02d}m{s % 60:02d}s" if h else f"{m}m{s % 60:02d}s"


def _tail(path: Path, lines=20) -> str:
    """The last lines of a text file."""
    try:
        return "\n".join(path.read_text(errors="replace").splitlines()[-lines:])
    except OSError:
        return "(no log)"


def _postprocess(out: Path, say) -> int:
    """Check the driver finished, write the observables, print a summary."""
    from softpack.analysis.observables import process_run
    from softpack.analysis.tables import read_table

    done = out / "raw" / "done.json"
    if not done.is_file():
        raise RunError(f"{done} missing: the simulation did not finish, so"
                       " its raw output is partial")
    if say is None:
        def say(text):
            print(f"softpack run: {text}", flush=True)
    try:
        series_csv, particles_csv = process_run(out)
    except (OSError, ValueError, KeyError, ConfigError) as err:
        raise RunError(f"post-processing {out}: {err}") from None
    finish = json.loads(done.read_text())
    s = read_table(series_csv)
    last = {k: v[-1] for k, v in s.items()} if len(s["step"]) else {}
    say(f"stopped by {finish.get('reason', '?')} after"
        f" {finish.get('steps', '?')} steps; Phi = {last.get('phi', 0):.4f},"
        f" eps = {last.get('eps', 0):.4f}, Z = {last.get('z', 0):.3f}")
    say(f"wrote {series_csv} and {particles_csv}")
    return 0
