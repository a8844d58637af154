"""Consistent load vector of a traction on named boundary triangles, integrated on the facets themselves.

scikit-fem's FacetBasis maps every facet quadrature point back into its tetrahedron with a Newton
iteration (``invF``); on curved P2 tets next to a crack slot (aspect ratios of 50 and more) that
iteration does not converge and the load cannot be built. The trace of the P2 (P1) tetrahedron basis on
a face is exactly the P2 (P1) triangle basis on that face's 6 (3) nodes, so the load can be integrated
on the facet triangles directly, with the same curved geometry and no inverse mapping:

    f[3 dof(j) + c] += sum_q w_q N_j(xi_q) t_c(x(xi_q)) |dx/dxi x dx/deta|.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from .mesh_data import MeshData, SkfemMesh


def _shape(xi: np.ndarray, eta: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangle shape functions (k, nq) and their xi, eta derivatives in gmsh node order
    (vertices 0, 1, 2, then mid-edge 01, 12, 20)."""
    L = np.array([1.0 - xi - eta, xi, eta])
    dL_dxi = np.array([-1.0, 1.0, 0.0])[:, None] * np.ones_like(xi)
    dL_deta = np.array([-1.0, 0.0, 1.0])[:, None] * np.ones_like(xi)
    if order == 1:
        return L, dL_dxi, dL_deta
    pairs = ((0, 1), (1, 2), (2, 0))
    N = np.vstack([L * (2 * L - 1)] + [4 * L[i] * L[j] for i, j in pairs])
    dN = []
    for dL in (dL_dxi, dL_deta):
        dN.append(np.vstack([(4 * L - 1) * dL] + [4 * (dL[i] * L[j] + L[i] * dL[j]) for i, j in pairs]))
    return N, dN[0], dN[1]


def facet_traction_load(md: MeshData, sk: SkfemMesh, group: str, traction: Callable[[np.ndarray], np.ndarray],
                        *, quad_order: int = 6) -> np.ndarray:
    """Load vector (interleaved, 3 per scalar dof) of ``traction`` on the 3D mesh's boundary group.

    traction : x (3, nf, nq) in mm -> t (3, nf, nq) in MPa (the same convention as assembly.traction_load).
    """
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTri

    if md.dim != 3:
        raise ValueError("facet_traction_load integrates on the triangles of a 3D mesh")
    tri = md.groups[group]
    k = 6 if md.order == 2 else 3
    if tri.shape[1] != k:
        raise ValueError(f"group {group!r} holds {tri.shape[1]}-node facets, expected {k}")
    X, W = get_quadrature(RefTri, quad_order)
    N, dxi, deta = _shape(X[0], X[1], md.order)                  # (k, nq)
    xyz = md.nodes_mm[tri].transpose(2, 0, 1)                    # (3, nf, k)
    x = np.einsum("cfk,kq->cfq", xyz, N)
    jac = np.cross(np.einsum("cfk,kq->fqc", xyz, dxi), np.einsum("cfk,kq->fqc", xyz, deta))
    da = np.linalg.norm(jac, axis=-1) * W[None, :]               # (nf, nq)
    t = np.asarray(traction(x))                                  # (3, nf, nq)
    local = np.einsum("cfq,kq,fq->fkc", t, N, da)                # (nf, k, 3)
    dofs = sk.node_to_dof[tri]                                   # (nf, k)
    n = int(sk.node_to_dof.max()) + 1
    f = np.zeros(3 * n)
    for c in range(3):
        f[c::3] = np.bincount(dofs.ravel(), weights=local[:, :, c].ravel(), minlength=n)
    return f
