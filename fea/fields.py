"""Stress recovery and VTU output.

Stresses are evaluated from the displacement gradient at every element's own nodes and averaged over the
elements sharing a node (plain nodal averaging; good enough for pictures and hot-spot reading, not for
error estimation). VTU is written directly as XML with base64 binary arrays: no extra dependency, and
ParaView and pyvista read it (quadratic cells keep their mid nodes, so P2 fields render curved).
"""
from __future__ import annotations

import base64
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


def _array(name: str, a: np.ndarray) -> str:
    a = np.ascontiguousarray(a)
    vtk_type = {"f": "Float64", "i": "Int64", "u": "UInt8"}[a.dtype.kind]
    ncomp = 1 if a.ndim == 1 else a.shape[1]
    raw = a.tobytes()
    payload = base64.b64encode(np.uint64(len(raw)).tobytes() + raw).decode("ascii")
    return (f'<DataArray type="{vtk_type}" Name="{name}" NumberOfComponents="{ncomp}" format="binary">'
            f"{payload}</DataArray>\n")


def write_vtu(path: Path, md: MeshData, point_data: Mapping[str, np.ndarray],
              cell_data: Mapping[str, np.ndarray] | None = None) -> Path:
    """Write the mesh and fields as a VTU file (atomically). Arrays are (N,) or (N, k) per node / cell.

    Typical point data: ``displacement_mm`` (N, 3), ``von_mises_MPa`` (N,), ``stress_MPa`` (N, 6)."""
    vtk_type, perm = _VTK[(md.dim, md.order)]
    cells = md.cells if perm is None else md.cells[:, perm]
    ncell, k = cells.shape
    parts = ['<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
             'header_type="UInt64">\n<UnstructuredGrid>\n',
             f'<Piece NumberOfPoints="{md.nodes_mm.shape[0]}" NumberOfCells="{ncell}">\n<PointData>\n']
    parts += [_array(n, np.asarray(v, np.float64)) for n, v in point_data.items()]
    parts.append("</PointData>\n<CellData>\n")
    parts += [_array(n, np.asarray(v, np.float64)) for n, v in (cell_data or {}).items()]
    parts.append("</CellData>\n<Points>\n")
    parts.append(_array("Points", np.asarray(md.nodes_mm, np.float64)))
    parts.append("</Points>\n<Cells>\n")
    parts.append(_array("connectivity", cells.astype(np.int64).ravel()))
    parts.append(_array("offsets", (np.arange(1, ncell + 1, dtype=np.int64) * k)))
    parts.append(_array("types", np.full(ncell, vtk_type, dtype=np.uint8)))
    parts.append("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text("".join(parts), encoding="ascii")
    return path


def write_solid_fields(path: Path, md: MeshData, sk: SkfemMesh, u: np.ndarray, lame: Lame) -> Path:
    """The fields every elasticity study writes (the registry's ``vtu_fields``): displacement, von Mises
    and the stress tensor at the mesh nodes, as VTU."""
    s = nodal_stress(md, sk, u, lame)
    return write_vtu(path, md, {"displacement_mm": nodal_displacement(md, sk, u), "von_mises_MPa": von_mises(s),
                                "stress_MPa": s})
