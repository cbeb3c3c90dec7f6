"""Disk meshes: element counts, body tags, areas, orientation, atomic output."""

import dolfinx.io
import dolfinx.mesh
import numpy as np
import pytest
from mpi4py import MPI

import softpack.scene.mesh as mesh_module
from softpack import paths
from softpack.scene import shapes, triangulation
from softpack.scene.mesh import (PAPER_ELEMENT_SIZE, mesh_disks, output_paths,
                                 read_bodies)
from softpack.scene.triangulation import signed_areas
from softpack.scene.packing import Packing, random_packing

H = PAPER_ELEMENT_SIZE


def read_back(xdmf):
    """The mesh and 'bodies' tags as the driver reads them."""
    with dolfinx.io.XDMFFile(MPI.COMM_SELF, str(xdmf), "r") as f:
        mesh = f.read_mesh(name="mesh")
        mesh.topology.create_connectivity(2, 0)
        tags = f.read_meshtags(mesh, name="bodies")
    return mesh, tags


def cell_coordinates(mesh):
    """Vertex coordinates of each cell, shape (cells, 3, 2)."""
    dofs = mesh.geometry.dofmap.array.reshape(-1, 3)
    return mesh.geometry.x[dofs][:, :, :2], dofs


@pytest.fixture(scope="module")
def paper_pair(tmp_path_factory):
    """One disk of each of the paper's diameters at the paper's h."""
    stem = tmp_path_factory.mktemp("pair") / "pair"
    centres, radii = [(0.02, 0.02), (0.06, 0.03)], [0.010, 0.015]
    return mesh_disks(centres, radii, H, stem), np.array(centres), radii


@pytest.fixture(scope="module")
def small_packing(tmp_path_factory):
    """A 12-disk packing meshed at the paper's h, read back from file."""
    packing = random_packing(7, counts=(8, 4), length=0.12, width=0.10)
    info = mesh_disks(packing.centres, packing.radii, H,
                      tmp_path_factory.mktemp("packing") / "small")
    return packing, info, read_back(info.xdmf)


def test_paper_element_counts(paper_pair):
    info, _, _ = paper_pair
    small, large = info.triangles_per_body
    assert abs(small - 670) <= 0.1 * 670
    assert abs(large - 1506) <= 0.1 * 1506
    assert info.n_triangles == small + large


def test_tags_follow_bodies_through_reordering(small_packing):
    packing, info, (mesh, tags) = small_packing
    xy, _ = cell_coordinates(mesh)
    n_cells = len(xy)
    assert np.array_equal(np.sort(tags.indices), np.arange(n_cells))
    body = np.empty(n_cells, dtype=int)
    body[tags.indices] = tags.values
    assert np.array_equal(np.bincount(body), info.triangles_per_body)
    centroid = xy.mean(axis=1)
    distance = np.linalg.norm(centroid - packing.centres[body], axis=1)
    assert np.all(distance < packing.radii[body])


def test_tags_follow_cells_given_out_of_order(tmp_path):
    """Interleaved input cells make dolfinx permute bodies, not only cells,
    when it reads the file: the tags must follow."""
    points, triangles = mesh_module.disk_triangulation([0.01], 3e-3)[0.01]
    centres = np.array([(0.0, 0.0), (0.05, 0.0)])
    x = np.vstack([points + centres[0], points + centres[1]])
    cells = np.vstack([triangles, triangles + len(points)])
    body = np.repeat([0, 1], len(triangles))
    order = np.arange(len(cells)).reshape(2, -1).T.ravel()  # 0, n, 1, n+1..
    mesh_module._write_xdmf(tmp_path / "m.xdmf", x, cells[order], body[order])
    mesh, tags = read_back(tmp_path / "m.xdmf")
    xy, _ = cell_coordinates(mesh)
    tag = np.empty(len(xy), dtype=int)
    tag[tags.indices] = tags.values
    original = np.asarray(mesh.topology.original_cell_index)
    assert np.any(body[order][original] != body[order])  # dolfinx permuted
    nearest = np.argmin(np.linalg.norm(
        xy.mean(axis=1)[:, None] - centres[None], axis=2), axis=1)
    assert np.array_equal(tag, nearest)


def test_areas_close_to_disks(small_packing):
    packing, info, (mesh, tags) = small_packing
    xy, _ = cell_coordinates(mesh)
    area = np.abs(signed_areas(xy.reshape(-1, 2),
                               np.arange(3 * len(xy)).reshape(-1, 3)))
    per_body = np.zeros(packing.n_particles)
    np.add.at(per_body, tags.values, area[tags.indices])
    # The polygon is inscribed: each boundary chord s <= 1.2 h cuts off a
    # segment of area ~ s^3 / (12 r), so 0 < pi r^2 - A < pi (1.2 h)^2 / 6.
    deficit = np.pi * packing.radii**2 - per_body
    assert np.all(deficit > 0)
    assert np.all(deficit < np.pi * (1.2 * H)**2 / 6)
    table = read_bodies(info.bodies_csv)
    assert np.allclose(table["reference_area"], per_body, rtol=1e-12)
    assert np.allclose(info.reference_areas, per_body, rtol=1e-12)


def test_bodies_table(small_packing):
    packing, info, _ = small_packing
    table = read_bodies(info.bodies_csv)
    assert info.bodies_csv.read_text().startswith(
        "body,x,y,radius,reference_area,angle\n")
    assert np.array_equal(table["body"], np.arange(packing.n_particles))
    assert np.array_equal(table["radius"], packing.radii)
    assert np.array_equal(np.stack([table["x"], table["y"]], 1),
                          packing.centres)


def test_cells_counter_clockwise(small_packing):
    _, _, (mesh, _) = small_packing
    xy, _ = cell_coordinates(mesh)
    a, b = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    assert np.all(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 0)


def test_boundary_nodes_on_circles(small_packing):
    packing, _, (mesh, tags) = small_packing
    xy, dofs = cell_coordinates(mesh)
    body = np.empty(len(xy), dtype=int)
    body[tags.indices] = tags.values
    mesh.topology.create_connectivity(1, 2)
    facets = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    f2v = mesh.topology.connectivity(1, 0)
    f2c = mesh.topology.connectivity(1, 2)
    c2v = mesh.topology.connectivity(2, 0)
    x = mesh.geometry.x[:, :2]
    on_circle = []
    for f in facets:
        cell = f2c.links(f)[0]
        # vertex and geometry numbering agree cell by cell for P1
        local = [list(c2v.links(cell)).index(v) for v in f2v.links(f)]
        r = np.linalg.norm(x[dofs[cell, local]] - packing.centres[body[cell]],
                           axis=1)
        on_circle.append(r - packing.radii[body[cell]])
    on_circle = np.concatenate(on_circle)
    assert len(facets) == len(on_circle) // 2
    assert np.max(np.abs(on_circle)) < 1e-15
    inside = np.linalg.norm(xy - packing.centres[body][:, None], axis=2)
    assert np.all(inside <= packing.radii[body][:, None] + 1e-15)


def test_invalid_arguments_write_nothing(tmp_path):
    for bad in [dict(element_size=-H), dict(element_size=0.01),
                dict(radii=[0.01, -0.01]), dict(centres=[(0, 0)])]:
        args = dict(centres=[(0, 0), (0.05, 0)], radii=[0.01, 0.01],
                    element_size=H, out_stem=tmp_path / "bad")
        args.update(bad)
        with pytest.raises(ValueError):
            mesh_disks(**args)
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_nothing(tmp_path, monkeypatch):
    def broken(*args):
        raise RuntimeError("disk full")

    monkeypatch.setattr(mesh_module, "_write_xdmf", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        mesh_disks([(0, 0)], [0.01], 2e-3, tmp_path / "m")
    assert list(tmp_path.iterdir()) == []


def test_interrupted_rename_does_not_look_complete(tmp_path, monkeypatch):
    stem = tmp_path / "m"
    mesh_disks([(0, 0)], [0.01], 2e-3, stem)
    real_replace, calls = mesh_module.os.replace, []

    def replace_once(src, dst):
        calls.append(dst)
        if len(calls) > 1:
            raise OSError("interrupted")
        real_replace(src, dst)

    monkeypatch.setattr(mesh_module.os, "replace", replace_once)
    with pytest.raises(OSError, match="interrupted"):
        mesh_disks([(0, 0)], [0.012], 2e-3, stem)
    xdmf, h5, bodies_csv = output_paths(stem)
    assert not bodies_csv.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.h5", "m.xdmf"]


def test_cli_disk(tmp_path, capsys):
    stem = tmp_path / "sub" / "disk"
    assert mesh_module.main(["disk", "--diameter", "0.02", "--element-size",
                             "2e-3", "--out", str(stem)]) == 0
    assert "1 bodies" in capsys.readouterr().out
    table = read_bodies(output_paths(stem)[2])
    assert table["radius"].tolist() == [0.01]


def test_cli_packing(tmp_path):
    stem = tmp_path / "pk"
    assert mesh_module.main([
        "packing", "--seed", "3", "--counts", "5", "2", "--length", "0.1",
        "--width", "0.08", "--element-size", "3e-3", "--out", str(stem)]) == 0
    packing = Packing.from_csv(tmp_path / "pk.packing.csv")
    assert packing.seed == 3 and packing.n_particles == 7
    table = read_bodies(output_paths(stem)[2])
    assert np.array_equal(table["radius"], packing.radii)
    again = tmp_path / "again"
    assert mesh_module.main(["packing", "--packing",
                             str(tmp_path / "pk.packing.csv"),
                             "--element-size", "3e-3", "--out",
                             str(again)]) == 0
    assert read_bodies(output_paths(again)[2])["x"].tolist() == \
        table["x"].tolist()


@pytest.mark.parametrize("argv, message", [
    (["disk", "--out", "x"], "--diameter"),
    (["disk", "--diameter", "-0.02", "--out", "x"], "must be positive"),
    (["disk", "--diameter", "0.02", "--element-size", "0.01", "--out", "x"],
     "too large"),
    (["packing", "--out", "x"], "--seed"),
    (["packing", "--seed", "1", "--counts", "5", "--out", "x"],
     "same number"),
    (["packing", "--seed", "-1", "--out", "x"], "non-negative"),
])
def test_cli_errors(argv, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_info:
        mesh_module.main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_geometry_file_gives_todays_triangles():
    """meshes/disk.geo gives exactly the triangles of the gmsh-API disk
    (occ.addDisk) that the mesher used before it: same nodes, same
    coordinates, same triangles, for both paper sizes and a coarse h."""
    import gmsh

    def api_disk(radius, h):
        triangulation.initialize_gmsh(gmsh)  # no FLTK preference files
        try:
            triangulation.mesh_options(gmsh, h)
            gmsh.model.add("api")
            surface = gmsh.model.occ.addDisk(0.0, 0.0, 0.0, radius, radius)
            gmsh.model.occ.synchronize()
            gmsh.model.mesh.generate(2)
            tags, coords, _ = gmsh.model.mesh.getNodes(
                2, surface, includeBoundary=True, returnParametricCoord=False)
            _, _, nodes = gmsh.model.mesh.getElements(2, surface)
            local = {int(t): i for i, t in enumerate(tags)}
            triangles = np.array([local[int(t)] for t in nodes[0]])
            return coords.reshape(-1, 3)[:, :2], triangles.reshape(-1, 3)
        finally:
            gmsh.finalize()

    for h in (H, 3e-3):
        from_file = mesh_module.disk_triangulation([0.010, 0.015], h)
        for radius in (0.010, 0.015):
            points, triangles = from_file[radius]
            expected, expected_triangles = api_disk(radius, h)
            assert points.shape == expected.shape
            assert np.array_equal(points, expected)
            # the same triangles (the mesher orients them counter-clockwise)
            assert np.array_equal(np.sort(triangles, axis=1),
                                  np.sort(expected_triangles, axis=1))
    assert shapes.shape_file("disk").parent == paths.MESHES
    with pytest.raises(FileNotFoundError, match="meshes/README.md"):
        shapes.shape_file("star")
