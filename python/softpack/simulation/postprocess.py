"""After the driver: a run directory's observables and its summary.

:func:`postprocess` (``series.csv``, ``particles.csv``, ``network.csv``,
``stress.csv`` and the summary lines, in either dimension) and
:func:`postprocess_3d` (3D: two lines on the raw output first,
docs/bodies_3d.md); both return the run's exit status,
EXIT_FLAGGED with the reason when ``raw/done.json`` flags the run.
"""

from __future__ import annotations

from pathlib import Path

from softpack.contract.run_directory import (EXIT_DONE, EXIT_FLAGGED,
                                             RunDirectory, RunError,
                                             run_flags)
from softpack.scene.config import ConfigError
from softpack.simulation.interrupt import echo


def postprocess_3d(out: Path, say) -> int:
    """A 3D run: its raw output's Phi, phi_base and energy balance in two
    lines, then :func:`postprocess` (the observables of both dimensions:
    series.csv, particles.csv, network.csv, stress.csv; docs/bodies_3d.md)."""
    from softpack.contract.tables import read_table

    run = RunDirectory(out)
    finish = run.done()
    if say is None:
        def say(text):
            echo(f"softpack run: {text}")
    steps = read_table(run.raw.steps_csv)
    phi, residual = steps["phi"], steps["energy_residual"]
    supplied = max(abs(float(w)) for w in steps["wall_work"])
    say(f"stopped by {finish.get('reason', '?')} after"
        f" {finish.get('steps', '?')} steps, t = {steps['time'][-1]:.4g} s;"
        f" Phi (volume fraction) {phi[0]:.4f} -> {phi[-1]:.4f};"
        f" energy balance residual {residual[-1]:.3g} J of"
        f" {supplied:.3g} J supplied by the walls")
    if "phi_base" in steps and steps["phi_base"][0] > 0:
        say(f"phi_base (the bottom faces' area fraction of the base)"
            f" {steps['phi_base'][0]:.4f} -> {steps['phi_base'][-1]:.4f}")
    return postprocess(out, say)


def exit_status(finish: dict, say) -> int:
    """EXIT_FLAGGED, saying why, if raw/done.json's run is flagged; else
    EXIT_DONE."""
    flags = run_flags(finish)
    if flags:
        say("finished flagged (exit status 3): " + "; ".join(flags))
        return EXIT_FLAGGED
    return EXIT_DONE


def postprocess(out: Path, say) -> int:
    """Check the driver finished, write the observables, print a summary."""
    from softpack.analysis.observables import (process_run, retained_report,
                                               z_report)
    from softpack.analysis.summary import check_lines, summary_lines
    from softpack.contract.tables import read_table

    finish = RunDirectory(out).done()
    if say is None:
        def say(text):
            echo(f"softpack run: {text}")
    try:
        series_csv, particles_csv = process_run(out)
    except (OSError, ValueError, KeyError, ConfigError) as err:
        raise RunError(f"post-processing {out}: {err}") from None
    s = read_table(series_csv)
    for line in summary_lines(out):
        say(line)
    for report in (z_report(s), retained_report(s)):  # Z says what it is
        if report:
            say(report)
    for line in check_lines(finish):
        say(line)
    say(f"wrote {series_csv} and {particles_csv}")
    return exit_status(finish, say)

