"""pytest set-up for softpack's Python tests, and their shared fixtures.

``./softpack test`` sets ``PYTHONPATH`` and ``SOFTPACK_ROOT``; when run
directly with pytest, the package is found under the repository's
``python/`` folder.

Fixtures: ``registry`` (the material registry, the build's or a stand-in:
material_registry.py; a module that needs it in every test says
``pytestmark = pytest.mark.usefixtures("registry")``), ``fake_bin`` (the
fake driver of fake_driver.py as the build's) and ``fake_mesh`` (a body
table instead of the dolfinx mesh).
"""

import math
import os
import sys
from pathlib import Path

import pytest

#: Skips fail ./softpack test unless allowed (strict_skips.py).
pytest_plugins = ["strict_skips"]

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
if str(ROOT / "python") not in sys.path:
    sys.path.insert(0, str(ROOT / "python"))


@pytest.fixture
def registry(tmp_path_factory, monkeypatch):
    """The material registry's path (material_registry.use_registry)."""
    from material_registry import use_registry

    return use_registry(tmp_path_factory, monkeypatch)


@pytest.fixture
def fake_bin(tmp_path, monkeypatch):
    """A directory with the fake driver, as SOFTPACK_BIN; fast polling."""
    from fake_driver import FAKE_DRIVER
    from softpack import paths
    from softpack.simulation import driver

    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    exe = bin_dir / "softpack-simulate"
    exe.write_text(FAKE_DRIVER)
    exe.chmod(0o755)
    monkeypatch.setattr(paths, "BIN", bin_dir)
    monkeypatch.setattr(driver, "POLL_SECONDS", 0.02)
    return bin_dir


@pytest.fixture
def fake_mesh(monkeypatch):
    """Replace the dolfinx mesh by a body table (the driver is fake)."""
    from softpack.scene.mesh import MeshInfo, output_paths

    def mesh_particles(bodies, centres, angles, out_stem):
        xdmf, h5, table = output_paths(out_stem)
        table.parent.mkdir(parents=True, exist_ok=True)
        radii = [b.bounding_radius for b in bodies]
        areas = [math.pi * r * r for r in radii]
        table.write_text("body,x,y,radius,reference_area,angle\n" + "".join(
            f"{i},{c[0]!r},{c[1]!r},{r!r},{a!r},0.0\n"
            for i, (c, r, a) in enumerate(zip(centres, radii, areas))))
        return MeshInfo(xdmf, h5, table, (1,) * len(radii),
                        (3,) * len(radii), tuple(areas))
    monkeypatch.setattr("softpack.scene.build.mesh_particles", mesh_particles)
