"""The shape check of issue 13 (softpack.references.plates): one rounded
square and one rounded pentagon between two plates, softpack-simulate
against a static dolfinx computation of the same mesh.

The dolfinx side is first checked on its own against an exact solution (a
homogeneous plane-strain compression of a rectangle, representable exactly
by P1); the comparison with the driver runs on a coarse mesh (h = 2 mm) up
to eps = 0.1 (a few seconds each on one core). The full comparison and the
refinement study are in docs/shapes/README.md.
"""

import math

import numpy as np
import pytest

from driver_required import require_driver
from softpack.references import plates as pl
from softpack.references import plates_reference

MU, LAM = 0.15e6, 0.3e6


def _rectangle(width, height, nx, ny):
    """Structured triangles of [-w/2, w/2] x [-h/2, h/2]."""
    xs = np.linspace(-width / 2, width / 2, nx + 1)
    ys = np.linspace(-height / 2, height / 2, ny + 1)
    points = np.array([[x, y] for y in ys for x in xs])
    cells = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 1, a + nx + 2
            cells += [[a, b, d], [a, d, c]]
    return points, np.array(cells)


def test_boundary_weights_are_half_the_adjacent_edges():
    points, cells = _rectangle(2.0, 1.0, 2, 1)
    nodes, weight = plates_reference.boundary_weights(points, cells)
    assert len(nodes) == 6  # every node of a 2 x 1 grid is on the boundary
    assert weight.sum() == pytest.approx(6.0)  # the perimeter
    corners = np.isin(nodes, [0, 2, 3, 5])
    np.testing.assert_allclose(weight[corners], 1.0)  # (1 + 1) / 2
    np.testing.assert_allclose(weight[~corners], 1.0)  # (1 + 1) / 2


def _homogeneous_force(eps):
    """-P_yy (Pa) and lambda_x of a block compressed
    in y by lambda_y = exp(-eps) with free sides (P_xx = 0), plane strain
    neo-Hookean (paper Eq. 1)."""
    from scipy.optimize import brentq

    ly = math.exp(-eps)
    lx = brentq(lambda lx: MU * (lx**2 - 1) + LAM * math.log(lx * ly),
                1.0, 2.0)
    p_yy = MU * ly - MU / ly + LAM * math.log(lx * ly) / ly
    return -p_yy, lx


def test_dolfinx_reference_is_exact_for_a_homogeneous_compression():
    """A W x H block between frictionless plates deforms homogeneously:
    f = -P_yy(lambda) W exactly, up to the penalty's penetration
    (k = 1e5 mu / D: measured relative error -1.2e-4 at eps = 0.05 to
    -1.7e-4 at eps = 0.2, proportional to 1/k), and the pinned node
    carries no force (measured 4.5e-16 f); the plates carry the same force
    (measured 3.5e-12 apart), the penetration measured 6.6e-6 D (all
    2026-12-03)."""
    pytest.importorskip("dolfinx")
    width, height = 0.016, 0.010
    points, cells = _rectangle(width, height, 8, 5)
    ref = plates_reference.static_reference(points, cells, MU, LAM, -height / 2,
                              height / 2, 0.02, 0.2, n_steps=4)
    for eps, f_norm in zip(ref["eps"][1:], ref["f_norm"][1:]):
        exact = _homogeneous_force(eps)[0] * width / (height * MU)
        assert f_norm == pytest.approx(exact, rel=3e-4)
    np.testing.assert_allclose(ref["f_norm_top"], ref["f_norm_bottom"],
                               rtol=4e-11)
    assert ref["pin_reaction_over_f"][1:].max() < 5e-15
    assert 0 < ref["max_penetration_over_D"].max() < 1e-5


def test_config_is_the_single_disk_protocol_with_a_polygon(registry):
    p = pl.Params(shape="square")
    config = pl.plates_config(p, -0.009, 0.009)
    (species,) = config["species"]
    assert (species["shape"], species["sides"], species["orientation"]) == (
        "polygon", 4, "fixed")
    assert species["angle"] == pytest.approx(math.pi / 4)  # faces on plates
    assert species["corner_radius"] == p.corner_radius
    assert config["box"]["enabled"] is False
    assert config["contact"]["friction"] == 0.01
    approach = 2 * p.speed * config["stop"]["max_time"]
    assert approach >= 0.018 * (1 - math.exp(-p.max_strain))
    assert pl.plates_config(pl.Params())["species"][0]["angle"] == 0.0


@pytest.mark.parametrize("shape", ["square", "pentagon"])
def test_softpack_and_dolfinx_agree_within_1_percent(shape, tmp_path):
    """Coarse mesh (h = 2 mm), up to eps = 0.1: softpack's force within 1 %
    of the static dolfinx one from eps = 0.02 on, the body barely turns,
    the dolfinx penalty's penetration is negligible. Measured 2026-12-03
    (as docs/shapes/README.md reports): largest difference from eps = 0.02
    0.32 % (square), 0.33 % (pentagon); rotation 1.7e-4, 8.0e-4 rad;
    penetration 4.6e-6, 1.2e-5 D."""
    require_driver()
    pytest.importorskip("dolfinx")
    params = pl.Params(shape=shape, element_size=2e-3, max_strain=0.1,
                       reference_steps=10)
    assert pl.main([f"--{k.replace('_', '-')}={v}" for k, v in
                    (("shape", shape), ("element_size", 2e-3),
                     ("max_strain", 0.1), ("reference_steps", 10))]
                   + ["--out", str(tmp_path)]) == 0
    import json

    doc = json.loads((tmp_path / "plates.json").read_text())
    assert doc["params"]["shape"] == params.shape
    assert doc["comparison"]["max_abs_relative_difference_from_0.02"] < 0.01
    assert doc["softpack"]["max_rigid_rotation_rad"] < 8e-3
    assert doc["dolfinx"]["max_penetration_over_D"] < 1e-4
    force = np.genfromtxt(tmp_path / "force_dolfinx.csv", delimiter=",",
                          names=True)
    assert np.all(np.diff(force["f_norm"]) > 0)
