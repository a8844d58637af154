"""p-multigrid for quadratic elements: the P2 system's first coarse level is P1 on the same mesh.

Smoothed aggregation struggles with P2 stiffness matrices: their graph mixes vertex and mid-edge
couplings of very different strength. Linear interpolation from the vertices (P1 -> P2, exact for linear
fields) gives a geometric coarse level with 1/7 of the unknowns on which the same aggregation works as
designed (docs/decisions/018-multigrid-settings.md).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

# Local mid-edge dofs of scikit-fem's P2 elements, in element_dofs order after the vertices:
# ElementTetP2 numbers its edges like MeshTet.t2e, ElementTriP2 like MeshTri.t2f.
EDGE_VERTICES = {10: ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)), 6: ((0, 1), (1, 2), (0, 2))}


def p1_prolongation(element_dofs: np.ndarray) -> tuple[sp.csr_matrix, int]:
    """Scalar interpolation P1 -> P2 on one mesh: (n_P2 x n_vertices) and the vertex count.

    Vertex dofs come first in scikit-fem's P2 numbering, so the vertex block is the identity; each
    mid-edge dof takes the mean of its edge's two vertices."""
    nloc = element_dofs.shape[0]
    if nloc not in EDGE_VERTICES:
        raise ValueError(f"p1_prolongation: {nloc} local dofs is not a P2 triangle or tetrahedron")
    nvloc = 4 if nloc == 10 else 3
    n_vert = int(element_dofs[:nvloc].max()) + 1
    n = int(element_dofs.max()) + 1
    mids = np.concatenate([element_dofs[nvloc + k] for k in range(nloc - nvloc)])
    a = np.concatenate([element_dofs[i] for i, _ in EDGE_VERTICES[nloc]])
    b = np.concatenate([element_dofs[j] for _, j in EDGE_VERTICES[nloc]])
    # each mid dof's first occurrence by one reverse scatter (the earliest write lands last): no sort needed
    first = np.full(n, -1, np.int64)
    first[mids[::-1]] = np.arange(mids.size - 1, -1, -1)
    mids = np.flatnonzero(first >= 0)
    first = first[mids]
    rows = np.concatenate([np.arange(n_vert), mids, mids])
    cols = np.concatenate([np.arange(n_vert), a[first], b[first]])
    vals = np.concatenate([np.ones(n_vert), np.full(2 * mids.size, 0.5)])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n_vert)), n_vert


def vector_prolongation(scalar: sp.csr_matrix, dim: int, free: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Interleaved vector prolongation restricted to the free fine dofs and the free coarse dofs.

    A coarse (vertex) dof is free when the same dof of the fine system is free; a mid-edge dof next
    to a fixed vertex keeps only its free neighbour's weight, which is the right interpolation of a
    field that vanishes on the fixed dofs."""
    P = sp.kron(scalar, sp.identity(dim, format="csr"), format="csr")
    n_fine = P.shape[0]
    is_free = np.zeros(n_fine, bool)
    is_free[free] = True
    coarse_free = np.flatnonzero(is_free[:P.shape[1]])       # vertex dofs are the first fine dofs
    return P[free][:, coarse_free].tocsr(), coarse_free


def v_cycle(levels, coarse_solver):
    """One V-cycle from a zero guess over pyamg ``levels`` (A, P, R, pre/postsmoother): a symmetric
    preconditioner r -> z for ``pcg``. pyamg's own ``solve(maxiter=1)`` also computes the residual norm
    before and after every cycle, a large share of the solve (docs/decisions/018-multigrid-settings.md)."""
    last = len(levels) - 1

    def cycle(b: np.ndarray, k: int = 0) -> np.ndarray:
        if k == last:
            return np.asarray(coarse_solver(levels[k].A, b)).reshape(b.shape)
        level = levels[k]
        x = np.zeros_like(b)
        level.presmoother(level.A, x, b)
        x += level.P @ cycle(level.R @ (b - level.A @ x), k + 1)
        level.postsmoother(level.A, x, b)
        return x

    return cycle


def pcg(A, b: np.ndarray, precondition, *, rtol: float, maxiter: int) -> tuple[np.ndarray, int]:
    """Preconditioned conjugate gradients from x = 0, stopping at ||r|| <= rtol ||b|| (the recursive
    residual, as pyamg's cg; the caller checks the true one). Returns (x, iterations); at ``maxiter``
    it returns the last iterate and the caller's residual check reports the failure."""
    x = np.zeros_like(b)
    r = b.copy()
    limit = rtol * np.linalg.norm(b)
    z = precondition(r)
    p = z.copy()
    rz = float(r @ z)
    for it in range(1, maxiter + 1):
        q = A @ p
        alpha = rz / float(p @ q)
        x += alpha * p
        r -= alpha * q
        if np.linalg.norm(r) <= limit:
            return x, it
        z = precondition(r)
        rz_next = float(r @ z)
        p *= rz_next / rz
        p += z
        rz = rz_next
    return x, maxiter


def v_cycle_fused(sweeps, levels, coarse_solver):
    """``v_cycle`` with fused sweeps (``fused_sweeps.FineSweeps`` of ``levels[k].A``, one per level or None
    for pyamg's smoothers there; levels[0] must have one): r -> (z, A z) for ``pcg_with_products``. The
    forward sweep from zero hands back its residual and the backward sweep the product, so a fused level's
    matrix is read twice per cycle instead of three times, and CG needs no product of its own (see
    fused_sweeps)."""
    last = len(levels) - 1

    def cycle(b: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray | None]:
        if k == last:
            return np.asarray(coarse_solver(levels[k].A, b)).reshape(b.shape), None
        level = levels[k]
        fused = sweeps[k] if k < len(sweeps) else None
        if fused is None:
            x = np.zeros_like(b)
            level.presmoother(level.A, x, b)
            x += level.P @ cycle(level.R @ (b - level.A @ x), k + 1)[0]
            level.postsmoother(level.A, x, b)
            return x, None
        x, ux = fused.forward_from_zero(b)
        # the residual b - A x is -U x; the cycle below is linear (and negation exact), so the sign
        # goes onto the correction instead of a negated copy of the vector
        x -= level.P @ cycle(level.R @ ux, k + 1)[0]
        return x, fused.backward(b, x)

    return lambda r: cycle(r, 0)


def pcg_with_products(b: np.ndarray, precondition, *, rtol: float, maxiter: int) -> tuple[np.ndarray, int]:
    """``pcg`` for a preconditioner that also returns A z: r -> (z, A z). The product A p of the search
    direction p = z + beta p_old is A z + beta A p_old, with no pass over A. Its round-off accumulates
    over the iterations like the recursive residual's own (the caller checks the true residual)."""
    x = np.zeros_like(b)
    r = b.copy()
    limit = rtol * np.linalg.norm(b)
    z, q = precondition(r)
    p = z.copy()
    rz = float(r @ z)
    for it in range(1, maxiter + 1):
        alpha = rz / float(p @ q)
        x += alpha * p
        r -= alpha * q
        if np.linalg.norm(r) <= limit:
            return x, it
        z, az = precondition(r)
        rz_next = float(r @ z)
        beta = rz_next / rz
        p *= beta
        p += z
        q *= beta
        q += az
        rz = rz_next
    return x, maxiter
