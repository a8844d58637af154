"""numba kernels of the compiled 3D stiffness path (``assembly.stiffness(..., compiled=True)``).

The numpy path forms every element's pair blocks as one (pairs, ...) array, sorts their keys and sums
equal keys by a sparse product, then mirrors the upper triangle. Here the block pattern of the full
symmetric matrix comes first (node -> element lists, one marker per row, no global sort), then each
element adds its pair blocks straight into their places in the upper triangle, and one pass copies the
transposes below (the matrix is exactly symmetric, as the numpy path's; a diagonal pair's Q is formed on
a <= b and mirrored, so the diagonal blocks are too).

The scatter is bound by cache misses, not arithmetic: so only the upper blocks are added, the elements
are visited by their lowest vertex (the rows they touch are still in cache), and the element geometry is
computed in the kernel from the node positions, not read from ``element_geometry``'s arrays
(docs/decisions/004-assembly-kernels.md).

Compiled once per machine (``cache=True``) and imported only for systems that load numba anyway (the
fused p-multigrid's, ``fused_sweeps.MIN_DOFS``): the small systems keep the numpy path.
"""
from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["block_pattern", "add_upper_elasticity_blocks", "mirror_upper", "condense_blocks_in_place"]


@nb.njit(cache=True, nogil=True)
def _node_elements(element_dofs, n):
    """CSR of the elements of each node (ascending), from (nel, nloc) element dofs."""
    nel, nloc = element_dofs.shape
    ptr = np.zeros(n + 1, np.int64)
    for e in range(nel):
        for k in range(nloc):
            ptr[element_dofs[e, k] + 1] += 1
    for i in range(n):
        ptr[i + 1] += ptr[i]
    fill = ptr[:-1].copy()
    elems = np.empty(ptr[n], np.int64)
    for e in range(nel):
        for k in range(nloc):
            i = element_dofs[e, k]
            elems[fill[i]] = e
            fill[i] += 1
    return ptr, elems


@nb.njit(cache=True, nogil=True, inline="always")
def _neighbours(i, ptr, elems, element_dofs, mark, out, lo):
    """Write the distinct blocks J of row i (J shares an element with i) to out[lo:], in the order met, each
    once (mark[J] = i); returns how many."""
    c = lo
    for p in range(ptr[i], ptr[i + 1]):
        e = elems[p]
        for k in range(element_dofs.shape[1]):
            j = element_dofs[e, k]
            if mark[j] != i:
                mark[j] = i
                out[c] = j
                c += 1
    return c - lo


@nb.njit(cache=True, nogil=True)
def block_pattern(element_dofs, n):
    """(indptr int64, indices int32) of the node-block pattern of (nel, nloc) element dofs: block (I, J)
    where I and J share an element, every row's columns sorted, the diagonal included."""
    nloc = element_dofs.shape[1]
    ptr, elems = _node_elements(element_dofs, n)
    widest = 0
    for i in range(n):
        widest = max(widest, (ptr[i + 1] - ptr[i]) * nloc)
    scratch = np.empty(widest, np.int32)
    mark = np.full(n, -1, np.int64)
    indptr = np.zeros(n + 1, np.int64)
    for i in range(n):
        indptr[i + 1] = indptr[i] + _neighbours(i, ptr, elems, element_dofs, mark, scratch, 0)
    indices = np.empty(indptr[n], np.int32)
    mark[:] = -1
    for i in range(n):
        lo = indptr[i]
        c = lo + _neighbours(i, ptr, elems, element_dofs, mark, indices, lo)
        # insertion sort of the short row: cheaper than a sort call per row (docs/decisions/004-assembly-kernels.md)
        for q in range(lo + 1, c):
            j = indices[q]
            m = q
            while m > lo and indices[m - 1] > j:
                indices[m] = indices[m - 1]
                m -= 1
            indices[m] = j
    return indptr, indices


@nb.njit(cache=True, inline="always")
def _find(indices, lo, hi, j):
    """Position of column j in the sorted indices[lo:hi] (it is there: the pattern holds every pair)."""
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if indices[mid] <= j:
            lo = mid
        else:
            hi = mid
    return lo


@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")   # inlined: as fast as one loop nest
def _element_gradients(X, geo_dofs, e, dG, dN, weights, g, gw, J, adj):
    """One element's physical gradients g (nloc, 3, nq) and their weighted copy gw = w |det J| g, in place;
    returns the number of its quadrature points where det J = 0."""
    nloc, _, nq = dN.shape
    degenerate = 0
    for q in range(nq):
        for c in range(3):
            for r in range(3):
                J[c, r] = 0.0
        for k in range(dG.shape[0]):
            node = geo_dofs[e, k]
            for c in range(3):
                x = X[node, c]
                for r in range(3):
                    J[c, r] += x * dG[k, r, q]
        for i in range(3):                 # adj[i, j] = cofactor C_ji, as element_gradients._inverse_det
            i1, i2 = (i + 1) % 3, (i + 2) % 3
            for j in range(3):
                j1, j2 = (j + 1) % 3, (j + 2) % 3
                adj[i, j] = J[j1, i1] * J[j2, i2] - J[j1, i2] * J[j2, i1]
        det = J[0, 0] * adj[0, 0] + J[0, 1] * adj[1, 0] + J[0, 2] * adj[2, 0]
        if det == 0.0:
            degenerate += 1
        for i in range(3):
            for j in range(3):
                adj[i, j] /= det             # now the inverse, inv[r, a] = dxi_r / dx_a
        w = weights[q] * abs(det)
        for k in range(nloc):
            for a in range(3):
                s = dN[k, 0, q] * adj[0, a] + dN[k, 1, q] * adj[1, a] + dN[k, 2, q] * adj[2, a]
                g[k, a, q] = s
                gw[k, a, q] = w * s
    return degenerate


@nb.njit(cache=True, nogil=True, error_model="numpy")   # numpy's float rules: no zero-division test
def add_upper_elasticity_blocks(X, geo_dofs, dG, dN, weights, element_dofs, lam, mu, indptr, indices, data):
    """Add every element's 3x3 pair blocks of isotropic elasticity into the upper block triangle
    (row <= column) of the BSR ``data`` (nnzb, 3, 3), elements in the order given; returns the number of
    degenerate elements (det J = 0), which add nothing finite.

    The geometry is computed here, element by element, as ``element_gradients.element_geometry`` does
    for all at once (J_cr = sum_k x_ck dG_kr, its inverse by cofactors, g_k = J^-T dN_k): its (3, 3, nq,
    nel) arrays were fresh memory the machine first had to map (docs/decisions/004-assembly-kernels.md).
    X (n, 3) geometry node positions; geo_dofs (nel, ngeo) and dG (ngeo, 3, nq): the map's nodes and
    reference gradients; dN (nloc, 3, nq) the field's; weights (nq,); element_dofs (nel, nloc). Block of
    the local pair (i, j): with Q_ab = sum_q w |det J| g_ia g_jb, K_ij = lam Q + mu Q^T + mu tr(Q) I,
    added at (I, J) if I < J, else K_ij^T at (J, I)."""
    nloc, dim, nq = dN.shape
    nel = element_dofs.shape[0]
    g = np.empty((nloc, 3, nq))
    gw = np.empty((nloc, 3, nq))
    J = np.empty((3, 3))
    adj = np.empty((3, 3))
    Q = np.empty((3, 3))
    degenerate = 0
    for e in range(nel):
        degenerate += _element_gradients(X, geo_dofs, e, dG, dN, weights, g, gw, J, adj)
        for i in range(nloc):
            I = element_dofs[e, i]
            # the diagonal pair: Q on a <= b, mirrored, so its block is exactly symmetric
            for a in range(3):
                for b in range(a, 3):
                    s = 0.0
                    for q in range(nq):
                        s += gw[i, a, q] * g[i, b, q]
                    Q[a, b] = s
                    Q[b, a] = s
            tr = mu * (Q[0, 0] + Q[1, 1] + Q[2, 2])
            p = _find(indices, indptr[I], indptr[I + 1], I)
            for a in range(3):
                for b in range(3):
                    data[p, a, b] += (lam + mu) * Q[a, b]
                data[p, a, a] += tr
            for j in range(i + 1, nloc):
                Jd = element_dofs[e, j]
                for a in range(3):
                    for b in range(3):
                        s = 0.0
                        for q in range(nq):
                            s += gw[i, a, q] * g[j, b, q]
                        Q[a, b] = s
                tr = mu * (Q[0, 0] + Q[1, 1] + Q[2, 2])
                if I < Jd:
                    p = _find(indices, indptr[I], indptr[I + 1], Jd)
                    for a in range(3):
                        for b in range(3):
                            data[p, a, b] += lam * Q[a, b] + mu * Q[b, a]
                        data[p, a, a] += tr
                else:
                    p = _find(indices, indptr[Jd], indptr[Jd + 1], I)
                    for a in range(3):
                        for b in range(3):
                            data[p, b, a] += lam * Q[a, b] + mu * Q[b, a]
                        data[p, a, a] += tr
    return degenerate


@nb.njit(cache=True, nogil=True)
def mirror_upper(indptr, indices, data):
    """Copy each upper block (r, c), c > r, transposed to (c, r). Row c's lower blocks are its first ones,
    in ascending r, so visiting rows r in order fills them front to back."""
    n = indptr.size - 1
    nxt = indptr[:-1].copy()
    for r in range(n):
        for p in range(indptr[r], indptr[r + 1]):
            c = indices[p]
            if c > r:
                m = nxt[c]
                for a in range(3):
                    for b in range(3):
                        data[m, b, a] = data[p, a, b]
                nxt[c] = m + 1


@nb.njit(cache=True, nogil=True)
def condense_blocks_in_place(indptr, indices, data, keep):
    """K[keep][:, keep] of a BSR matrix's node blocks (``solver.condense_blocks``: the same entries in
    the same order), written over the front of its own ``indices`` and ``data`` (a kept block never
    moves back: m <= p), so no fresh memory is mapped for the copy. Returns the
    condensed indptr and its block count m; indices[:m], data[:m] are the condensed arrays."""
    n = indptr.size - 1
    new = np.full(n, -1, np.int64)
    c = 0
    for i in range(n):
        if keep[i]:
            new[i] = c
            c += 1
    out = np.zeros(c + 1, np.int64)
    m = 0
    r = 0
    for i in range(n):
        if not keep[i]:
            continue
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if keep[j]:
                indices[m] = new[j]
                if m != p:
                    for a in range(data.shape[1]):
                        for b in range(data.shape[2]):
                            data[m, a, b] = data[p, a, b]
                m += 1
        r += 1
        out[r] = m
    return out, m


def load() -> None:
    """Load (or on a fresh cache compile) the kernels now, on one tiny element, so that their load does
    not compete for the interpreter lock with whatever runs beside the assembly."""
    dofs = np.arange(10, dtype=np.int64)[None, :]
    indptr, indices = block_pattern(dofs, 10)
    X = np.zeros((10, 3))
    dN = np.zeros((10, 3, 1))
    data = np.zeros((indices.size, 3, 3))
    add_upper_elasticity_blocks(X, dofs, dN, dN, np.ones(1), dofs, 1.0, 1.0, indptr, indices, data)
    mirror_upper(indptr, indices, data)
    # int32 block pointers, as scipy gives a stiffness matrix's: the signature the solver calls
    condense_blocks_in_place(indptr.astype(np.int32), indices, data, np.ones(10, np.bool_))
