"""``./softpack bench --mpi``: the driver on 1, 2 and 4 MPI ranks (issue 14).

The paper case (100 disks at the paper's mesh, the default settings) for
``--steps`` time steps, from a state a run wrote (``--from-state``: the
crowded end of a compaction) or from the initial packing, on 1, 2 and 4
ranks with one OpenMP thread each (so that the ranks, not the threads, are
measured; 4 ranks are oversubscribed on a 2-core machine and reported as
such). For each: the wall time of the stepping and its split by part
(raw/done.json), the peak memory of each rank and the bytes each rank handed
to collectives, per step, and what its domain-wise NLGS sent per sweep
(done.json's "mpi"), and whether the run is the 1-rank run (Phi and strain
energy of the last step).

With ``--mpi-to-phi PHI`` the runs go from the state to that packing
fraction instead, writing every 12 steps, and are compared output step by
output step with the 1-rank run (issue 14's check): Phi and the strain
energy at every output step, and in every contact file the same contacts
and their normal forces.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from softpack.bench.common import FAST, scaled_config, scene_for, stepping_cost
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.simulation import driver


def run_ranks(config, scene: dict, out: Path, ranks: int,
              initial_state: Path | None) -> dict:
    """One driver run on ``ranks`` ranks; its cost, memory and traffic."""
    run = RunDirectory(out)
    finished = driver.launch(run, config, scene, initial_state=initial_state,
                             log=run.driver_log, quiet=True, ranks=ranks,
                             threads=1)
    # One rank: its own peak memory (os.wait4); several: done.json's.
    done, peak_mb = finished.done, finished.peak_memory_mb
    cost = stepping_cost(run, done)
    rows = read_table(run.raw.steps_csv)
    steps = cost["steps"]
    mpi = done.get("mpi", {})
    result = {"ranks": ranks, "cores": len(os.sched_getaffinity(0)),
              "oversubscribed": ranks > len(os.sched_getaffinity(0)),
              "steps": steps, "seconds": cost["seconds"],
              "ms_per_step": cost["ms_per_step"],
              "phi": float(rows["phi"][-1]),
              "strain_energy": float(rows["strain_energy"][-1]),
              "contacts": int(rows["contacts"][-1]),
              "nlgs_sweeps": int(rows["nlgs_iterations"][-1]),
              "bodies_per_rank": mpi.get(
                  "bodies", [sum(s["count"] for s in config["species"])]),
              "peak_rss_mb_per_rank": mpi.get("peak_rss_mb", [peak_mb]),
              "kb_sent_per_step_per_rank":
                  [b / 1e3 / steps for b in mpi.get("bytes_sent", [])],
              "collectives_per_step":
                  [c / steps for c in mpi.get("collectives", [])],
              # the domain-wise NLGS: what a rank sends after each sweep
              "nlgs_sweeps_per_step_per_rank":
                  [w / steps for w in mpi.get("nlgs_sweeps", [])],
              "nlgs_bytes_per_sweep_per_rank":
                  [b / max(w, 1) for b, w in zip(
                      mpi.get("nlgs_bytes_sent", []),
                      mpi.get("nlgs_sweeps", []))],
              "nlgs_kb_per_step_per_rank":
                  [b / 1e3 / steps for b in mpi.get("nlgs_bytes_sent", [])]}
    result.update({k: v for k, v in cost.items() if k.startswith("ms_")
                   and k != "ms_per_step"})
    return result


def _forces_by_contact(table) -> dict:
    """Normal force by contact (candidate, node, antagonist, wall)."""
    keys = zip(*(np.asarray(table[k]).astype(int).tolist() for k in (
        "candidate", "node", "antagonist", "wall")))
    return dict(zip(keys, np.asarray(table["fn"], dtype=float).tolist()))


def same_run(serial: Path, other: Path) -> dict:
    """Largest differences of a run's output steps from the serial run's:
    Phi (absolute) and the strain energy (relative); per contact file, the
    contacts (candidate, node, antagonist, wall) found by one run only, and
    the largest difference of a normal force of a contact both found,
    relative to the file's largest force."""
    serial, other = RunDirectory(serial).raw, RunDirectory(other).raw
    a = read_table(serial.steps_csv)
    b = read_table(other.steps_csv)
    if len(a["step"]) != len(b["step"]):
        return {"output_steps": [len(a["step"]), len(b["step"])]}
    files = sorted(p.name for p in serial.contacts.iterdir())
    one_run_only, fn_diff = {}, 0.0
    for name in files:
        x = _forces_by_contact(read_table(serial.contacts / name))
        y = _forces_by_contact(read_table(other.contacts / name))
        if set(x) != set(y):
            one_run_only[name] = sorted(set(x) ^ set(y))
        both = set(x) & set(y)
        scale = max((abs(x[k]) for k in both), default=0.0)
        if scale > 0:
            fn_diff = max(fn_diff, max(abs(x[k] - y[k]) for k in both) / scale)
    energy = np.asarray(a["strain_energy"], dtype=float)
    return {"output_steps": len(a["step"]),
            "phi_max_abs_diff": float(np.max(np.abs(
                np.asarray(b["phi"]) - np.asarray(a["phi"])))),
            "strain_energy_max_rel_diff": float(np.max(np.abs(
                np.asarray(b["strain_energy"]) - energy) / energy)),
            "contact_files": len(files),
            "contacts_in_one_run_only": one_run_only,
            "fn_max_rel_diff": fn_diff}


def bench_mpi(work: Path, steps: int, state: Path | None,
              ranks=(1, 2, 4), to_phi: float | None = None) -> dict:
    """The paper case on each number of ranks (see the module)."""
    if to_phi is None:
        # Steps, not Phi, end these runs (a state may be past the target).
        sets = {"stop.steps": steps, "stop.packing_fraction": 0,
                "output.every_steps": steps}
    else:
        sets = {"stop.packing_fraction": to_phi, "output.every_steps": 12,
                "output.fields": False}
    config = scaled_config(1, {**FAST, **sets})
    scene = scene_for(config, "n100")
    runs = [run_ranks(config, scene, work / f"mpi-{n}", n, state)
            for n in ranks]
    if to_phi is not None:
        for n, r in zip(ranks, runs):
            r["against_serial"] = same_run(work / f"mpi-{ranks[0]}",
                                           work / f"mpi-{n}")
    serial = runs[0]
    for r in runs:
        r["phi_minus_serial"] = r["phi"] - serial["phi"]
        r["strain_energy_rel_diff"] = (
            r["strain_energy"] / serial["strain_energy"] - 1)
        r["speedup"] = serial["seconds"] / r["seconds"]
        # detection runs whole on every rank; the NLGS is split by domain
        r["replicated_fraction"] = r["ms_detection"] / r["ms_per_step"]
    return {"case": "paper (100 disks), defaults",
            "steps": steps if to_phi is None else None, "to_phi": to_phi,
            "from_state": str(state) if state else None, "runs": runs}


def table(report: dict) -> str:
    """The report as text lines."""
    lines = [f"{report['case']}, "
             + (f"{report['steps']} steps" if report.get("steps")
                else f"to Phi {report.get('to_phi')}")
             + (f" from {report['from_state']}" if report["from_state"]
                else "")]
    for r in report["runs"]:
        lines.append(
            f"{r['ranks']} rank(s){' (oversubscribed)' if r['oversubscribed'] else ''}:"
            f" {r['ms_per_step']:.0f} ms/step (speed-up {r['speedup']:.2f}),"
            f" replicated detection {100 * r['replicated_fraction']:.0f} %,"
            f" NLGS {r['ms_nlgs']:.0f} ms/step, sending"
            f" {[round(b) for b in r['nlgs_bytes_per_sweep_per_rank']]}"
            f" B/sweep/rank,"
            f" peak memory per rank {r['peak_rss_mb_per_rank']} MB,"
            f" sent {[round(k, 1) for k in r['kb_sent_per_step_per_rank']]}"
            f" kB/step/rank, dPhi {r['phi_minus_serial']:.1e},"
            f" dE/E {r['strain_energy_rel_diff']:.1e}")
        if "against_serial" in r:
            lines.append(f"  against 1 rank, every output step:"
                         f" {r['against_serial']}")
    return "\n".join(lines)
