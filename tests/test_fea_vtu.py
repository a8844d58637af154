"""VTU output a ParaView user can work with: compressed binary, the physical group of every cell, the named
boundary facets (fixed, loaded, crack_face, ...) in NAME.boundary.vtu, and FieldData naming the study,
its load and its material. Read back with pyvista (VTK's own reader)."""
import math
import re

import numpy as np
import pytest

from strainwave.fea.fields import boundary_path, field_info, field_text, write_vtu
from strainwave.fea.mesh_data import MeshData
from strainwave.params import load_params


def _group_id(grid, name):
    return field_text(grid, "physical_group_names").index(name) + 1


@pytest.fixture(scope="module")
def shaft_mesh():
    """The output shaft (D 70, d 45, L 200 mm), coarse P1: its 'fixed' end is an annulus at z = 0."""
    import warnings

    from strainwave.fea.meshing import mesh_part
    from strainwave.fea.session import gmsh_session
    from strainwave.geometry.parts import build_part

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params()
    part = build_part("output-shaft", params)
    with gmsh_session() as model:
        return params, mesh_part(model, part, size_mm=15.0, order=1)


def test_cells_groups_and_field_data_read_back(shaft_mesh, tmp_path):
    import pyvista as pv

    params, md = shaft_mesh
    info = field_info("shaft-torsion", "torque T = 1000 N*mm on 'loaded'", params.material)
    path = write_vtu(tmp_path / "shaft.vtu", md, {"displacement_mm": md.nodes_mm * 1e-3}, info=info)
    head = path.read_bytes()[:4000]
    assert b'compressor="vtkZLibDataCompressor"' in head and b'format="appended"' in head
    grid = pv.read(path)
    assert grid.n_cells == md.cells.shape[0]
    names = field_text(grid, "physical_group_names")
    assert names[0] == "solid" and set(names[1:]) == set(md.groups)
    assert (grid.cell_data["physical_group"] == _group_id(grid, "solid")).all()
    assert field_text(grid, "study") == ["shaft-torsion"]
    assert field_text(grid, "load")[0].startswith("torque T = 1000")
    assert field_text(grid, "fields_at")[0].startswith("the solved load: torque T = 1000")
    assert grid.field_data["load_scale_applied"][0] == 1.0
    assert grid.field_data["youngs_modulus_MPa"][0] == params.material.youngs_modulus_MPa
    assert grid.field_data["poisson_ratio"][0] == params.material.poisson_ratio

    boundary = pv.read(boundary_path(path))
    assert boundary_path(path).name == "shaft.boundary.vtu"
    assert field_text(boundary, "physical_group_names") == names
    assert sum(len(rows) for rows in md.groups.values()) == boundary.n_cells
    # ParaView's Threshold on physical_group selects 'fixed': the clamped annulus at z = 0
    fixed = boundary.threshold((_group_id(boundary, "fixed") - 0.5, _group_id(boundary, "fixed") + 0.5),
                               scalars="physical_group")
    assert fixed.n_cells == len(md.groups["fixed"])
    assert np.abs(fixed.points[:, 2]).max() < 1e-9
    area = fixed.compute_cell_sizes(length=False, volume=False)["Area"].sum()
    annulus = math.pi / 4 * (70.0 ** 2 - 45.0 ** 2)
    assert area == pytest.approx(annulus, rel=0.02)        # straight P1 chords inscribed in the circles
    # the boundary file holds its faces' points only, each with its node id in the volume's file
    ids = np.asarray(boundary.point_data["volume_point_id"])
    assert ids.size == np.unique(np.concatenate([np.ravel(r) for r in md.groups.values()])).size <= md.nodes_mm.shape[0]
    assert np.allclose(boundary.points, md.nodes_mm[ids], atol=1e-5)
    assert np.allclose(boundary.point_data["displacement_mm"], md.nodes_mm[ids] * 1e-3)


def test_quadratic_section_with_crack_face_and_point_group(tmp_path):
    """2D P2: edges of a named group (quadratic edges, VTK 21) and a node set (vertices) come back."""
    import pyvista as pv

    nodes = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    md = MeshData(nodes, np.array([[0, 1, 2, 3, 4, 5]]), 2, 2,
                  groups={"crack_face": np.array([[0, 1, 3]]), "tip": np.array([[1]])})
    path = write_vtu(tmp_path / "section.vtu", md, {"u_mm": nodes[:, :2] * 0})
    grid, boundary = pv.read(path), pv.read(boundary_path(path))
    assert list(grid.celltypes) == [22] and field_text(grid, "physical_group_names") == ["section", "crack_face", "tip"]
    assert list(boundary.celltypes) == [21, 1]
    crack = boundary.threshold((1.5, 2.5), scalars="physical_group")
    assert np.allclose(sorted(crack.points[:, 0]), [0, 1, 2])
    assert not list(tmp_path.glob(".*tmp"))


def test_arrays_are_compressed(tmp_path):
    """A smooth field compresses: the file is far smaller than its raw bytes."""
    n = 20000
    nodes = np.zeros((n, 3))
    nodes[:, 0] = np.arange(n)
    cells = np.stack([np.arange(n - 3), np.arange(1, n - 2), np.arange(2, n - 1), np.arange(3, n)], axis=1)
    md = MeshData(nodes, cells, 3, 1)
    path = write_vtu(tmp_path / "big.vtu", md, {"zero": np.zeros(n)})
    raw = nodes.nbytes + cells.nbytes * 2 + n * 8
    assert path.stat().st_size < 0.3 * raw
    assert re.search(rb'header_type="UInt64" compressor="vtkZLibDataCompressor"', path.read_bytes()[:1000])
