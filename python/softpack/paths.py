"""Where softpack's files are: the repository, the build, its executables.

The one place that knows the layout; everything else imports these.
``./softpack`` sets ``SOFTPACK_ROOT`` and ``SOFTPACK_BIN``; without them
(``import softpack`` from a checkout) the repository is this file's and the
build is ``ROOT/build``.
"""

from __future__ import annotations

import os
from pathlib import Path

#: The repository (examples/, schema/, forms/, ...).
ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
#: The build's executables (softpack-simulate, softpack-fclib, ...).
BIN = Path(os.environ.get("SOFTPACK_BIN") or ROOT / "build" / "bin")
#: The build directory (generated registry: forms/materials.json).
BUILD = BIN.parent
#: The parameter schema (docs/contract.md).
SCHEMA = ROOT / "schema" / "parameters.toml"
#: The material registry written by the build from forms/materials/.
MATERIALS = BUILD / "forms" / "materials.json"
#: The gmsh geometry of particle shapes.
MESHES = ROOT / "meshes"


def executable(name: str) -> Path:
    """``BIN/name``; raises FileNotFoundError saying how to build it."""
    exe = BIN / name
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        raise FileNotFoundError(f"{exe} not found: build it with ./softpack"
                                " build (or set SOFTPACK_BIN)")
    return exe
