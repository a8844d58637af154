"""The VTU a user gets from `strainwave solve --vtu` (issue 40): at the rated load the command reports (and
saying so), stress components named, principal stresses, region ids, zlib through VTK's writer, its text
FieldData as VTK String arrays (issue 52), read by pyvista and VTK's own XML reader, and by meshio through
pyvista (meshio 5.3's own reader refuses String arrays: a test records that, docs/decisions/067). One cheap solve (coarse P1 shaft, h = 15 mm: the coarsest whose three meshes differ) for the module."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from conftest import STRAINWAVE
from strainwave.fea.fields import field_text, principal_stresses, rescale_vtu, von_mises


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    out = tmp_path_factory.mktemp("vtu")
    proc = subprocess.run([STRAINWAVE, "solve", "shaft-torsion", "--mesh-size-mm", "15", "--order", "1",
                           "--vtu", str(out / "shaft.vtu"), "--json", str(out / "solve.json")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return out / "shaft.vtu", json.loads((out / "solve.json").read_text())


def test_meshio_gets_both_files_with_named_fields_through_pyvista(solved):
    import meshio
    import pyvista as pv

    path, _ = solved
    fields = {"shaft.vtu": {"displacement_mm", "stress_MPa", "von_mises_MPa", "principal_stress_1_MPa",
                            "principal_stress_2_MPa", "principal_stress_3_MPa"},
              "shaft.boundary.vtu": {"displacement_mm", "von_mises_MPa", "volume_point_id"}}   # faces repeat two
    for name, expected in fields.items():
        grid = pv.read(path.with_name(name))
        mesh = pv.to_meshio(grid)   # the documented route (README, docs/outputs.md)
        assert isinstance(mesh, meshio.Mesh)
        assert mesh.points.shape == (grid.n_points, 3) and sum(len(c.data) for c in mesh.cells) == grid.n_cells
        assert set(mesh.point_data) == expected
        assert np.array_equal(mesh.point_data["von_mises_MPa"], grid.point_data["von_mises_MPa"])
        assert "physical_group" in mesh.cell_data


def test_meshio_own_reader_refuses_vtk_string_arrays(solved):
    """meshio 5.3.5 reads no VTK String array (its issue 1370): the day it does, this fails and the README's
    pyvista route for meshio users can go."""
    import meshio

    path, _ = solved
    with pytest.raises((meshio.ReadError, AssertionError)):   # 5.3.5: a bare assert on the appended String data
        meshio.read(path)


def test_text_field_data_reads_as_str_in_pyvista_and_vtk(solved):
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkStringArray
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    path, _ = solved
    for name in ("shaft.vtu", "shaft.boundary.vtu"):
        grid = pv.read(path.with_name(name))
        names = list(grid.field_data["physical_group_names"])
        assert names[0] == "solid" and {"fixed", "loaded"} <= set(names) and all(isinstance(n, str) for n in names)
        assert str(grid.field_data["study"][0]) == "shaft-torsion"
        assert str(grid.field_data["fields_at"][0]).startswith("the rated load: output torque T = 1e+06 N*mm")
        assert float(grid.field_data["load_scale_applied"][0]) == pytest.approx(1000.0)
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(path.with_name(name)))
        reader.Update()
        material = reader.GetOutput().GetFieldData().GetAbstractArray("material")
        assert isinstance(material, vtkStringArray) and material.GetValue(0).startswith("E = ")


def test_vtk_reader_sees_component_names_and_the_rated_load(solved):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    path, doc = solved
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfCells() > 0
    stress = grid.GetPointData().GetArray("stress_MPa")
    assert [stress.GetComponentName(k) for k in range(6)] == ["xx", "yy", "zz", "xy", "yz", "xz"]
    # the file is at the load the command reported: its peak von Mises is the printed rated peak
    vm = grid.GetPointData().GetArray("von_mises_MPa").GetRange()[1]
    assert vm == pytest.approx(doc["stress_at_rated"]["peak_von_mises_MPa"], rel=1e-5)
    assert grid.GetFieldData().GetArray("rated_load").GetValue(0) == pytest.approx(doc["stress_at_rated"]["load"]["rated"])


def test_pyvista_reads_fields_that_agree_with_their_tensor(solved):
    import pyvista as pv

    path, doc = solved
    grid = pv.read(path)
    assert field_text(grid, "fields_at")[0].startswith("the rated load: output torque T = 1e+06 N*mm")
    assert field_text(grid, "physical_group_names")[0] == "solid"
    assert set(np.unique(grid.cell_data["physical_group"])) == {1}
    s = np.asarray(grid.point_data["stress_MPa"], float)
    # von Mises and the principal stresses are those of the stored tensor (float32: 1e-4 relative)
    assert np.allclose(grid.point_data["von_mises_MPa"], von_mises(s), rtol=1e-4, atol=1e-4 * s.max())
    p = np.column_stack([grid.point_data[f"principal_stress_{k}_MPa"] for k in (1, 2, 3)])
    assert (p[:, 0] >= p[:, 1] - 1e-4).all() and (p[:, 1] >= p[:, 2] - 1e-4).all()
    assert np.allclose(p.sum(axis=1), s[:, :3].sum(axis=1), atol=1e-3 * np.abs(s).max())


def test_rescale_is_idempotent_and_scales_only_load_linear_arrays(solved, tmp_path):
    import shutil

    import pyvista as pv

    path, _ = solved
    copy = tmp_path / "shaft.vtu"
    shutil.copy(path, copy)
    shutil.copy(path.with_name("shaft.boundary.vtu"), tmp_path / "shaft.boundary.vtu")
    before = pv.read(copy)
    rescale_vtu(copy, 2000.0, "test: twice the rated load")
    rescale_vtu(copy, 2000.0, "test: twice the rated load")   # again: still 2000 x the solved load
    after = pv.read(copy)
    assert np.allclose(after.point_data["von_mises_MPa"], 2 * before.point_data["von_mises_MPa"], rtol=1e-6)
    assert np.array_equal(after.cell_data["physical_group"], before.cell_data["physical_group"])
    assert np.allclose(after.points, before.points)
    assert field_text(after, "fields_at") == ["test: twice the rated load"]
    boundary = pv.read(tmp_path / "shaft.boundary.vtu")
    assert boundary.field_data["load_scale_applied"][0] == 2000.0


def test_principal_stresses_of_a_known_tensor():
    # pure shear tau in xy: principal +tau, 0, -tau; von Mises sqrt(3) tau
    s = np.array([[0.0, 0.0, 0.0, 5.0, 0.0, 0.0]])
    assert np.allclose(principal_stresses(s), [[5.0, 0.0, -5.0]])
    assert von_mises(s)[0] == pytest.approx(np.sqrt(3) * 5.0)
