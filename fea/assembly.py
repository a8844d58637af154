"""Vectorised linear-elasticity stiffness and traction loads on scikit-fem bases.

scikit-fem's stock ``asm(linear_elasticity(...))`` evaluates the vector form per component pair and took
38 s / 3.5 GB at 297k P2 dofs on this machine. Here the element matrices come from the SCALAR basis
gradients G (element, point, function, direction) in one batched product

    M_e[(i,a),(j,b)] = sum_q w_q G_ia G_jb,
    K_e = lam M_e + mu M_e^(a<->b) + mu delta_ab sum_c M_e[(i,c),(j,c)],

i.e. the 3x3 blocks of the isotropic Hooke law, and are scattered into a block-sparse (BSR, 3x3)
matrix through one sorted sparsity pattern (np.unique) and nine bincounts. Global dof numbering is
scikit-fem's interleaved vector numbering: dof = dim * scalar_dof + component.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


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


def scalar_basis(mesh, element, *, intorder: int | None = None):
    """scikit-fem CellBasis of the scalar element. P2 default intorder 2: exact for straight-sided
    elements (the integrand is quadratic) and half the cost of the stock order 4."""
    from skfem import Basis
    if intorder is None:
        intorder = 2 * max(element.maxdeg - 1, 1) if element.maxdeg > 1 else 1
    return Basis(mesh, element, intorder=intorder)


def _sparsity(element_dofs: np.ndarray, n: int):
    """Sorted unique (row, col) scalar pattern of all element pairs and each pair's slot in it."""
    nloc, nel = element_dofs.shape
    rows = np.repeat(element_dofs.T, nloc, axis=1).astype(np.int64)      # (nel, nloc*nloc): i-major
    cols = np.tile(element_dofs.T, (1, nloc)).astype(np.int64)
    keys, slot = np.unique((rows * n + cols).ravel(), return_inverse=True)
    indptr = np.searchsorted(keys // n, np.arange(n + 1)).astype(np.int64)
    indices = (keys % n).astype(np.int32)
    return indptr, indices, slot.reshape(nel, nloc * nloc)


def elasticity_stiffness(basis, lame: Lame, *, thickness_mm: float = 1.0, chunk: int = 20000,
                         fmt: str = "csr") -> sp.spmatrix:
    """Global stiffness of isotropic linear elasticity (3D, or 2D with plane-stress ``lame`` and thickness).

    Parameters
    ----------
    basis : scalar scikit-fem CellBasis (P1 or P2, tetra or triangle); its quadrature is used.
    lame : Lame constants (``Lame.from_young(E, nu, plane_stress=True)`` for plane stress).
    thickness_mm : multiplies 2D stiffness (plane stress per unit thickness otherwise).
    fmt : "csr" or "bsr" (3x3 / 2x2 blocks; pyamg uses the block size directly).
    """
    dim = basis.mesh.dim()
    edofs = basis.element_dofs                       # (nloc, nel)
    nloc, nel = edofs.shape
    n = basis.N
    indptr, indices, slot = _sparsity(edofs, n)
    data = np.zeros((indices.size, dim, dim))
    dx = basis.dx                                    # (nel, nq): weights times |det J|
    scale = thickness_mm if dim == 2 else 1.0
    for s in range(0, nel, chunk):
        e = slice(s, min(s + chunk, nel))
        # G: (ne, nq, nloc*dim), row index i*dim + a
        G = np.stack([basis.basis[i][0].grad[:, e, :] for i in range(nloc)], axis=0)   # (nloc, dim, ne, nq)
        G = G.transpose(2, 3, 0, 1).reshape(G.shape[2], G.shape[3], nloc * dim)
        M = np.matmul((G * dx[e][:, :, None]).transpose(0, 2, 1), G)                  # (ne, nld, nld)
        M = M.reshape(-1, nloc, dim, nloc, dim)
        lap = np.einsum("eicjc->eij", M)
        K = lame.lam_MPa * M + lame.mu_MPa * M.transpose(0, 1, 4, 3, 2)
        for a in range(dim):
            K[:, :, a, :, a] += lame.mu_MPa * lap
        K *= scale
        sl = slot[e].ravel()
        Kb = K.transpose(0, 1, 3, 2, 4).reshape(-1, dim, dim)                          # (ne*nloc*nloc, a, b)
        for a in range(dim):
            for b in range(dim):
                data[:, a, b] += np.bincount(sl, weights=Kb[:, a, b], minlength=indices.size)
    K = sp.bsr_matrix((data, indices, indptr), shape=(n * dim, n * dim))
    return K if fmt == "bsr" else K.tocsr()


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
