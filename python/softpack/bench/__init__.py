"""``./softpack bench``: the benchmarks under bench/ and the paper case's cost.

Runs, in order, and prints a table (also written to
``bench/results/bench-<date>.json``):

1. ``softpack-bench-nlgs``: NLGS sweeps per second on the 2020-contact FCLIB
   problem (../shared/data/fclib).
2. ``softpack-bench-detection``: contact detection time for 100, 400 and 1600
   disks and the fitted exponent of time ~ N^p.
3. The paper case (100 disks, 92k triangles): ``--steps`` time steps from the
   initial packing at the paper's settings (h = 9 us, theta 0.5, Newton 1e-6,
   NLGS 1e-8)
   and at the defaults (h = 72 us, theta 0.55, Newton 1e-4, NLGS 1e-6), with the
   per-step cost split by part (assembly, factorization, solves, Delassus,
   detection, NLGS) and the peak memory of the driver.
4. Scaling with the number of disks (25, 100, 400; same element size, box
   scaled with sqrt(N), piston speed scaled with the box length so that the
   strain rate is the same), each compressed from its initial packing to the
   same packing fraction (``--scaling-phi``, 0.80): cost per unit strain and
   the fitted exponents.

Every run is a configuration validated like a user's and launched the one
way (:mod:`softpack.bench.common`). ``--sharing``, ``--mpi`` and
``--disks`` run the benchmarks of :mod:`.sharing`, :mod:`.mpi` and
:mod:`.disks` instead (and ``--periodic`` that of :mod:`.periodic`); this module only dispatches.

``--from-state FILE`` times ``--steps`` steps of the paper case (seed 0 mesh)
from a state a run wrote (``runs/<run>/raw/state.bin``), at both settings:
the crowded end of the compaction without recomputing its start.

``--periodic 100,400`` times the periodic cell against the walled box with
the same disks (:mod:`.periodic`); ``--periodic-shear 100,400`` the same
disks' stress-controlled simple shear, in seconds per unit shear strain.

``--laws neo_hookean_nodal,viscoelastic_neo_hookean`` times each law
against neo-Hookean on the paper case, alternating (:mod:`.laws`).

``--full`` also runs the whole paper case (fast settings, seed 0) with
``./softpack run`` and reports its wall time.

``--solids3d [MM,...]`` times 3D steps of examples/cylinders3d_small.toml
at several element sizes (default 6, 4, 3, 2.5 mm) against the number of
tetrahedra, with the fitted exponents (:mod:`.solids3d`, issue 40); with
``--from-state`` a state of examples/paper3d.toml, also the paper's 100
cylinders from it.

``--invariance [--lever NAME:KEY=VALUE,...] [--whole]`` judges the
defaults and each lever against a 9-us reference and issue 41's accuracy
budget (:mod:`softpack.bench.invariance`); exit status 3 when the defaults
miss it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
from pathlib import Path

from softpack.bench.common import RESULTS, WORK


def _parser() -> argparse.ArgumentParser:
    """Command line of ``./softpack bench``."""
    parser = argparse.ArgumentParser(prog="softpack bench",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int,
                        help="time steps per paper-case measurement (default"
                        " 100; --solids3d: 30 per element size)")
    parser.add_argument("--no-scaling", action="store_true",
                        help="skip the 25/100/400-disk scaling runs")
    parser.add_argument("--scaling-phi", type=float, default=0.80,
                        help="packing fraction the scaling runs stop at")
    parser.add_argument("--from-state", type=Path, metavar="FILE",
                        help="also time --steps steps from this state of the"
                        " seed-0 paper case (a run's raw/state.bin); with"
                        " --disks: continue an earlier leg of the same case"
                        " from its state")
    parser.add_argument("--full", action="store_true",
                        help="also run the whole paper case (the defaults)")
    parser.add_argument("--invariance", action="store_true",
                        help="only judge the defaults and each --lever"
                        " against the 9-us reference and the accuracy"
                        " budget, Phi 0.80 -> 0.84 (softpack.bench.invariance)")
    parser.add_argument("--lever", action="append", default=[],
                        metavar="NAME:KEY=VALUE,...",
                        help="with --invariance: a lever to judge, e.g."
                        " f4:time.max_step_factor=4 (repeatable)")
    parser.add_argument("--whole", action="store_true",
                        help="with --invariance: also from the initial"
                        " packing to Phi 0.88")
    parser.add_argument("--fresh", action="store_true",
                        help="with --invariance: rerun the kept runs")
    parser.add_argument("--sharing", action="store_true",
                        help="only time the driver alone, beside a busy"
                        " process and beside another run (issue 18)")
    parser.add_argument("--mpi", action="store_true",
                        help="only time --steps steps of the paper case on 1,"
                        " 2 and 4 MPI ranks (from --from-state if given)")
    parser.add_argument("--mpi-to-phi", type=float, metavar="PHI",
                        help="with --mpi: run from --from-state to this"
                        " packing fraction and compare every output step"
                        " and contact file with the 1-rank run")
    parser.add_argument("--disks", type=int, metavar="N",
                        help="only compact N paper disks from a fresh"
                        " packing and mesh to --disks-phi, timed whole with"
                        " the driver's peak memory (issue 17: 1,000)")
    parser.add_argument("--disks-ranks", type=int, default=1, metavar="R",
                        help="run --disks on R MPI ranks (default 1)")
    parser.add_argument("--disks-phi", type=float, default=0.88,
                        help="packing fraction that ends --disks")
    parser.add_argument("--disks-periodic", action="store_true",
                        help="run --disks in a periodic cell of the box's"
                        " edges compacted isotropically at the piston's rate"
                        " of area change (issue 38)")
    parser.add_argument("--periodic", metavar="N,...",
                        help="only time --steps steps of N paper disks in a"
                        " periodic cell and in the walled box (e.g. 100,400)")
    parser.add_argument("--periodic-shear", metavar="N,...",
                        help="only time --steps steps of N paper disks in a"
                        " stress-controlled periodic cell under simple shear"
                        " (e.g. 100,400): seconds per unit shear strain")
    parser.add_argument("--laws", metavar="LAW,...",
                        help="only time --steps steps of the paper case with"
                        " each law against neo_hookean, alternating"
                        " --law-repeats times (issue 39: at most 1.3x)")
    parser.add_argument("--law-repeats", type=int, default=2, metavar="R",
                        help="with --laws: runs of each law (default 2)")
    parser.add_argument("--solids3d", nargs="?", const="default",
                        metavar="MM,...",
                        help="only time --steps (default here: 30) 3D steps"
                        " of examples/cylinders3d_small.toml, compacted, at"
                        " each element size in mm (default 6,4,3,2.5):"
                        " cost per step against tetrahedra (issue 40); with"
                        " --from-state a state of examples/paper3d.toml: also"
                        " that run's steps from it")
    return parser


def main(argv=None) -> int:
    """Entry point of ``./softpack bench``; returns the exit status."""
    args = _parser().parse_args(argv)
    if args.steps is None:
        args.steps = 30 if args.solids3d else 100
    WORK.mkdir(parents=True, exist_ok=True)
    if args.sharing:
        from softpack.bench.sharing import bench_sharing
        return _save(bench_sharing(WORK), f"sharing-{_stamp()}.json")
    if args.disks:
        from softpack.bench.disks import bench_disks, table
        result = bench_disks(args.disks, args.disks_phi, args.disks_ranks,
                             args.from_state, args.disks_periodic)
        print(table(result))
        ranks = f"r{args.disks_ranks}-" if args.disks_ranks > 1 else ""
        cell = "periodic-" if args.disks_periodic else ""
        return _save(result,
                     f"disks-{args.disks}-{cell}{ranks}{_stamp()}.json")
    if args.periodic or args.periodic_shear:
        return _periodic(args)
    if args.laws:
        from softpack.bench.laws import bench_laws, table
        report = bench_laws(args.laws.split(","), args.steps,
                            args.law_repeats)
        print(table(report))
        return _save_quiet(report, f"laws-{_stamp()}.json")
    if args.mpi:
        from softpack.bench.mpi import bench_mpi, table
        report = bench_mpi(WORK, args.steps, args.from_state,
                           to_phi=args.mpi_to_phi)
        print(table(report))
        return _save(report, f"mpi-{_stamp()}.json")
    if args.invariance:
        return _invariance(args)
    if args.solids3d:
        return _solids3d(args)
    return _default(args)


def _solids3d(args) -> int:
    """``--solids3d [MM,...]``."""
    from softpack.bench.solids3d import SIZES, bench_solids3d, table

    sizes = SIZES
    if args.solids3d != "default":
        try:
            sizes = [float(mm) * 1e-3 for mm in args.solids3d.split(",")]
        except ValueError:
            print("softpack bench: --solids3d takes element sizes in mm"
                  f" separated by commas, e.g. 6,4,3; got {args.solids3d!r}")
            return 2
    report = bench_solids3d(sizes, args.steps,
                            paper3d_state=args.from_state)
    report["date"] = _now()
    print(table(report))
    return _save_quiet(report, f"solids3d-{_stamp()}.json")


def _periodic(args) -> int:
    """``--periodic N,...``."""
    from softpack.bench import periodic

    option, given = (("--periodic-shear", args.periodic_shear)
                     if args.periodic_shear else ("--periodic", args.periodic))
    try:
        counts = [int(n) for n in given.split(",")]
    except ValueError:
        print(f"softpack bench: {option} takes disk counts separated by"
              f" commas, e.g. 100,400; got {given!r}")
        return 2
    if args.periodic_shear:
        report = periodic.bench_periodic_shear(counts, args.steps)
        print(periodic.shear_table(report))
        return _save_quiet(report, f"periodic-shear-{_stamp()}.json")
    report = periodic.bench_periodic(counts, args.steps)
    print(periodic.table(report))
    return _save_quiet(report, f"periodic-{_stamp()}.json")


def _invariance(args) -> int:
    """``--invariance [--lever ...] [--whole] [--fresh]``."""
    from softpack.bench.invariance import bench_invariance, parse_lever, table

    try:
        levers = [parse_lever(text) for text in args.lever]
    except ValueError as e:
        print(f"softpack bench: {e}")
        return 2
    report = bench_invariance(levers, whole=args.whole, fresh=args.fresh)
    print(table(report))
    _save_quiet(report, f"invariance-{_stamp()}.json")
    # Defaults outside the budget: a finding the exit status carries.
    defaults = [report[part]["rows"]["defaults"]
                for part in ("interval", "whole") if part in report]
    return 0 if all(r["within_budget"] for r in defaults) else 3


def _default(args) -> int:
    """The default runs (the module doc's list) and their table."""
    from softpack.bench.common import bench_detection, bench_nlgs
    from softpack.bench.paper import (bench_full, bench_paper, bench_scaling,
                                      table)

    report = {"date": _now(),
              "cores": os.cpu_count(), "nlgs": bench_nlgs(),
              "detection": bench_detection(), "paper": bench_paper(args.steps)}
    if args.from_state:
        report["late_state"] = str(args.from_state)
        report["late"] = bench_paper(args.steps, args.from_state)
    if not args.no_scaling:
        report["scaling"] = bench_scaling(args.scaling_phi)
    if args.full:
        report["full"] = bench_full()
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"bench-{report['date'].replace(':', '')}.json"
    path.write_text(json.dumps(report, indent=2) + "\n")
    print(table(report))
    print(f"\nwritten: {path}")
    return 0


def _now() -> str:
    """The date and time, to the second (ISO 8601)."""
    return datetime.datetime.now().isoformat(timespec="seconds")


def _stamp() -> str:
    """:func:`_now` for a file name (no colons)."""
    return _now().replace(":", "")


def _save(result: dict, name: str) -> int:
    """Write a result under bench/results/ and print it."""
    _save_quiet(result, name)
    print(json.dumps(result, indent=2))
    return 0


def _save_quiet(result: dict, name: str) -> int:
    """Write a result under bench/results/ and name the file."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / name).write_text(json.dumps(result, indent=2) + "\n")
    print(f"\nwritten: {RESULTS / name}")
    return 0
