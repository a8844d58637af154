"""Stress recovery and VTU output.

Stresses are evaluated from the displacement gradient at every element's own nodes and averaged over the
elements sharing a node (plain nodal averaging; good enough for pictures and hot-spot reading, not for
error estimation). VTU is written directly as XML with zlib-compressed base64 binary arrays: no extra
dependency, and ParaView and pyvista read it (quadratic cells keep their mid nodes, so P2 fields render
curved).

Next to ``NAME.vtu`` (the cells, with the cell data ``physical_group``) goes ``NAME.boundary.vtu``: the
facets of every named group (``fixed``, ``loaded``, ``crack_face``, ``crack``, ...) with the same
``physical_group`` ids, so a ParaView user selects a face set with Threshold on that id. Both files carry
FieldData: ``physical_group_names`` (id k is entry k - 1; 1 is the volume), and the study, its load and
its material (``field_info``).
"""
from __future__ import annotations

import base64
import zlib
from pathlib import Path
from typing import Mapping

import numpy as np

from ..io_atomic import atomic_path
from .assembly import Lame
from .mesh_data import MeshData, SkfemMesh

# VTK cell types and the gmsh -> VTK node permutation (VTK tet10 mid-edge order 01 12 20 03 13 23)
_VTK = {(3, 1): (10, None), (3, 2): (24, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]), (2, 1): (5, None), (2, 2): (22, None)}


def nodal_displacement(md: MeshData, sk: SkfemMesh, u: np.ndarray) -> np.ndarray:
    """(N, 3) displacement at MeshData nodes from the interleaved skfem solution vector (z = 0 in 2D)."""
    d = md.dim
    out = np.zeros((md.nodes_mm.shape[0], 3))
    for c in range(d):
        out[:, c] = u[d * sk.node_to_dof + c]
    return out


def _element_node_stress(sk: SkfemMesh, u: np.ndarray, lame: Lame, d: int):
    """Cauchy stress at each element's own nodes: (3, 3, nel, nloc) (plane stress: zz = 0), and the basis."""
    from skfem import Basis
    elem = sk.element
    X = np.asarray(elem.doflocs, float).T                      # reference node positions (dim, nloc)
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
    for a in range(d):
        sig[a, a] += lame.lam_MPa * tr
    return sig, basis


_COMPONENTS = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)]


def nodal_stress(md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame) -> np.ndarray:
    """Averaged nodal Cauchy stress (N, 6) as xx, yy, zz, xy, yz, zx in MPa (plane stress: zz = 0).

    ``lame`` must match the analysis (plane-stress Lame constants in 2D)."""
    d = md.dim
    sig, basis = _element_node_stress(sk, u, lame, d)
    dofs = basis.element_dofs                                   # (nloc, nel); quadrature node q = local dof q
    n = basis.N
    count = np.bincount(dofs.ravel(), minlength=n)
    s_dof = np.zeros((n, 6))
    for k, (a, b) in enumerate(_COMPONENTS):
        if a < d and b < d:
            s_dof[:, k] = np.bincount(dofs.ravel(), weights=sig[a, b].T.ravel(), minlength=n) / np.maximum(count, 1)
    return s_dof[sk.node_to_dof]


def cell_stress(md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame) -> np.ndarray:
    """Mean Cauchy stress of each cell over its own nodes (M, 6), in MeshData cell order (= skfem's)."""
    d = md.dim
    sig, _ = _element_node_stress(sk, u, lame, d)
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
    return {"study": study, "load": load,
            "material": f"E = {material.youngs_modulus_MPa:g} MPa, nu = {material.poisson_ratio:g}",
            "youngs_modulus_MPa": float(material.youngs_modulus_MPa), "poisson_ratio": float(material.poisson_ratio)}


def _array(name: str, a: np.ndarray) -> str:
    """One binary DataArray, zlib-compressed in a single block (VTK's header: 1 block, its raw size,
    the last block's raw size, its compressed size; UInt64), header and data base64-encoded apart."""
    a = np.ascontiguousarray(a)
    vtk_type = {"f": "Float64", "i": "Int64", "u": "UInt8"}[a.dtype.kind]
    ncomp = 1 if a.ndim == 1 else a.shape[1]
    raw = a.tobytes()
    packed = zlib.compress(raw, 6)
    header = np.array([1, len(raw), len(raw), len(packed)], dtype=np.uint64).tobytes()
    payload = base64.b64encode(header).decode("ascii") + base64.b64encode(packed).decode("ascii")
    return (f'<DataArray type="{vtk_type}" Name="{name}" NumberOfComponents="{ncomp}" format="binary">'
            f"{payload}</DataArray>\n")


def _field_data(info: Mapping[str, str | float], names: list[str]) -> str:
    """FieldData: strings as VTK String arrays (ASCII codes, each string 0-terminated), numbers as Float64."""
    def strings(name, values):
        codes = " ".join(" ".join(str(b) for b in v.encode("utf-8")) + " 0" for v in values)
        return (f'<DataArray type="String" Name="{name}" NumberOfTuples="{len(values)}" format="ascii">'
                f"{codes}</DataArray>\n")
    parts = ["<FieldData>\n", strings("physical_group_names", names)]
    for key, value in info.items():
        if isinstance(value, str):
            parts.append(strings(key, [value]))
        else:
            parts.append(f'<DataArray type="Float64" Name="{key}" NumberOfTuples="1" format="ascii">'
                         f"{float(value)!r}</DataArray>\n")
    parts.append("</FieldData>\n")
    return "".join(parts)


def _piece(points: np.ndarray, cells: list[np.ndarray], types: np.ndarray, point_data, cell_data) -> str:
    ncell = len(types)
    connectivity = np.concatenate([c.ravel() for c in cells]).astype(np.int64) if cells else np.zeros(0, np.int64)
    offsets = np.cumsum(np.concatenate([np.full(c.shape[0], c.shape[1], np.int64) for c in cells])) \
        if cells else np.zeros(0, np.int64)
    parts = [f'<Piece NumberOfPoints="{points.shape[0]}" NumberOfCells="{ncell}">\n<PointData>\n']
    parts += [_array(n, np.asarray(v, np.float64)) for n, v in point_data.items()]
    parts.append("</PointData>\n<CellData>\n")
    parts += [_array(n, np.asarray(v)) for n, v in cell_data.items()]
    parts.append("</CellData>\n<Points>\n")
    parts.append(_array("Points", np.asarray(points, np.float64)))
    parts.append("</Points>\n<Cells>\n")
    parts.append(_array("connectivity", connectivity))
    parts.append(_array("offsets", offsets.astype(np.int64)))
    parts.append(_array("types", np.asarray(types, np.uint8)))
    parts.append("</Cells>\n</Piece>\n")
    return "".join(parts)


def _vtu_text(field_data: str, piece: str) -> str:
    return ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
            'header_type="UInt64" compressor="vtkZLibDataCompressor">\n<UnstructuredGrid>\n'
            + field_data + piece + "</UnstructuredGrid>\n</VTKFile>\n")


def boundary_path(path: Path) -> Path:
    """Where the named boundary facets of ``path`` (NAME.vtu) go: NAME.boundary.vtu."""
    path = Path(path)
    return path.with_name(f"{path.stem}.boundary.vtu")


def write_vtu(path: Path, md: MeshData, point_data: Mapping[str, np.ndarray],
              cell_data: Mapping[str, np.ndarray] | None = None, *,
              info: Mapping[str, str | float] | None = None) -> Path:
    """Write the mesh and fields as a VTU file, and its named boundary facets as NAME.boundary.vtu
    (both atomically). Arrays are (N,) or (N, k) per node / cell; ``info`` becomes FieldData
    (``field_info``). Returns the path of the cells' file.

    Typical point data: ``displacement_mm`` (N, 3), ``von_mises_MPa`` (N,), ``stress_MPa`` (N, 6)."""
    vtk_type, perm = _VTK[(md.dim, md.order)]
    cells = md.cells if perm is None else md.cells[:, perm]
    names = [VOLUME_GROUP[md.dim], *sorted(md.groups)]
    fields = _field_data(info or {}, names)
    volume_cells = {"physical_group": np.ones(cells.shape[0], np.int64),
                    **{n: np.asarray(v, np.float64) for n, v in (cell_data or {}).items()}}
    volume = _vtu_text(fields, _piece(md.nodes_mm, [cells], np.full(cells.shape[0], vtk_type), point_data,
                                      volume_cells))
    facets, types, ids = [], [], []
    for gid, name in enumerate(names[1:], start=2):
        rows = np.asarray(md.groups[name])
        k = rows.shape[1]
        facet_type = _FACET_VTK_BY_DIM[(md.dim, k)] if k == 3 else _FACET_VTK[k]
        facets.append(rows)
        types.append(np.full(rows.shape[0], facet_type))
        ids.append(np.full(rows.shape[0], gid, np.int64))
    # the boundary file shares the volume's points, so point data (displacement, stress) shows on the faces
    boundary = _vtu_text(fields, _piece(md.nodes_mm, facets, np.concatenate(types) if types else np.zeros(0),
                                        point_data, {"physical_group": np.concatenate(ids) if ids
                                                     else np.zeros(0, np.int64)}))
    path = Path(path)
    with atomic_path(boundary_path(path)) as tmp:
        tmp.write_text(boundary, encoding="ascii")
    with atomic_path(path) as tmp:
        tmp.write_text(volume, encoding="ascii")
    return path


def write_solid_fields(path: Path, md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame,
                       info: Mapping[str, str | float] | None = None) -> Path:
    """The fields every elasticity study writes (the registry's ``vtu_fields``): displacement, von Mises
    and the stress tensor at the mesh nodes, as VTU (``info``: FieldData, see ``field_info``)."""
    s = nodal_stress(md, sk, u, lame)
    return write_vtu(path, md, {"displacement_mm": nodal_displacement(md, sk, u), "von_mises_MPa": von_mises(s),
                                "stress_MPa": s}, info=info)
