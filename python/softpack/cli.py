"""Dispatch of ``./softpack`` subcommands implemented in Python.

Each subcommand lives in its own module exposing ``main(argv) -> int``; this
file only maps names to modules so that importing one subcommand never pulls
in the heavy dependencies (dolfinx, gmsh, matplotlib) of another.
"""

import importlib
import sys

COMMANDS = {
    "run": "softpack.simulation.run",
    "mesh": "softpack.scene.mesh",
    "single-disk": "softpack.references.single_disk",
    "plot-single-disk": "softpack.plots.single_disk",
    "plot": "softpack.plots.paper",
    "bench": "softpack.bench",
}


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] not in COMMANDS:
        print(f"softpack: expected one of {', '.join(COMMANDS)}", file=sys.stderr)
        return 2
    name, rest = argv[0], argv[1:]
    return importlib.import_module(COMMANDS[name]).main(rest)


if __name__ == "__main__":
    sys.exit(main())
