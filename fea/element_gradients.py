"""Isoparametric P1/P2 simplex quadrature data, computed directly with the element index LAST.

The same quantities as a scikit-fem ``CellBasis`` (``basis.basis[i][0].grad``, ``basis.dx``) on the
same quadrature rule, without building one: the Jacobian of the (curved, P2) map comes from the
element's geometry nodes, J_cr = sum_k x_ck dN_k/dxi_r, its 3x3 (2x2) inverse is written out by
cofactors, and the physical gradients are g_k = J^-T dN_k. Element-last arrays make every step a long
contiguous vector operation. Local dof order is scikit-fem's: vertices, then the P2 edge nodes
01 12 02 03 13 23 (tets) / 01 12 02 (triangles).
Much faster than skfem's CellBasis for the same numbers (docs/decisions/004-assembly-kernels.md).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# local vertex pairs of the P2 edge dofs in scikit-fem's order (RefTet.edges / RefTri.facets)
SKFEM_EDGES = {3: ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)), 2: ((0, 1), (1, 2), (0, 2))}


@dataclass(frozen=True)
class ElementGeometry:
    """Quadrature data of every element of a P1/P2 simplex mesh.

    dN : (nloc, dim, nq) reference gradients of the field's local shape functions.
    inv : (dim, dim, nq, nel) inverse Jacobian, inv[r, a] = dxi_r / dx_a.
    dx : (nq, nel) quadrature weight times |det J|.
    element_dofs : (nloc, nel) global scalar dofs (scikit-fem numbering); n_dofs their count.
    """

    dN: np.ndarray
    inv: np.ndarray
    dx: np.ndarray
    element_dofs: np.ndarray
    n_dofs: int

    @property
    def dim(self) -> int:
        return self.dN.shape[1]

    @property
    def grad(self) -> np.ndarray:
        """(nloc, dim, nq, nel) physical gradients g_ka = sum_r dN_kr inv_ra."""
        return np.einsum("krq,raqe->kaqe", self.dN, self.inv)


def default_intorder(order: int) -> int:
    """Quadrature order of the stiffness: 2(p - 1), exact for straight-sided elements (P1: 1)."""
    return 2 * (order - 1) if order > 1 else 1


def simplex_quadrature(dim: int, intorder: int) -> tuple[np.ndarray, np.ndarray]:
    """scikit-fem's rule on the reference tetrahedron / triangle: points (dim, nq), weights (nq,)."""
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTet, RefTri
    return get_quadrature(RefTet if dim == 3 else RefTri, intorder)


def reference_gradients(dim: int, order: int, points: np.ndarray) -> np.ndarray:
    """(nloc, dim, nq) reference-element shape-function gradients at ``points`` (dim, nq).

    Barycentric form: L_0 = 1 - sum xi, L_r = xi_r; P1 N_i = L_i; P2 vertex N_i = L_i (2 L_i - 1),
    edge N_ab = 4 L_a L_b (the standard Lagrange simplex, as scikit-fem's ElementTetP2/TriP2)."""
    nq = points.shape[1]
    L = np.vstack([1.0 - points.sum(axis=0), points])                  # (dim+1, nq)
    dL = np.vstack([-np.ones(dim), np.eye(dim)])                        # (dim+1, dim): dL_i/dxi_r
    if order == 1:
        return np.repeat(dL[:, :, None], nq, axis=2)
    vert = (4.0 * L - 1.0)[:, None, :] * dL[:, :, None]
    edge = [4.0 * (L[b][None, :] * dL[a][:, None] + L[a][None, :] * dL[b][:, None]) for a, b in SKFEM_EDGES[dim]]
    return np.concatenate([vert, np.stack(edge)], axis=0)


def reference_values(dim: int, order: int, points: np.ndarray) -> np.ndarray:
    """(nloc, nq) reference-element shape-function values at ``points`` (dim, nq), the same Lagrange basis
    and local order as ``reference_gradients``: P1 N_i = L_i; P2 vertex L_i (2 L_i - 1), edge 4 L_a L_b."""
    L = np.vstack([1.0 - points.sum(axis=0), points])                  # (dim+1, nq)
    if order == 1:
        return L
    return np.vstack([L * (2.0 * L - 1.0)] + [4.0 * L[a] * L[b] for a, b in SKFEM_EDGES[dim]])


def quadrature_points(nodes: np.ndarray, geo_dofs: np.ndarray, geo_order: int, points: np.ndarray) -> np.ndarray:
    """(dim, nq, nel) physical positions of the reference ``points`` (dim, nq) under the (curved) element map
    of the geometry nodes ``nodes`` (dim, n) indexed by ``geo_dofs`` (ngeo, nel)."""
    N = reference_values(nodes.shape[0], geo_order, points)
    return np.einsum("kq,cke->cqe", N, nodes[:, geo_dofs])


def _inverse_det(J: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Batched inverse and determinant of J (dim, dim, ...) by cofactors (inv has the same layout)."""
    if J.shape[0] == 2:
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        return np.array([[J[1, 1], -J[0, 1]], [-J[1, 0], J[0, 0]]]) / det, det
    adj = np.empty_like(J)                           # adj[i, j] = cofactor C_ji
    for i in range(3):
        for j in range(3):
            j1, j2, i1, i2 = (j + 1) % 3, (j + 2) % 3, (i + 1) % 3, (i + 2) % 3
            adj[i, j] = J[j1, i1] * J[j2, i2] - J[j1, i2] * J[j2, i1]
    det = J[0, 0] * adj[0, 0] + J[0, 1] * adj[1, 0] + J[0, 2] * adj[2, 0]
    return adj / det, det


def element_geometry(nodes: np.ndarray, element_dofs: np.ndarray, order: int, *, intorder: int | None = None,
                     quadrature: tuple[np.ndarray, np.ndarray] | None = None,
                     geometry: tuple[np.ndarray, int] | None = None, n_dofs: int | None = None) -> ElementGeometry:
    """Quadrature data of the P``order`` Lagrange field on a simplex mesh with (curved) P1/P2 geometry.

    nodes : (dim, n) positions of the geometry nodes; element_dofs : (nloc, nel) field dofs, local
    order as scikit-fem. By default the map is isoparametric (the field's own dofs are the geometry
    nodes); ``geometry=(geo_dofs, geo_order)`` gives other geometry nodes (e.g. P1 field on a P2 mesh).
    ``quadrature=(points, weights)`` overrides scikit-fem's rule of ``intorder`` (default 2(p-1));
    ``n_dofs`` defaults to the number of nodes (isoparametric) or the largest field dof + 1.
    Raises ValueError on a degenerate element (det J = 0)."""
    dim = nodes.shape[0]
    points, weights = quadrature or simplex_quadrature(dim, default_intorder(order) if intorder is None else intorder)
    geo_dofs, geo_order = geometry or (element_dofs, order)
    dG = reference_gradients(dim, geo_order, points)                    # (ngeo, dim, nq)
    ngeo, nel = geo_dofs.shape
    nq = points.shape[1]
    X = nodes[:, geo_dofs].transpose(1, 0, 2).reshape(ngeo, dim * nel)  # (k, c e)
    # J[c, r, q, e] = sum_k X[c, k, e] dG[k, r, q]: one gemm over the local nodes, element last
    J = (dG.reshape(ngeo, dim * nq).T @ X).reshape(dim, nq, dim, nel).transpose(2, 0, 1, 3)
    inv, det = _inverse_det(J)
    if not np.all(det != 0.0):
        raise ValueError("element_geometry: degenerate element (det J = 0)")
    dN = dG if geometry is None else reference_gradients(dim, order, points)
    if n_dofs is None:
        n_dofs = int(nodes.shape[1]) if geometry is None else int(element_dofs.max()) + 1
    return ElementGeometry(dN, inv, np.abs(det) * weights[:, None], element_dofs, n_dofs)


def geometry_of_basis(basis) -> ElementGeometry:
    """The ElementGeometry of a scalar scikit-fem CellBasis (P1/P2 Lagrange element on a MeshTet1/2 or
    MeshTri1/2), on the basis' own quadrature points and weights."""
    mesh, order = basis.mesh, int(basis.elem.maxdeg)
    dim = mesh.dim()
    nloc = (dim + 1) if order == 1 else (dim + 1) * (dim + 2) // 2
    kind = type(mesh).__name__
    if kind not in ("MeshTet1", "MeshTet2", "MeshTri1", "MeshTri2") or order not in (1, 2) \
            or basis.element_dofs.shape[0] != nloc:
        raise ValueError(f"geometry_of_basis: unsupported mesh/element {kind}/{type(basis.elem).__name__}")
    geo = (mesh.dofs.element_dofs, 2) if kind.endswith("2") else (mesh.t, 1)
    return element_geometry(mesh.doflocs, basis.element_dofs, order, quadrature=(basis.X, basis.W), geometry=geo,
                            n_dofs=basis.N)
