"""``./softpack run --resume DIR``: finish a run that was killed.

A run writes ``raw/state.bin`` at every output step (atomically: the
driver writes a temporary file and renames it), so a killed run can go on
from its last output step. The driver, started from a state, writes its raw
output afresh from the state's step on (``raw/steps.csv`` and
``raw/particles.csv`` truncated, ``raw/contacts/`` per step); so this
module keeps what the killed run wrote in ``raw.part/`` and merges it with
the new output afterwards:

- rows and files of steps up to and including the state's step come from
  the killed run (its row at that step holds the contact forces averaged
  over the interval before it; the resumed driver's first row has none);
- later ones from the resumed driver; its ``seconds`` column is shifted
  by the seconds the killed run had spent, so that it keeps growing;
- ``raw/setup.json`` is the original run's; ``raw/done.json``,
  ``raw/state.bin`` the resumed driver's.

``[stop] steps`` counts from the state's step in the driver, so the
resumed driver is given the steps left. A resumed run killed again is
resumed the same way (``raw.part/`` then first takes in what the previous
resumption wrote). The mesh and driver.json of the run are reused (only
``initial_state`` and ``stop.steps`` change, the paths inside the run
directory when it was copied or moved since, and a key the schema gained
since the run was made is added with the run's config.toml's value, its
default: :func:`add_new_keys`); the resumed driver continues
its fields (fields.xdmf, fields/: its frames up to the state's time kept, the
later ones dropped), so that every frame of every segment reads as one time
series however often the run is resumed.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from softpack.contract.run_directory import RawOutput, RunDirectory
from softpack.simulation.driver_input import edit_driver_json


def prepare_resume(out: Path, config, run_error) -> int:
    """Set ``out`` up for the driver to go on; the state's step.

    Parameters
    ----------
    out : Path
        A killed run's directory.
    config : Config
        Its configuration (``out/config.toml``).
    run_error : type
        The exception class to raise (RunError), with a message.
    """
    run = RunDirectory(out)
    raw, part = run.raw, run.raw_part
    if run.series_csv.exists():
        raise run_error(f"--resume {out}: holds a complete run (series.csv);"
                        " nothing to resume")
    if raw.done_json.exists():
        raise run_error(f"--resume {out}: the simulation finished (raw/"
                        "done.json); recompute its observables with"
                        f" ./softpack run --observables-only --out {out}")
    if part.path.is_dir() and raw.path.is_dir():  # killed again resuming
        if raw.steps_csv.is_file() and _rows(raw.steps_csv)[1]:
            merge_raw(part.path, raw.path)
        shutil.rmtree(raw.path)
    elif raw.path.is_dir():
        # A state the driver cannot read is refused before anything moves
        if raw.state_bin.is_file():
            try:
                state_step(raw.state_bin)
            except ValueError as err:
                raise run_error(f"--resume {out}: {err}") from None
        raw.path.rename(part.path)
    if not part.state_bin.is_file():
        raise run_error(f"--resume {out}: no raw/state.bin to resume from"
                        " (the run was killed before its first output step,"
                        " or [output] state = false); start it again")
    state = run.resume_state
    shutil.copyfile(part.state_bin, state)
    # A run with [[stages]] keeps its stage beside the state (the driver's
    # stage record, S.stage.json next to S.bin).
    if part.stage_record.is_file():
        shutil.copyfile(part.stage_record, run.resume_stage_record)
    try:
        step = state_step(state)
    except ValueError as err:
        raise run_error(f"--resume {out}: {err}") from None
    added = []

    def resume_from_state(doc):
        if config["stop"]["steps"] > 0:  # the driver counts from the state
            doc["stop"]["steps"] = max(config["stop"]["steps"] - step, 1)
        doc["initial_state"] = str(state)
        relocate(doc, run.path)
        added.extend(add_new_keys(doc, config))

    edit_driver_json(run.path, resume_from_state)
    return step, added


def add_new_keys(doc: dict, config) -> list:
    """Add to driver.json's sections the keys the schema gained since the
    run was made, with ``config``'s values (the run's config.toml read now:
    their defaults); return them as ``section.key = value``. The driver
    refuses a driver.json without every key of its schema."""
    from softpack.contract.schema import load_schema
    added = []
    for name, section in load_schema().items():
        if (section.stage != "driver" or section.is_map or name not in doc
                or not isinstance(doc[name], dict)):
            continue  # (arrays of tables are the run's own entries)
        for key, value in config[name].items():
            if key not in doc[name]:
                doc[name][key] = json.loads(json.dumps(value))
                added.append(f"{name}.{key} = {value!r}")
    return added


def relocate(doc: dict, directory: Path) -> None:
    """Point driver.json's paths inside its run directory at ``directory``:
    a run directory copied or moved after it was killed would otherwise
    have its driver write into the old one (the output directory and the
    mesh are absolute paths)."""
    old, new = str(doc["directory"]), str(Path(directory).resolve())
    if old == new:
        return

    def moved(value):
        if isinstance(value, dict):
            return {k: moved(v) for k, v in value.items()}
        if isinstance(value, list):
            return [moved(v) for v in value]
        if isinstance(value, str) and (value == old
                                       or value.startswith(old + "/")):
            return new + value[len(old):]
        return value
    doc.update(moved(doc))


def state_step(path: Path) -> int:
    """The step of a state file, as the driver that wrote it reads it.

    The state's layout is the driver's own (driver/io/state_file.h):
    ``softpack-simulate --state-info FILE`` prints its step and time.
    """
    from softpack.simulation import driver

    result = subprocess.run([str(driver.executable()), "--state-info",
                             str(path)], capture_output=True, text=True)
    if result.returncode != 0:
        raise ValueError(result.stderr.strip().removeprefix(
            "softpack-simulate: ") or f"{path}: not a softpack state file")
    return int(json.loads(result.stdout)["step"])


def finish_resume(out: Path) -> None:
    """Merge the killed part into the resumed output; tidy up."""
    run = RunDirectory(out)
    merge_raw(run.raw_part.path, run.raw.path, into_new=True)
    shutil.rmtree(run.raw_part.path)
    run.resume_state.unlink(missing_ok=True)
    run.resume_stage_record.unlink(missing_ok=True)


def merge_raw(old: Path, new: Path, into_new=False) -> None:
    """Merge two raw outputs of one run; ``new`` starts at a state's step.

    Without ``into_new`` the result goes into ``old`` (a resumption killed
    again: what it wrote joins the killed part); with it, into ``new``.
    """
    old, new = RawOutput(old), RawOutput(new)
    header, new_rows = _rows(new.steps_csv)
    step = header.index("step")
    first = int(new_rows[0][step]) if new_rows else None
    target = new if into_new else old
    _merge_table(old.steps_csv, new.steps_csv, target.steps_csv, first,
                 "seconds")
    _merge_table(old.particles_csv, new.particles_csv, target.particles_csv,
                 first, None)
    for olds, news, targets in zip(old.step_dirs, new.step_dirs,
                                   target.step_dirs):
        _merge_step_files(olds, news, targets, first)
    if into_new:
        shutil.copyfile(old.setup_json, new.setup_json)
    else:
        for source, to in ((new.state_bin, old.state_bin),
                           (new.stage_record, old.stage_record),
                           (new.done_json, old.done_json)):
            if source.exists():
                shutil.copyfile(source, to)


def _merge_table(old: Path, new: Path, target: Path, first, shift):
    """Rows of ``old`` up to ``first`` (included), then ``new``'s after it
    (:func:`splice_rows`)."""
    header, old_rows = _rows(old)
    new_header, new_rows = _rows(new)
    if new_rows and new_header != header:
        raise ValueError(f"{new}: columns differ from {old}: not the same"
                         " run")
    step = header.index("step")
    column = header.index(shift) if shift in header else None
    rows = splice_rows(old_rows, new_rows, first, step, column)
    tmp = target.with_name(target.name + ".tmp")
    with open(tmp, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(r) + "\n")
    tmp.replace(target)


def splice_rows(old_rows, new_rows, first, step, shift=None) -> list:
    """The killed part's rows up to step ``first`` (included), then the
    resumed driver's after it: one run's rows.

    Rows are lists of strings (a CSV's) or dicts of floats (the progress's);
    ``step`` and ``shift`` index them. ``shift``: a column of the new rows
    offset by the old rows' value at ``first`` (the driver's seconds restart
    at zero); None for none.
    """
    keep = [r for r in old_rows if first is None or int(r[step]) <= first]
    offset = 0.0
    if shift is not None and keep:
        at_first = [r for r in keep if int(r[step]) == first]
        offset = float((at_first or keep)[-1][shift])
    later = [r.copy() for r in new_rows if int(r[step]) > (first or -1)]
    if shift is not None and offset:
        for r in later:
            value = float(r[shift]) + offset
            r[shift] = repr(value) if isinstance(r[shift], str) else value
    return keep + later


def _merge_step_files(old: Path, new: Path, target: Path, first) -> None:
    """Per-step files: ``old``'s up to ``first`` (included), then ``new``'s."""
    if not old.is_dir() and not new.is_dir():
        return
    target.mkdir(parents=True, exist_ok=True)
    for source, wanted in ((old, lambda s: first is None or s <= first),
                           (new, lambda s: first is not None and s > first)):
        if not source.is_dir() or source == target:
            continue
        for path in source.iterdir():
            s = _step_of(path)
            if s is not None and wanted(s):
                shutil.copyfile(path, target / path.name)
    if target == new and first is not None:  # new's own files up to first
        for path in new.iterdir():
            s = _step_of(path)
            if s is not None and s <= first and not (old / path.name).exists():
                path.unlink()


def _step_of(path: Path):
    """The step of ``step_NNNNNNNN.*``, or None."""
    stem = path.name.split(".")[0]
    if stem.startswith("step_") and stem[5:].isdigit():
        return int(stem[5:])
    return None


def _rows(path: Path):
    """Header and complete rows (lists of fields) of a CSV file."""
    try:
        lines = path.read_text().splitlines()
    except OSError:
        return [], []
    if not lines:
        return [], []
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    return header, [r for r in rows if len(r) == len(header)]
