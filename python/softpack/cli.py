"""Dispatch of ``./softpack`` subcommands implemented in Python.

Each subcommand lives in its own module exposing ``main(argv) -> int``; this
file only maps names to modules so that importing one subcommand never pulls
in the heavy dependencies (dolfinx, gmsh, matplotlib) of another. It also
holds the argparse value types the subcommands share, so that an ordinary
mistake (``--time-step 0``) is one line naming the option and exit status 2,
never a traceback.
"""

import argparse
import importlib
import math
import sys

COMMANDS = {
    "run": "softpack.simulation.run",
    "mesh": "softpack.scene.mesh",
    "single-disk": "softpack.references.single_disk",
    "adhesion": "softpack.references.adhesion",
    "viscoelastic-disk": "softpack.references.viscoelastic_disk",
    "plot-single-disk": "softpack.plots.single_disk",
    "plot": "softpack.plots.paper",
    "plot-loading": "softpack.plots.loading",
    "plot-shear": "softpack.plots.shear",
    "plot-plane-strain": "softpack.plots.plane_strain",
    "bench": "softpack.bench",
    "reference3d": "softpack.references.cylinder3d",
    "reference2d": "softpack.references.disk_mixed",
    "reference-sphere": "softpack.references.sphere_axisym",
}


def _number(kind, text, low, strict):
    """``text`` as a finite ``kind`` above ``low`` (argparse type)."""
    try:
        value = kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not {'an integer' if kind is int else 'a number'}"
        ) from None
    if not math.isfinite(value) or value < low or (strict and value == low):
        raise argparse.ArgumentTypeError(
            f"must be {'>' if strict else '>='} {low:g}, not {text}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    return _number(float, text, 0.0, True)


def nonnegative_float(text: str) -> float:
    """argparse type: a finite number >= 0."""
    return _number(float, text, 0.0, False)


def positive_int(text: str) -> int:
    """argparse type: an integer > 0."""
    return _number(int, text, 0, True)


def main(argv=None):
    """Run the subcommand ``argv[0]`` with the rest; its exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] not in COMMANDS:
        print(f"softpack: expected one of {', '.join(COMMANDS)}", file=sys.stderr)
        return 2
    name, rest = argv[0], argv[1:]
    return importlib.import_module(COMMANDS[name]).main(rest)


if __name__ == "__main__":
    sys.exit(main())
