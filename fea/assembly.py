"""Vectorised linear-elasticity stiffness and traction loads.

scikit-fem's stock ``asm(linear_elasticity(...))`` evaluates the vector form per component pair, too slow
and too large at 3D P2 sizes (docs/decisions/004-assembly-kernels.md). Here, with Q_ab = sum_q w g_ia g_jb the 3x3 outer
product of the SCALAR basis gradients of the local pair (i, j), the stiffness block of the pair is the
isotropic Hooke law

    K_ij = lam Q + mu Q^T + mu tr(Q) I,

(K_e[(i,a),(j,b)] = int lam d_a phi_i d_b phi_j + mu d_b phi_i d_a phi_j + mu delta_ab grad phi_i . grad phi_j).
Only the pairs i <= j are formed (the matrix is symmetric, ``block_scatter`` mirrors it), and not per
element by a small matmul: with g = J^-T dN, Q = sum_{q,r,s} [dN_ir dN_js](q) [w |det J| inv_ra inv_sb](q,e)
is ONE gemm of a constant (pairs x q r s) matrix with the per-element geometry tensor, for every
element and component at once; the Lame combination and the split into symmetric / antisymmetric parts
(for the orientation of the global pair) are a fixed (dim^2 x dim^2) map folded into that tensor.
Global dof numbering is scikit-fem's interleaved vector numbering: dof = dim * scalar_dof + component.

The per-element matmul + np.unique + 9 bincounts it replaces was several times slower
(docs/decisions/004-assembly-kernels.md).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp

from strainwave.fea.block_scatter import component_pairs, orient, pair_keys, split_matrix, symmetric_matrix, upper_blocks
from strainwave.fea.element_gradients import (ElementGeometry, default_intorder, element_geometry, geometry_of_basis,
                                              quadrature_points, reference_gradients, simplex_quadrature)


@dataclass(frozen=True)
class Lame:
    lam_MPa: float
    mu_MPa: float

    @classmethod
    def from_young(cls, youngs_modulus_MPa: float, poisson_ratio: float, *, plane_stress: bool = False) -> "Lame":
        """Lame constants; plane stress replaces lambda by 2 lam mu / (lam + 2 mu) = E nu / (1 - nu^2)."""
        E, nu = youngs_modulus_MPa, poisson_ratio
        mu = E / (2.0 * (1.0 + nu))
        lam = E * nu / (1.0 - nu ** 2) if plane_stress else E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
        return cls(lam, mu)


@dataclass(frozen=True)
class ThermalStrain:
    """Isotropic thermal (initial) strain eps_th = alpha dT I over the stress-free reference temperature.

    temperature_rise_K : x (dim, ...) in mm -> dT (...) in K (or deg C: a difference), at any points.
    """

    alpha_per_K: float
    temperature_rise_K: Callable[[np.ndarray], np.ndarray]

    def stress_per_K(self, lame: Lame, dim: int) -> float:
        """c in C eps_th = c dT I: (3 lam + 2 mu) alpha = E alpha / (1 - 2 nu) in 3D; in 2D with plane-stress
        ``lame`` (the project's only 2D model) (2 lam* + 2 mu) alpha = E alpha / (1 - nu)."""
        return (dim * lame.lam_MPa + 2.0 * lame.mu_MPa) * self.alpha_per_K

    def rise_at(self, x: np.ndarray) -> np.ndarray:
        """dT at the points x (dim, ...), broadcast to their shape (a uniform rise may return a scalar)."""
        return np.broadcast_to(np.asarray(self.temperature_rise_K(x), float), x.shape[1:])


def thermal_load(nodes: np.ndarray, element_dofs: np.ndarray, order: int, lame: Lame, thermal: ThermalStrain, *,
                 thickness_mm: float = 1.0, intorder: int | None = None, chunk: int = 4096) -> np.ndarray:
    """Consistent load of a thermal strain, f = int B^T C eps_th dV, interleaved (dim * n_dofs,).

    For isotropic C, C eps_th = c dT I, so f_(i,a) = int c dT d(phi_i)/dx_a dV. Isoparametric P1/P2 simplex
    mesh: ``nodes`` (dim, n) and ``element_dofs`` (nloc, nel) as ``element_gradients.element_geometry``'s;
    dT is evaluated at the quadrature points (the stiffness' rule unless ``intorder``, so that a uniform
    rise is reproduced to round-off). 2D: plane stress, times ``thickness_mm``."""
    dim = nodes.shape[0]
    points, weights = simplex_quadrature(dim, default_intorder(order) if intorder is None else intorder)
    coef = thermal.stress_per_K(lame, dim) * (thickness_mm if dim == 2 else 1.0)
    n_dofs = nodes.shape[1]
    f = np.zeros(dim * n_dofs)
    for s in range(0, element_dofs.shape[1], chunk):
        edofs = element_dofs[:, s:s + chunk]
        geom = element_geometry(nodes, edofs, order, quadrature=(points, weights), n_dofs=n_dofs)
        dT = thermal.rise_at(quadrature_points(nodes, edofs, order, points))          # (nq, ne)
        fe = np.einsum("kaqe,qe->kae", geom.grad, coef * dT * geom.dx)                  # (nloc, dim, ne)
        rows = dim * edofs[:, None, :] + np.arange(dim)[None, :, None]
        f += np.bincount(rows.ravel(), weights=fe.ravel(), minlength=f.size)
    return f


def scalar_basis(mesh, element, *, intorder: int | None = None):
    """scikit-fem CellBasis of the scalar element. P2 default intorder 2: exact for straight-sided
    elements (the integrand is quadratic) and half the cost of the stock order 4."""
    from skfem import Basis
    if intorder is None:
        intorder = 2 * max(element.maxdeg - 1, 1) if element.maxdeg > 1 else 1
    return Basis(mesh, element, intorder=intorder)


def lame_map(lame: Lame, dim: int) -> np.ndarray:
    """(dim^2, dim^2) map of the row-major flattened Q to K = lam Q + mu Q^T + mu tr(Q) I (row vectors)."""
    L = np.zeros((dim * dim, dim * dim))
    for a in range(dim):
        for b in range(dim):
            L[a * dim + b, a * dim + b] += lame.lam_MPa
            L[a * dim + b, b * dim + a] += lame.mu_MPa
        for c in range(dim):
            L[c * dim + c, a * dim + a] += lame.mu_MPa
    return L


def stiffness(geom: ElementGeometry, lame: Lame, *, thickness_mm: float = 1.0, chunk: int = 4096,
              fmt: str = "csr") -> sp.spmatrix:
    """Global stiffness of isotropic linear elasticity (3D, or 2D with plane-stress ``lame`` and thickness)
    from the quadrature data of a P1/P2 simplex mesh. ``chunk`` elements at a time (memory ~ 3 kB each);
    fmt "csr" or "bsr" (dim x dim blocks). ``compiled_stiffness`` is the 3D path of systems that load
    numba anyway."""
    dim, nq = geom.dim, geom.dx.shape[0]
    edofs = geom.element_dofs
    nloc, nel = edofs.shape
    iu, ju = np.triu_indices(nloc)
    npair, nrs = iu.size, nq * dim * dim
    # R[p, (q, r, s)] = dN_{i_p r}(q) dN_{j_p s}(q): the reference part of Q, the same for every element
    R = np.einsum("prq,psq->pqrs", geom.dN[iu], geom.dN[ju]).reshape(npair, nrs)
    fold = lame_map(lame, dim) @ split_matrix(dim) * (thickness_mm if dim == 2 else 1.0)   # (dim^2, k)
    k, n_sym = fold.shape[1], len(component_pairs(dim)[0])
    m = npair * nel
    W = np.empty((m, k))
    keys = np.empty(m, np.int64)
    for s in range(0, nel, chunk):
        e = slice(s, min(s + chunk, nel))
        ne = e.stop - e.start
        rows = slice(s * npair, (s + ne) * npair)                              # chunk-major, then pair
        A = (geom.inv[..., e] * geom.dx[:, e]).transpose(2, 0, 3, 1)           # (q, r, e, a)
        B = geom.inv[..., e].transpose(2, 0, 3, 1)                              # (q, s, e, b)
        T = (A[:, :, None, :, :, None] * B[:, None, :, :, None, :]).reshape(nrs * ne, dim * dim)
        np.matmul(R, (T @ fold).reshape(nrs, ne * k), out=W[rows].reshape(npair, ne * k))
        I, J = edofs[iu, e], edofs[ju, e]                                      # (npair, ne)
        keys[rows] = pair_keys(I, J, geom.n_dofs).ravel()
        orient(I, J, W[rows].reshape(npair, ne, k), n_sym)                      # while in cache
    rows, cols, blocks = upper_blocks(keys, W, geom.n_dofs, dim)
    del W, keys                                    # the peak is in the mirror: free what we can first
    K = symmetric_matrix(rows, cols, blocks, geom.n_dofs, dim)
    del rows, cols, blocks
    return K if fmt == "bsr" else K.tocsr()


def compiled_stiffness(nodes: np.ndarray, element_dofs: np.ndarray, order: int, lame: Lame, *,
                       geometry: tuple[np.ndarray, int] | None = None, intorder: int | None = None,
                       n_dofs: int | None = None) -> sp.bsr_matrix:
    """The 3D stiffness in 3x3 node blocks by ``assembly_kernels``, straight from the mesh: the arguments
    as ``element_gradients.element_geometry``'s (nodes (3, n), element_dofs (nloc, nel), the field's
    order, ``geometry=(geo_dofs, geo_order)`` for a non-isoparametric map). The same matrix as
    ``stiffness(element_geometry(...))`` to round-off (summation order), with the same sorted pattern and
    exact symmetry. Raises ValueError on a degenerate element (det J = 0)."""
    from strainwave.fea import assembly_kernels as k
    if nodes.shape[0] != 3:
        raise ValueError(f"compiled_stiffness: 3D only, got dim {nodes.shape[0]}")
    points, weights = simplex_quadrature(3, default_intorder(order) if intorder is None else intorder)
    geo_dofs, geo_order = geometry or (element_dofs, order)
    dG = reference_gradients(3, geo_order, points)
    dN = dG if geometry is None else reference_gradients(3, order, points)
    if n_dofs is None:
        n_dofs = int(nodes.shape[1]) if geometry is None else int(element_dofs.max()) + 1
    # elements by their lowest vertex (the vertices come first in the local order): see assembly_kernels
    order_e = np.argsort(element_dofs[:4].min(axis=0), kind="stable")
    edofs = np.ascontiguousarray(element_dofs.T[order_e], dtype=np.int64)
    gdofs = edofs if geometry is None else np.ascontiguousarray(geo_dofs.T[order_e], dtype=np.int64)
    indptr, indices = k.block_pattern(edofs, n_dofs)
    data = np.zeros((indices.size, 3, 3))
    degenerate = k.add_upper_elasticity_blocks(np.ascontiguousarray(nodes.T, dtype=float), gdofs,
                                               np.ascontiguousarray(dG), np.ascontiguousarray(dN),
                                               np.ascontiguousarray(weights, dtype=float), edofs,
                                               float(lame.lam_MPa), float(lame.mu_MPa), indptr, indices, data)
    if degenerate:
        raise ValueError("element_geometry: degenerate element (det J = 0)")
    k.mirror_upper(indptr, indices, data)
    itype = np.int32 if indices.size < 2 ** 31 else np.int64
    K = sp.bsr_matrix((data, indices.astype(itype, copy=False), indptr.astype(itype)),
                      shape=(3 * n_dofs, 3 * n_dofs))
    K.has_sorted_indices = True
    return K


def elasticity_stiffness(basis, lame: Lame, *, thickness_mm: float = 1.0, chunk: int = 4096,
                         fmt: str = "csr") -> sp.spmatrix:
    """``stiffness`` on a scalar scikit-fem CellBasis (P1/P2 simplex, its quadrature is used).

    Parameters
    ----------
    basis : scalar scikit-fem CellBasis (P1 or P2, tetra or triangle, MeshTet1/2 or MeshTri1/2).
    lame : Lame constants (``Lame.from_young(E, nu, plane_stress=True)`` for plane stress).
    thickness_mm : multiplies 2D stiffness (plane stress per unit thickness otherwise).
    fmt : "csr" or "bsr" (3x3 / 2x2 blocks; pyamg uses the block size directly).
    """
    return stiffness(geometry_of_basis(basis), lame, thickness_mm=thickness_mm, chunk=chunk, fmt=fmt)


def vector_basis_of(basis):
    """The vector (dim-component) CellBasis on the same mesh and quadrature as ``basis``."""
    from skfem import Basis, ElementVector
    return Basis(basis.mesh, ElementVector(basis.elem), quadrature=basis.quadrature)


def facet_vector_basis(mesh, element, facets: np.ndarray, *, intorder: int = 4):
    """Vector FacetBasis on the given boundary facets (for tractions and face averages)."""
    from skfem import ElementVector, FacetBasis
    return FacetBasis(mesh, ElementVector(element), facets=facets, intorder=intorder)


def traction_load(fbasis, traction) -> np.ndarray:
    """Consistent load vector f_i = int_Gamma t(x) . v_i dA of a traction field.

    traction : callable x -> t, x of shape (dim, nfacets, nq) in mm, t in MPa of the same shape.
    """
    from skfem import LinearForm
    from skfem.helpers import dot

    @LinearForm
    def form(v, w):
        return dot(traction(w.x), v)

    return form.assemble(fbasis)
