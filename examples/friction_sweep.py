"""A friction sweep on the CI-sized case with softpack's Python API.

Three compactions of examples/small.toml (14 disks, about 10 s each on one
core) at mu_f = 0, 0.3 and 0.6, the same packing (seed 0); prints the final
Phi, strain, active contacts and stored energy of each and draws the
paper's figures of the three runs (14 disks are too few for Z: its rules
leave no balanced particle, so Z is NaN here). Usage, from anywhere once
``./softpack build`` has run (OUT: default runs/friction_sweep)::

    /usr/bin/python3 examples/friction_sweep.py [OUT]

See docs/python_api.md.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    import softpack
except ImportError:  # not on the path: use this checkout's package
    sys.path.insert(0, str(HERE.parent / "python"))
    import softpack

FRICTIONS = (0.0, 0.3, 0.6)


def main(out: Path) -> int:
    """Run the sweep into ``out/mu<friction>``; draw into ``out/figures``."""
    runs = []
    print(f"{'mu_f':>5} {'steps':>6} {'Phi':>7} {'eps':>7} {'contacts':>8}"
          f" {'E (J/m)':>10}")
    for mu in FRICTIONS:
        config = softpack.load_config(HERE / "small.toml",
                                      {"contact.friction": mu})
        directory = out / f"mu{mu:g}"
        # force: a second run of the script replaces its own runs
        series = softpack.run(config, directory, force=True)
        runs.append(directory)
        last = {name: series[name][len(series["phi"]) - 1]
                for name in ("step", "phi", "eps", "active_contacts",
                             "strain_energy")}
        print(f"{mu:5.2f} {int(last['step']):6d} {last['phi']:7.4f}"
              f" {last['eps']:7.4f} {int(last['active_contacts']):8d}"
              f" {last['strain_energy']:10.4g}")
    figures = softpack.plot_runs(runs, out / "figures")
    print(f"figures: {', '.join(p.name for p in figures)} in"
          f" {out / 'figures'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1]) if len(sys.argv) > 1
                  else Path("runs/friction_sweep")))
