"""``./softpack run [CONFIG] [--out DIR]``: one compaction, start to finish.

1. Validate CONFIG (default ``examples/paper.toml``) with the command-line
   overrides ``--seed`` and ``--friction``; on error print the message and
   exit with status 2 before writing anything.
2. Write into DIR (default ``runs/<config stem>-seed<seed>``, with
   ``-mu<friction>`` appended when ``--friction`` is given):
   ``config.toml`` (the resolved configuration, every key),
   ``mesh/packing.{xdmf,h5,bodies.csv,packing.csv}`` (random packing and
   its mesh), ``driver.json`` (``docs/driver_io.md``).
3. Run ``$SOFTPACK_BIN/softpack-simulate DIR/driver.json`` (``build/bin``
   when ``SOFTPACK_BIN`` is unset); its output goes to ``DIR/run.log``,
   and the terminal shows progress (percent, strain, Phi, ETA) read from
   ``raw/steps.csv`` as the driver writes it.
4. Post-process (:mod:`softpack.analysis.observables`) into ``particles.csv`` and
   then ``series.csv``, each written to a temporary file and renamed.

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
import tomllib
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from softpack.scene.config import (ConfigError, initial_packing_fraction,
                             load_config, to_driver_json, to_toml)

from softpack.paths import ROOT
DRIVER = "softpack-simulate"
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
                   help="override [geometry] seed (random packing)")
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
        overrides["geometry.seed"] = args.seed
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
    name = f"{config.stem}-seed{config['geometry']['seed']}"
    if with_friction:
        name += f"-mu{config['contact']['friction']:g}"
    return Path("runs") / name


def driver_executable() -> Path:
    """``$SOFTPACK_BIN/softpack-simulate``, else ``build/bin``'s."""
    bin_dir = os.environ.get("SOFTPACK_BIN") or ROOT / "build" / "bin"
    exe = Path(bin_dir) / DRIVER
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        raise RunError(f"{exe} not found: build it with ./softpack build"
                       " (or set SOFTPACK_BIN)")
    return exe


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
    from softpack.scene.mesh import mesh_disks
    from softpack.scene.packing import PackingError, random_packing

    exe = driver_executable()
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
        g = config["geometry"]
        try:
            packing = random_packing(
                g["seed"], counts=g["counts"], diameters=g["diameters"],
                length=g["length"], width=g["width"], gap=g["gap"])
        except PackingError as err:
            raise RunError(f"packing: {err}") from None
        info = mesh_disks(packing.centres, packing.radii,
                          config["mesh"]["element_size"],
                          out / "mesh" / "packing")
        packing.to_csv(out / "mesh" / "packing.packing.csv")
        say(f"packing: {packing.n_particles} disks, seed {g['seed']},"
            f" Phi0 = {packing.packing_fraction:.4f}; mesh: "
            f"{info.n_triangles} triangles")
        to_driver_json(config, info.xdmf, out,
                       initial_state=initial_state)
        if initial_state is not None:
            say(f"starting from {initial_state}")
        say(f"{exe} {out / 'driver.json'}")
        started = time.time()
        status = _simulate(exe, out, config, log)
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


def _simulate(exe, out, config, log) -> int:
    """Run the driver, its output to the log; show progress; exit status."""
    progress = Progress(config, out / "raw" / "steps.csv")
    log.flush()
    proc = subprocess.Popen([str(exe), str(out / "driver.json")], cwd=out,
                            stdin=subprocess.DEVNULL, stdout=log,
                            stderr=subprocess.STDOUT)
    try:
        while proc.poll() is None:
            time.sleep(POLL_SECONDS)
            progress.update(log)
    except BaseException:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        raise
    progress.update(log, final=True)
    return proc.returncode


class Progress:
    """Progress of a running driver from the rows of ``raw/steps.csv``.

    The fraction done is the larger of ``(Phi - Phi0) / (target - Phi0)``
    and ``time / max_time`` (the two stopping criteria); the ETA assumes the
    rest goes at the same pace.
    """

    def __init__(self, config, steps_csv: Path):
        self.steps_csv = steps_csv
        self.phi0 = initial_packing_fraction(config)
        self.target = config["loading"]["target_packing_fraction"]
        self.max_time = config["loading"]["max_time"]
        self.length = config["geometry"]["length"]
        self.piston_speed = config["loading"]["piston_speed"]
        self.started = time.time()
        self.tty = sys.stdout.isatty()
        self.logged = -1  # last 5 % mark written to the log / non-tty

    def fraction(self, phi, t) -> float:
        """Fraction of the run done, in [0, 1]."""
        done = max((phi - self.phi0) / (self.target - self.phi0)
                   if phi == phi else 0.0, t / self.max_time)
        return min(max(done, 0.0), 1.0)

    def line(self, row) -> str:
        """One progress line from the last row of ``steps.csv``."""
        t, phi = row["time"], row.get("phi", float("nan"))
        length = row.get("piston_x", float("nan")) - row.get("left_x", 0.0)
        if not length > 0:  # no wall columns: assume the nominal speed
            length = self.length - self.piston_speed * t
        eps = -math.log(length / self.length) if length > 0 else math.inf
        done = self.fraction(phi, t)
        elapsed = time.time() - self.started
        eta = elapsed * (1 - done) / done if done > 0 else float("nan")
        return (f"{100 * done:5.1f} %  step {int(row['step'])}  t = {t:.4g}"
                f" s  eps = {eps:.4f}  Phi = {phi:.4f}  elapsed"
                f" {_duration(elapsed)}  ETA {_duration(eta)}")

    def update(self, log, final=False) -> None:
        """Show the latest row: a live line on a terminal, 5 % marks else."""
        row = _last_row(self.steps_csv)
        if row is None:
            return
        text = self.line(row)
        mark = int(20 * self.fraction(row.get("phi", float("nan")),
                                      row["time"]))
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
    from softpack.analysis.observables import process_run, read_table

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
