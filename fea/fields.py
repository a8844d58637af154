"""Stress recovery and VTU output.

Stresses are evaluated from the displacement gradient at every element's own nodes and averaged over the
elements sharing a node (plain nodal averaging; good enough for pictures and hot-spot reading, not for
error estimation). VTU is written by VTK's own XML writer, zlib-compressed, fields as Float32 with named
components (``stress_MPa``: xx, yy, zz, xy, yz, xz; ``displacement_mm``: x, y, z), beside von Mises and the
three principal stresses; ParaView, pyvista and meshio read it (quadratic cells keep their mid nodes, so P2
fields render curved). Text FieldData is VTK String arrays (ParaView's spreadsheet and pyvista show text);
meshio 5.3 refuses String arrays, so a meshio user reads through ``pyvista.to_meshio(pyvista.read(FILE))``
(docs/decisions/067-out52b-strings-progress.md).

The load the fields are at is said in every file: ``fields_at`` (text) and ``load_scale_applied`` (the factor
from the solved load, 1 as solved). ``rescale_vtu`` turns a study's fields into those of another load (the
validation and ``solve`` write them at the rated load, the one their reports state).

Next to ``NAME.vtu`` (the cells, with the cell data ``physical_group``) goes ``NAME.boundary.vtu``: the
facets of every named group (``fixed``, ``loaded``, ``crack_face``, ``crack``, ...) with the same
``physical_group`` ids, so a ParaView user selects a face set with Threshold on that id. Both files carry
FieldData: ``physical_group_names`` (id k is entry k - 1; 1 is the volume), and the study, its load and
its material (``field_info``).
"""
from __future__ import annotations

from pathlib import Path
from typing import Mapping

import numpy as np

from strainwave.io_atomic import atomic_path
from strainwave.fea.assembly import Lame, ThermalStrain
from strainwave.fea.mesh_data import MeshData, SkfemMesh

# VTK cell types and the gmsh -> VTK node permutation (VTK tet10 mid-edge order 01 12 20 03 13 23)
_VTK = {(3, 1): (10, None), (3, 2): (24, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]), (2, 1): (5, None), (2, 2): (22, None)}


def nodal_displacement(md: MeshData, sk: SkfemMesh, u: np.ndarray) -> np.ndarray:
    """(N, 3) displacement at MeshData nodes from the interleaved skfem solution vector (z = 0 in 2D)."""
    d = md.dim
    out = np.zeros((md.nodes_mm.shape[0], 3))
    for c in range(d):
        out[:, c] = u[d * sk.node_to_dof + c]
    return out


def _element_node_stress(sk: SkfemMesh, u: np.ndarray, lame: Lame, d: int, thermal: ThermalStrain | None = None,
                         inset: float = 0.0):
    """Cauchy stress sigma = C (eps - eps_th) at each element's own nodes: (d, d, nel, nloc) (plane stress:
    zz = 0), and the basis; ``inset`` > 0 reads each node that fraction of the way to the element's centre."""
    from skfem import Basis
    elem = sk.element
    X = np.asarray(elem.doflocs, float).T                      # reference node positions (dim, nloc)
    X = X + inset * (X.mean(axis=1, keepdims=True) - X)
    basis = Basis(sk.mesh, elem, quadrature=(X, np.ones(X.shape[1])))
    nloc = X.shape[1]
    grad = np.zeros((d, d, basis.nelems, nloc))                # du_a/dx_b at each element's nodes
    ue = np.stack([u[d * basis.element_dofs + c] for c in range(d)])  # (d, nloc, nel)
    for i in range(nloc):
        g = basis.basis[i][0].grad                              # (d, nel, nq=nloc)
        grad += ue[:, None, i, :, None] * g[None]
    eps = 0.5 * (grad + grad.transpose(1, 0, 2, 3))
    tr = np.trace(eps)
    sig = 2 * lame.mu_MPa * eps
    # C eps_th = c dT I: only the diagonal moves, by the rise at each element node
    hydro = lame.lam_MPa * tr
    if thermal is not None:
        x = sk.doflocs[:, basis.element_dofs].transpose(0, 2, 1)                 # (d, nel, nloc)
        hydro = hydro - thermal.stress_per_K(lame, d) * thermal.rise_at(x)
    for a in range(d):
        sig[a, a] += hydro
    return sig, basis


_COMPONENTS = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)]


def nodal_stress(md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame,
                 thermal: ThermalStrain | None = None, inset: float = 0.0) -> np.ndarray:
    """Averaged nodal Cauchy stress (N, 6) as xx, yy, zz, xy, yz, zx in MPa (plane stress: zz = 0).

    ``lame`` must match the analysis (plane-stress Lame constants in 2D); ``thermal`` the thermal strain
    it was solved with (sigma = C (eps - eps_th)); ``inset``: see ``_element_node_stress`` (a quarter-point
    element's map is singular at its tip node)."""
    d = md.dim
    sig, basis = _element_node_stress(sk, u, lame, d, thermal, inset)
    dofs = basis.element_dofs                                   # (nloc, nel); quadrature node q = local dof q
    n = basis.N
    count = np.bincount(dofs.ravel(), minlength=n)
    s_dof = np.zeros((n, 6))
    for k, (a, b) in enumerate(_COMPONENTS):
        if a < d and b < d:
            s_dof[:, k] = np.bincount(dofs.ravel(), weights=sig[a, b].T.ravel(), minlength=n) / np.maximum(count, 1)
    return s_dof[sk.node_to_dof]


def cell_stress(md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame,
                thermal: ThermalStrain | None = None) -> np.ndarray:
    """Mean Cauchy stress of each cell over its own nodes (M, 6), in MeshData cell order (= skfem's)."""
    d = md.dim
    sig, _ = _element_node_stress(sk, u, lame, d, thermal)
    out = np.zeros((md.cells.shape[0], 6))
    for k, (a, b) in enumerate(_COMPONENTS):
        if a < d and b < d:
            out[:, k] = sig[a, b].mean(axis=1)
    return out


def von_mises(stress: np.ndarray) -> np.ndarray:
    """von Mises equivalent stress of (..., 6) stresses (xx, yy, zz, xy, yz, zx)."""
    sxx, syy, szz, sxy, syz, szx = np.moveaxis(stress, -1, 0)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * (sxy ** 2 + syz ** 2 + szx ** 2))


# VTK cell types of boundary facets by (nodes per facet): vertex, line, quadratic edge, triangle, triangle6
_FACET_VTK = {1: 1, 2: 3, 3: None, 6: 22}
_FACET_VTK_BY_DIM = {(2, 3): 21, (3, 3): 5}      # 3 nodes: a quadratic edge in 2D, a triangle in 3D
VOLUME_GROUP = {3: "solid", 2: "section"}        # the physical group of the cells, as fea/meshing names it


def field_info(study: str, load: str, material) -> dict[str, str | float]:
    """FieldData every VTU of a study carries: what was solved, under which load, with which material."""
    return {"study": study, "load": load, "fields_at": f"the solved load: {load}", "load_scale_applied": 1.0,
            "material": f"E = {material.youngs_modulus_MPa:g} MPa, nu = {material.poisson_ratio:g}",
            "youngs_modulus_MPa": float(material.youngs_modulus_MPa), "poisson_ratio": float(material.poisson_ratio)}


# names of each component, so ParaView, meshio and pyvista users read "xx" rather than "0"
COMPONENT_NAMES = {"displacement_mm": ("x", "y", "z"), "stress_MPa": ("xx", "yy", "zz", "xy", "yz", "xz")}


def _text_array(name: str, values: list[str]):
    """Strings as a VTK String array, so ParaView and pyvista show text (issue 52)."""
    from vtkmodules.vtkCommonCore import vtkStringArray

    arr = vtkStringArray()
    arr.SetName(name)
    for value in values:
        arr.InsertNextValue(value)
    return arr


def field_text(mesh, name: str) -> list[str]:
    """The strings of FieldData ``name`` of a VTU these writers made (VTK String arrays; the 0-separated
    char arrays of files written before issue 52 are decoded)."""
    raw = mesh.field_data[name]
    values = np.asarray(raw)
    if values.dtype.kind in "iu":
        return [part.decode("utf-8") for part in bytes(values.astype(np.uint8)).split(b"\0")[:-1]]
    return [str(v) for v in values]


def _data_array(name: str, values: np.ndarray, dtype):
    from vtkmodules.util.numpy_support import numpy_to_vtk

    a = np.ascontiguousarray(np.asarray(values, dtype=dtype))
    arr = numpy_to_vtk(a.reshape(a.shape[0], -1) if a.ndim > 1 else a, deep=True)
    arr.SetName(name)
    for k, component in enumerate(COMPONENT_NAMES.get(name, ())[:arr.GetNumberOfComponents()]):
        arr.SetComponentName(k, component)
    return arr


def _grid(points: np.ndarray, cells: list[np.ndarray], types: np.ndarray, point_data, cell_data,
          info: Mapping[str, str | float], names: list[str]):
    """A vtkUnstructuredGrid, all Float32: 7 digits place a node to 0.02 um in a 160 mm part, a hundredth of the
    finest crack-front element, and give peaks to 1e-7."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, np.float32), deep=True))
    grid.SetPoints(pts)
    connectivity = np.concatenate([c.ravel() for c in cells]).astype(np.int64) if cells else np.zeros(0, np.int64)
    offsets = np.concatenate([[0], np.cumsum(np.concatenate([np.full(c.shape[0], c.shape[1], np.int64)
                                                              for c in cells]))]) if cells else np.zeros(1, np.int64)
    cell_array = vtkCellArray()
    cell_array.SetData(numpy_to_vtkIdTypeArray(offsets.astype(np.int64), deep=True),
                       numpy_to_vtkIdTypeArray(connectivity, deep=True))
    if connectivity.size == 0 or connectivity.max() < 2 ** 31 - 1:
        cell_array.ConvertTo32BitStorage()   # the writer then stores Int32 connectivity and offsets
    grid.SetCells(numpy_to_vtk(np.ascontiguousarray(types, np.uint8), deep=True), cell_array)
    for data, arrays in ((grid.GetPointData(), point_data), (grid.GetCellData(), cell_data)):
        for name, values in arrays.items():
            kind = np.asarray(values).dtype.kind
            data.AddArray(_data_array(name, values, np.int32 if kind in "iu" else np.float32))
    fd = grid.GetFieldData()
    fd.AddArray(_text_array("physical_group_names", names))
    for key, value in info.items():
        fd.AddArray(_text_array(key, [value]) if isinstance(value, str)
                    else _data_array(key, np.array([float(value)]), np.float64))
    return grid


def _write_grid(path: Path, grid) -> None:
    """VTK's own XML writer: appended raw binary, zlib level 1 (meshio reads zlib and LZMA, not LZ4): level 9
    took up to 17 times as long for files 0.5-2 % smaller (docs/decisions/045-ring-images-nafems-cost.md)."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetHeaderTypeToUInt64()
    writer.SetCompressorTypeToZLib()
    writer.SetCompressionLevel(1)
    if writer.Write() != 1:
        raise OSError(f"VTK could not write {path}")


def boundary_path(path: Path) -> Path:
    """Where the named boundary facets of ``path`` (NAME.vtu) go: NAME.boundary.vtu."""
    path = Path(path)
    return path.with_name(f"{path.stem}.boundary.vtu")


BOUNDARY_FIELDS = ("displacement_mm", "von_mises_MPa")   # point data the boundary file repeats
VOLUME_POINT_ID = "volume_point_id"   # the boundary file's point data: each point's node id in the volume's file


def write_vtu(path: Path, md: MeshData, point_data: Mapping[str, np.ndarray],
              cell_data: Mapping[str, np.ndarray] | None = None, *,
              info: Mapping[str, str | float] | None = None) -> Path:
    """Write the mesh and fields as a VTU file, and its named boundary facets as NAME.boundary.vtu
    (both atomically, through VTK's XML writer, zlib-compressed). Arrays are (N,) or (N, k) per node / cell;
    ``info`` becomes FieldData (``field_info``). Returns the path of the cells' file.

    Typical point data: ``displacement_mm`` (N, 3), ``von_mises_MPa`` (N,), ``stress_MPa`` (N, 6)."""
    vtk_type, perm = _VTK[(md.dim, md.order)]
    cells = md.cells if perm is None else md.cells[:, perm]
    names = [VOLUME_GROUP[md.dim], *sorted(md.groups)]
    info = {**(info or {}), "load_scale_applied": float((info or {}).get("load_scale_applied", 1.0))}
    volume_cells = {"physical_group": np.ones(cells.shape[0], np.int64), **dict(cell_data or {})}
    volume = _grid(md.nodes_mm, [cells], np.full(cells.shape[0], vtk_type), point_data, volume_cells, info, names)
    facets, types, ids = [], [], []
    for gid, name in enumerate(names[1:], start=2):
        rows = np.asarray(md.groups[name])
        k = rows.shape[1]
        facet_type = _FACET_VTK_BY_DIM[(md.dim, k)] if k == 3 else _FACET_VTK[k]
        facets.append(rows)
        types.append(np.full(rows.shape[0], facet_type))
        ids.append(np.full(rows.shape[0], gid, np.int64))
    # the boundary file holds only its faces' points, each with its node id in the volume's file; it repeats
    # displacement and von Mises, the full tensor stays in the volume's file
    used = np.unique(np.concatenate([f.ravel() for f in facets])) if facets else np.zeros(0, np.int64)
    shown = {k: np.asarray(v)[used] for k, v in point_data.items() if k in BOUNDARY_FIELDS} \
        or {k: np.asarray(v)[used] for k, v in point_data.items()}
    shown[VOLUME_POINT_ID] = used.astype(np.int32)
    boundary = _grid(md.nodes_mm[used], [np.searchsorted(used, f) for f in facets],
                     np.concatenate(types) if types else np.zeros(0),
                     shown, {"physical_group": np.concatenate(ids) if ids else np.zeros(0, np.int64)}, info, names)
    path = Path(path)
    with atomic_path(boundary_path(path)) as tmp:
        _write_grid(tmp, boundary)
    with atomic_path(path) as tmp:
        _write_grid(tmp, volume)
    return path


def principal_stresses(stress: np.ndarray) -> np.ndarray:
    """(..., 3) principal stresses, largest first, of (..., 6) stresses (xx, yy, zz, xy, yz, xz)."""
    sxx, syy, szz, sxy, syz, sxz = np.moveaxis(stress, -1, 0)
    tensor = np.stack([np.stack([sxx, sxy, sxz], -1), np.stack([sxy, syy, syz], -1),
                       np.stack([sxz, syz, szz], -1)], -2)
    return np.linalg.eigvalsh(tensor)[..., ::-1]


def stress_fields(stress: np.ndarray) -> dict[str, np.ndarray]:
    """Named nodal stress arrays: the tensor (components xx ... xz), von Mises and the three principal stresses."""
    principal = principal_stresses(stress)
    return {"stress_MPa": stress, "von_mises_MPa": von_mises(stress),
            **{f"principal_stress_{k + 1}_MPa": principal[:, k] for k in range(3)}}


def write_solid_fields(path: Path, md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame,
                       info: Mapping[str, str | float] | None = None, inset: float = 0.0) -> Path:
    """The fields every elasticity study writes (the registry's ``vtu_fields``): displacement, the stress
    tensor, von Mises and the principal stresses at the mesh nodes, as VTU (``info``: FieldData, see
    ``field_info``); ``inset``: see ``nodal_stress``."""
    s = nodal_stress(md, sk, u, lame, inset=inset)
    return write_vtu(path, md, {"displacement_mm": nodal_displacement(md, sk, u), **stress_fields(s)}, info=info)


# arrays linear in the load: displacements, rotations and stresses (never ids such as physical_group)
LINEAR_WORDS = ("disp", "rotation", "mises", "stress")


def _read_grid(path: Path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def rescale_vtu(path: Path, scale: float, fields_at: str, extra: Mapping[str, float] | None = None) -> Path:
    """Rewrite ``path`` and its boundary file so that every load-linear array is ``scale`` x the SOLVED load's
    (whatever scale the file carried before: idempotent), saying so in ``fields_at`` and ``load_scale_applied``;
    ``extra`` adds numeric FieldData (e.g. the rated load)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"load scale must be finite and > 0, got {scale}")
    for target in (boundary_path(path), Path(path)):
        if not target.exists():
            continue
        grid = _read_grid(target)
        fd = grid.GetFieldData()
        before = fd.GetArray("load_scale_applied")
        factor = scale / (float(before.GetValue(0)) if before is not None else 1.0)
        for data in (grid.GetPointData(), grid.GetCellData()):
            for k in range(data.GetNumberOfArrays()):
                arr = data.GetArray(k)
                if any(word in arr.GetName().lower() for word in LINEAR_WORDS):
                    scaled = numpy_to_vtk(vtk_to_numpy(arr) * np.float32(factor), deep=True)
                    scaled.SetName(arr.GetName())
                    for c in range(arr.GetNumberOfComponents()):
                        if arr.GetComponentName(c):
                            scaled.SetComponentName(c, arr.GetComponentName(c))
                    data.AddArray(scaled)   # replaces the array of the same name
        for name, value in {"load_scale_applied": scale, **(extra or {})}.items():
            fd.AddArray(_data_array(name, np.array([float(value)]), np.float64))
        fd.AddArray(_text_array("fields_at", [fields_at]))
        with atomic_path(target) as tmp:
            _write_grid(tmp, grid)
    return Path(path)
