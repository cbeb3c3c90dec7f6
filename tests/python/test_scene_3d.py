"""3D scenes (issue 40): the configuration, its refusals, the placement of
standing cylinders and spheres, and the two packing fractions of 3D
(softpack.analysis.solids) against hand-computed cases."""

import math

import numpy as np
import pytest

from softpack.analysis import solids as fractions
from softpack.scene.build import build_scene, check_user_shapes
from softpack.scene.config import ConfigError, validate
from softpack.scene.packing import scene_packing
from softpack.scene.shapes import ShapeError
from softpack.scene.solid_scene import place_solids
from softpack.scene.solids import signed_volumes
from softpack.scene.species import particle_table


def cylinders(**changes) -> dict:
    """The small 3D scene of standing cylinders (examples'), as TOML data."""
    data = {
        "model": {"dimension": 3, "thickness": 0.015},
        "box": {"length": 0.110, "width": 0.078, "height": 0.020},
        "species": [{"name": "small", "shape": "cylinder",
                     "diameter": 0.02, "count": 10},
                    {"name": "large", "shape": "cylinder",
                     "diameter": 0.03, "count": 4}],
        "mesh": {"element_size": 0.005},
        "material": {"parameters": {"shear_modulus": 0.15e6,
                                    "lame_lambda": 7.35e6}},
        "stop": {"packing_fraction": 0.6, "max_time": 0.06},
    }
    for key, value in changes.items():
        section, _, name = key.partition(".")
        if name:
            data.setdefault(section, {})[name] = value
        else:
            data[section] = value
    return data


def refused(data, *words):
    """The configuration is refused naming the file and every word."""
    with pytest.raises(ConfigError) as err:
        validate(data, "scene3d.toml")
    for word in ("scene3d.toml", *words):
        assert word in str(err.value), str(err.value)
    return str(err.value)


def test_a_3d_scene_of_standing_cylinders_is_valid():
    config = validate(cylinders(), "scene3d.toml")
    assert config["model"]["dimension"] == 3
    assert config["box"]["height"] == 0.020


@pytest.mark.parametrize("dimension, shape, other", [
    (3, "disk", "2D"), (3, "polygon", "2D"), (3, "geo", "2D"),
    (2, "sphere", "3D"), (2, "cylinder", "3D"), (2, "ellipsoid", "3D")])
def test_a_shape_of_the_other_dimension_is_refused(dimension, shape, other):
    data = cylinders(**{"model.dimension": dimension})
    data["species"][1]["shape"] = shape
    if dimension == 2:
        data["box"].pop("height")
        data["species"][0]["shape"] = "disk"
    message = refused(data, "[species.1] shape", shape,
                      f"a {other} shape in a {dimension}D scene")
    assert "allowed:" in message


def test_the_box_height_belongs_to_3d():
    data = cylinders(**{"model.dimension": 2})
    data["species"] = [{"shape": "disk", "diameter": 0.02, "count": 3}]
    refused(data, "[box] height", "[model] dimension = 3")
    data = cylinders()
    data["box"].pop("height")
    refused(data, "[box] height", "must be > 0 in 3D")


def test_a_body_larger_than_the_box_is_refused():
    refused(cylinders(**{"model.thickness": 0.0201}), "[species.0]",
            "[model] thickness", "[box] height")
    data = cylinders()
    data["species"][1]["diameter"] = 0.08
    refused(data, "[species.1]", "diameter", "larger than the box")
    data = cylinders()
    data["species"] = [{"shape": "sphere", "diameter": 0.0199, "count": 1}]
    refused(data, "[species.0]", "larger than the box")  # height 0.02
    data["species"] = [{"shape": "ellipsoid", "diameter": 0.012,
                        "aspect_ratio": 3.0, "count": 1}]
    # its long axis 0.012 x 3^(2/3) = 0.025 > the box's 0.020 height
    refused(data, "[species.0]", "larger than the box")


def test_what_3d_does_not_have_yet_is_refused():
    data = cylinders()
    data["species"][1]["shape"] = "sphere"
    refused(data, "cylinders", "do not mix", "sphere")
    refused(cylinders(material={"law": "viscoelastic_neo_hookean"}),
            "[material] law", "viscoelastic_neo_hookean", "plane strain only")
    data = cylinders()
    data["walls"] = {"plate": {"point": [0.0, 0.05], "normal": [0.0, -1.0]}}
    refused(data, "[walls.plate]", "box's walls only")
    refused(cylinders(**{"box.enabled": False, "stop.packing_fraction": 0.0}),
            "[box] enabled")


def test_a_3d_scene_takes_rigid_species():
    data = cylinders()
    data["species"][1]["material"] = "hard"
    data["materials"] = {"hard": {"rigid": True, "density": 2500.0}}
    config = validate(data, "scene3d.toml")
    assert config["materials"]["hard"]["rigid"] is True


def test_a_box_too_full_is_refused():
    data = cylinders(**{"stop.packing_fraction": 0.4})
    # pi/4 (10 x 20^2 + 4 x 30^2) 15 mm^3 / (110 x 78 x 20 mm^3) = 0.522
    refused(data, "fill 0.522", "[stop] packing_fraction")


def write_msh(path, points, tets):
    import meshio
    meshio.write(path, meshio.Mesh(points, [("tetra", np.asarray(tets))]),
                 file_format="gmsh22", binary=False)


def cube_tetrahedra(edge=1.0, origin=(0.0, 0.0, 0.0)):
    """A cube cut into six positively oriented tetrahedra (Kuhn's: each
    a path from corner 0 to corner 7 along the axes in one order)."""
    corners = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1]
                        for i in range(8)], dtype=float) * edge + origin
    tets = []
    for order in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1),
                  (2, 1, 0)):
        path, node = [0], 0
        for axis in order:
            node += 1 << axis
            path.append(node)
        tets.append(path)
    tets = np.array(tets)
    flip = signed_volumes(corners, tets) < 0
    tets[flip] = tets[flip][:, [0, 1, 3, 2]]
    return corners, tets


@pytest.mark.parametrize("defect, words", [
    ("inverted", "1 of 6 tetrahedra are inverted"),
    ("degenerate", "degenerate")])
def test_a_user_solid_with_bad_tetrahedra_is_refused(tmp_path, defect,
                                                     words):
    points, tets = cube_tetrahedra(0.01)
    if defect == "inverted":
        tets[2] = tets[2][[0, 1, 3, 2]]
    else:
        points = np.vstack([points, points[0] + [0.001, 0.0, 0.0],
                            points[0] + [0.002, 0.0, 0.0]])
        tets = np.vstack([tets, [0, 8, 9, 1]])  # four nodes on one line
    write_msh(tmp_path / "solid.msh", points, tets)
    data = cylinders(**{"mesh.element_size": 0.001})
    data["species"] = [{"shape": "msh", "file": str(tmp_path / "solid.msh"),
                        "diameter": 0.01, "count": 2}]
    with pytest.raises(ShapeError) as err:
        check_user_shapes(validate(data, "scene3d.toml"))
    for word in ("[species.0]", "solid.msh", words):
        assert word in str(err.value)


def test_a_user_solid_is_scaled_to_its_equal_volume_diameter(tmp_path):
    points, tets = cube_tetrahedra(1.0)
    write_msh(tmp_path / "cube.msh", points, tets)
    data = cylinders(**{"mesh.element_size": 0.001})
    data["species"] = [{"shape": "msh", "file": str(tmp_path / "cube.msh"),
                        "diameter": 0.01, "count": 2}]
    template, = check_user_shapes(validate(data, "scene3d.toml")).values()
    assert template.volume == pytest.approx(math.pi * 0.01**3 / 6, rel=1e-12)
    # a cube of that volume, centred: its corners at half its edge
    half = (math.pi / 6) ** (1 / 3) * 0.01 / 2
    assert np.abs(template.points).max() == pytest.approx(half, rel=1e-12)


def test_standing_cylinders_are_placed_as_the_2d_disks_of_the_same_seed():
    config = validate(cylinders(), "scene3d.toml")
    diameters, index = particle_table(config["species"], 0)
    centres = place_solids(config, None, diameters, index)
    flat = cylinders(**{"model.dimension": 2, "stop.packing_fraction": 0.8})
    flat["box"].pop("height")
    for spec in flat["species"]:
        spec["shape"] = "disk"
    disks = scene_packing(validate(flat, "flat.toml"), diameters / 2)
    assert np.array_equal(centres[:, :2], disks.centres)
    assert np.all(centres[:, 2] == 0.0075)  # bottom faces on z = 0


def two_cubes(lift):
    """A cube of 10 mm on the base and one of 20 mm lifted by ``lift``."""
    a, ta = cube_tetrahedra(0.01, (0.0, 0.0, 0.0))
    b, tb = cube_tetrahedra(0.02, (0.02, 0.01, lift))
    return (np.vstack([a, b]), np.vstack([ta, tb + len(a)]),
            np.repeat([0, 1], 6))


def test_volume_and_base_fractions_of_two_cubes_by_hand():
    extent = (0.05, 0.04, 0.03)  # L W H_box: 6e-5 m^3, base 2e-3 m^2
    points, tets, body = two_cubes(0.005)
    assert np.allclose(fractions.body_volumes(points, tets, body),
                       [1e-6, 8e-6], rtol=1e-12)
    assert fractions.volume_fraction(points, tets, body, extent) \
        == pytest.approx(9e-6 / 6e-5, rel=1e-12)  # 0.15
    # only the first cube stands on the base: 1e-4 m^2 of 2e-3
    assert fractions.base_area_fraction(points, tets, body, extent) \
        == pytest.approx(0.05, rel=1e-12)
    points, tets, body = two_cubes(5e-10)  # within BASE_TOLERANCE
    assert fractions.base_area_fraction(points, tets, body, extent) \
        == pytest.approx(5e-4 / 2e-3, rel=1e-12)
    faces = fractions.boundary_faces(tets)
    assert len(faces) == 24  # six faces of two triangles, per cube


def test_a_scene_of_standing_cylinders(tmp_path):
    config = validate(cylinders(**{"mesh.element_size": 0.006,
                                    "contact.max_penetration": 0.003}),
                      "scene3d.toml")
    scene = build_scene(config, tmp_path / "packing")
    points, tets, body = fractions.read_scene_mesh(scene.mesh.xdmf)
    assert body.max() == 13 and np.all(signed_volumes(points, tets) > 0)
    diameters, _ = particle_table(config["species"], 0)
    for b in range(14):
        x = points[np.unique(tets[body == b])]
        assert x[:, 2].min() == pytest.approx(0.0, abs=1e-15)
        assert x[:, 2].max() == pytest.approx(0.015, abs=1e-15)
        # every node within D/2 of the axis the placement put at the centre
        r = np.hypot(*(x[:, :2] - scene.packing.centres[b, :2]).T)
        assert r.max() == pytest.approx(diameters[b] / 2, rel=1e-12)
    extent = scene.packing.extent
    disks = math.pi * (10 * 0.01**2 + 4 * 0.015**2)
    base = fractions.base_area_fraction(points, tets, body, extent)
    # the meshed end faces are polygons inscribed in the circles: at 6 mm
    # at least 11 sides on the small ones, n sin(2 pi / n) / (2 pi) > 0.946
    assert 0.946 * disks / (0.110 * 0.078) < base < disks / (0.110 * 0.078)
    assert fractions.volume_fraction(points, tets, body, extent) \
        == pytest.approx(base * 0.015 / 0.020, rel=1e-12)
    assert scene.packing.packing_fraction == pytest.approx(
        base * 0.015 / 0.020, rel=1e-12)


def test_a_spheroid_has_the_volume_of_its_equal_volume_sphere():
    from softpack.scene.solids import solid_tetrahedra, spheroid_axes

    points, tets = solid_tetrahedra("ellipsoid", 0.002, 0.015, 2.0)
    a, b = spheroid_axes(2.0, 0.015)
    assert a / b == pytest.approx(2.0, rel=1e-12)
    assert a * b * b == pytest.approx(0.0075**3, rel=1e-12)
    # its nodes on the spheroid: the extents within it, the poles on z
    # (gmsh's sphere's, dilated) at 2 b
    extent = (points.max(axis=0) - points.min(axis=0)) / [2 * a, 2 * b, 2 * b]
    assert np.all(extent <= 1 + 1e-9) and np.all(extent > 0.98)
    assert extent[2] == pytest.approx(1.0, rel=1e-9)
    # the meshed solid is inscribed: its volume below the spheroid's, by
    # less than the 2 mm elements' chords take off (measured 0.973)
    volume = signed_volumes(points, tets).sum() / (math.pi * 0.015**3 / 6)
    assert 0.95 < volume < 1.0


def test_spheres_are_placed_clear_of_each_other_and_of_the_box(tmp_path):
    data = cylinders(**{"mesh.element_size": 0.004,
                        "contact.max_penetration": 0.002,
                        "stop.packing_fraction": 0.5})
    data["box"] = {"length": 0.08, "width": 0.06, "height": 0.06}
    data["species"] = [{"shape": "sphere", "diameter": 0.02, "count": 20}]
    scene = build_scene(validate(data, "scene3d.toml"), tmp_path / "s")
    points, tets, body = fractions.read_scene_mesh(scene.mesh.xdmf)
    gap = 1e-4  # [packing] gap's default
    assert np.all(points >= gap) and np.all(points <= np.array(
        [0.08, 0.06, 0.06]) - gap)
    centres = scene.packing.centres
    distance = np.linalg.norm(centres[:, None] - centres[None], axis=2)
    np.fill_diagonal(distance, np.inf)
    assert distance.min() >= 0.02 + gap
    assert fractions.base_area_fraction(points, tets, body,
                                        scene.packing.extent) == 0.0


def test_a_solid_in_a_2d_scene_is_refused(tmp_path):
    points, tets = cube_tetrahedra(0.01)
    write_msh(tmp_path / "cube.msh", points, tets)
    data = {"species": [{"shape": "msh", "file": str(tmp_path / "cube.msh"),
                         "diameter": 0.02, "count": 2}],
            "box": {"length": 0.1, "width": 0.1}, "stop": {"max_time": 0.1}}
    with pytest.raises(ShapeError) as err:
        check_user_shapes(validate(data, "flat.toml"))
    for word in ("[species.0]", "cube.msh", "a 3D solid (tetrahedra) in a 2D"
                 " scene"):
        assert word in str(err.value)


def test_friction_may_name_the_base_and_lid_of_a_3d_box_only():
    """A 3D box's base and lid are walls of [[friction]] (the experiment's
    lubricated base); a 2D scene has no such walls."""
    pair = [{"species": "small", "against": "base", "coefficient": 0.0},
            {"species": "large", "against": "lid", "coefficient": 0.0}]
    config = validate(cylinders(friction=pair), "scene3d.toml")
    assert [p["against"] for p in config["friction"]] == ["base", "lid"]
    flat = cylinders(friction=pair[:1])
    flat["model"] = {"dimension": 2}
    flat["species"] = [{"name": "small", "diameter": 0.02, "count": 10}]
    del flat["box"]["height"]
    refused(flat, "against = 'base'", "not a species")


def test_a_base_area_fraction_stop_needs_standing_cylinders():
    """[stop] base_area_fraction (phi_base, the bottom faces' area
    fraction) is refused in 2D and for solids that stand on no face."""
    data = cylinders(**{"model.dimension": 2, "box.height": 0.0,
                        "stop.base_area_fraction": 0.8})
    data["species"] = [{"shape": "disk", "diameter": 0.02, "count": 3}]
    refused(data, "[stop] base_area_fraction", "3D measure")
    data = cylinders(**{"stop.base_area_fraction": 0.8})
    data["species"] = [{"shape": "sphere", "diameter": 0.015, "count": 2}]
    refused(data, "[stop] base_area_fraction", "standing cylinders only")
    validate(cylinders(**{"stop.base_area_fraction": 0.8,
                          "stop.packing_fraction": 0.0}), "scene3d.toml")


def test_the_base_held_is_refused_in_2d():
    """contact.nlgs_condensation = "on" holds frictionless sets in 3D only;
    a 2D scene is refused before the run, "auto" is off there."""
    data = cylinders(**{"model.dimension": 2, "box.height": 0.0,
                        "contact.nlgs_condensation": "on"})
    data["species"] = [{"shape": "disk", "diameter": 0.02, "count": 3}]
    refused(data, "[contact] nlgs_condensation", "3D only")
    data["contact"]["nlgs_condensation"] = "auto"
    assert validate(data, "scene3d.toml")["model"]["dimension"] == 2
    held = validate(cylinders(**{"contact.nlgs_condensation": "on"}),
                    "scene3d.toml")
    assert held["contact"]["nlgs_condensation"] == "on"
