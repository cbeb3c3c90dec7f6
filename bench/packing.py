"""Time the scene stage for N paper-like particles: pack and mesh.

    SOFTPACK_ROOT=. PYTHONPATH=python /usr/bin/python3 bench/packing.py \
        [--count 1000] [--shape disk|polygon|ellipse] [--out DIR]

The paper's species (70 % D = 20 mm, 30 % D = 30 mm, element size
1.065 mm) in the paper's box scaled by sqrt(N / 100), so that the initial
packing fraction is the paper's 0.748 for disks (for other shapes the box is
scaled further so that their bounding circles fill 0.748). Prints the
seconds spent meshing the shapes (gmsh, once per shape and size), placing
them (scene.packing) and writing the one mesh (XDMF + HDF5).
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np

from softpack.scene import shapes
from softpack.scene.mesh import PAPER_ELEMENT_SIZE, mesh_particles
from softpack.scene.placement import place
from softpack.scene.packing import DEFAULT_GAP, PAPER_LENGTH, PAPER_WIDTH


def bench(count=1000, shape="disk", out=None, seed=0) -> dict:
    """Seconds of each part of the scene stage; see the module doc."""
    small = int(round(0.7 * count))
    species = [dict(name=n, shape=shape, diameter=d, count=c, sides=5,
                    corner_radius=2e-3, aspect_ratio=1.5, file="")
               for n, d, c in (("small", 0.02, small),
                               ("large", 0.03, count - small))]
    diameters = np.repeat([0.02, 0.03], [small, count - small])
    index = np.repeat([0, 1], [small, count - small])
    seconds = {}
    start = time.perf_counter()
    meshes = shapes.templates(species, diameters, index, PAPER_ELEMENT_SIZE)
    bodies = [meshes[shapes.shape_key(species[s], d)]
              for d, s in zip(diameters, index)]
    seconds["shapes (gmsh)"] = time.perf_counter() - start
    radii = np.array([b.bounding_radius for b in bodies])
    scale = math.sqrt(np.sum(radii**2) / (100 * (0.7 * 0.01**2
                                                 + 0.3 * 0.015**2)))
    length, width = PAPER_LENGTH * scale, PAPER_WIDTH * scale
    start = time.perf_counter()
    centres = place(radii, (length, width), DEFAULT_GAP,
                    np.random.default_rng(seed))
    seconds["packing"] = time.perf_counter() - start
    angles = np.random.default_rng(seed).uniform(0, 2 * math.pi, count)
    with tempfile.TemporaryDirectory() as tmp:
        stem = Path(out or tmp) / "bench"
        start = time.perf_counter()
        info = mesh_particles(bodies, centres, angles, stem)
        seconds["mesh (XDMF + HDF5)"] = time.perf_counter() - start
    seconds["triangles"] = info.n_triangles
    return seconds


def main(argv=None) -> int:
    """Command line: print the seconds of each part."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--shape", default="disk",
                        choices=["disk", "polygon", "ellipse"])
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    result = bench(args.count, args.shape, args.out)
    total = sum(v for k, v in result.items() if k != "triangles")
    for key, value in result.items():
        print(f"{key:24s} {value:10.2f}" if key != "triangles"
              else f"{key:24s} {value:10d}")
    print(f"{'total (s)':24s} {total:10.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
