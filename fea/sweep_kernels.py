"""numba kernels of ``fused_sweeps``: the Gauss-Seidel sweeps that also return the residual / product.

Compiled once per machine (``cache=True``: the first call of a fresh install compiles and stores them,
later processes load them from ``__pycache__``). Imported only when a p-multigrid solve starts, so the
other commands do not pay numba's import.
"""
from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["diagonal_positions", "forward_from_zero", "backward_with_product",
           "block_forward_from_zero", "block_backward_with_product"]

one = np.uint64(1)

# Indices are read as unsigned: signed ones make numba test for wrap-around at every access (docs/decisions/006-fused-sweeps.md).


@nb.njit(cache=True, inline="always")
def dot_up(data, indices, x, lo, hi):
    """sum of data[k] x[indices[k]] for k in [lo, hi), four partial sums, addresses ascending."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    s3 = 0.0
    k = lo
    while k + np.uint64(3) < hi:
        s0 += data[k] * x[np.uint64(indices[k])]
        s1 += data[k + one] * x[np.uint64(indices[k + one])]
        s2 += data[k + np.uint64(2)] * x[np.uint64(indices[k + np.uint64(2)])]
        s3 += data[k + np.uint64(3)] * x[np.uint64(indices[k + np.uint64(3)])]
        k += np.uint64(4)
    while k < hi:
        s0 += data[k] * x[np.uint64(indices[k])]
        k += one
    return (s0 + s1) + (s2 + s3)


@nb.njit(cache=True, inline="always")
def dot_down(data, indices, x, lo, hi):
    """The same sum over k in [lo, hi) with addresses descending (k from hi - 1 down to lo)."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    s3 = 0.0
    k = hi
    while k >= lo + np.uint64(4):
        s0 += data[k - one] * x[np.uint64(indices[k - one])]
        s1 += data[k - np.uint64(2)] * x[np.uint64(indices[k - np.uint64(2)])]
        s2 += data[k - np.uint64(3)] * x[np.uint64(indices[k - np.uint64(3)])]
        s3 += data[k - np.uint64(4)] * x[np.uint64(indices[k - np.uint64(4)])]
        k -= np.uint64(4)
    while k > lo:
        k -= one
        s0 += data[k] * x[np.uint64(indices[k])]
    return (s0 + s1) + (s2 + s3)


@nb.njit(cache=True)
def diagonal_positions(indptr, indices):
    """Position of each row's diagonal entry in the CSR arrays, -1 where a row has none (of a BSR matrix's
    block-row arrays: each block row's diagonal block)."""
    n = indptr.size - 1
    out = np.full(n, -1, np.int64)
    for i in range(n):
        for k in range(indptr[i], indptr[i + 1]):
            if indices[k] == i:
                out[i] = k
                break
    return out


@nb.njit(cache=True)
def forward_from_zero(indptr, indices, data, diag, b, x, ux):
    """x = (D + L)^-1 b, a forward Gauss-Seidel sweep from x = 0; ux += U x (A symmetric)."""
    for i in range(b.size):
        lo = np.uint64(indptr[i])
        dk = np.uint64(diag[i])
        xi = (b[i] - dot_up(data, indices, x, lo, dk)) / data[dk]
        x[i] = xi
        k = lo
        while k < dk:
            ux[np.uint64(indices[k])] += data[k] * xi
            k += one


@nb.njit(cache=True)
def backward_with_product(indptr, indices, data, diag, b, x, ax):
    """A backward Gauss-Seidel sweep on x in place; ax += A x of the result (A symmetric)."""
    n = b.size
    for m in range(n):
        i = n - 1 - m
        lo = np.uint64(indptr[i])
        dk = np.uint64(diag[i])
        hi = np.uint64(indptr[i + 1])
        upper = dot_down(data, indices, x, dk + one, hi)      # final values: (U x)_i
        lower = dot_down(data, indices, x, lo, dk)            # values before this sweep
        d = data[dk]
        xi = (b[i] - upper - lower) / d
        x[i] = xi
        ax[i] += upper + d * xi
        k = hi
        while k > dk + one:                                    # (L x)_j += a_ji x_i, j > i
            k -= one
            ax[np.uint64(indices[k])] += data[k] * xi


# The same sweeps over 3x3 node blocks (BSR): one column index per block instead of nine, so 8.4 instead
# of 12 bytes read per entry, and no CSR copy of the matrix (docs/decisions/006-fused-sweeps.md).
# The three rows of a node are swept together: one read of each block serves them, nine partial sums
# (row x column of the block) keep the addition chains short, and the node's own 3x3 diagonal block is
# swept row by row as pointwise Gauss-Seidel does.


@nb.njit(cache=True, inline="always")
def block_rows_dot(data, indices, x, lo, hi, ascending):
    """(s0, s1, s2): the three block rows over blocks [lo, hi) times x, each row's sum in three parts."""
    s00 = 0.0
    s01 = 0.0
    s02 = 0.0
    s10 = 0.0
    s11 = 0.0
    s12 = 0.0
    s20 = 0.0
    s21 = 0.0
    s22 = 0.0
    m = lo
    while m < hi:
        k = m if ascending else hi - one - (m - lo)
        j = np.uint64(3) * np.uint64(indices[k])
        x0 = x[j]
        x1 = x[j + one]
        x2 = x[j + np.uint64(2)]
        q = np.uint64(9) * k
        s00 += data[q] * x0
        s01 += data[q + one] * x1
        s02 += data[q + np.uint64(2)] * x2
        s10 += data[q + np.uint64(3)] * x0
        s11 += data[q + np.uint64(4)] * x1
        s12 += data[q + np.uint64(5)] * x2
        s20 += data[q + np.uint64(6)] * x0
        s21 += data[q + np.uint64(7)] * x1
        s22 += data[q + np.uint64(8)] * x2
        m += one
    return (s00 + s01) + s02, (s10 + s11) + s12, (s20 + s21) + s22


@nb.njit(cache=True, inline="always")
def block_scatter_transposed(data, indices, y, lo, hi, x0, x1, x2, ascending):
    """y[block column] += B^T (x0, x1, x2) for each block B in [lo, hi): the symmetric partner's product."""
    m = lo
    while m < hi:
        k = m if ascending else hi - one - (m - lo)
        j = np.uint64(3) * np.uint64(indices[k])
        q = np.uint64(9) * k
        y[j] += data[q] * x0 + data[q + np.uint64(3)] * x1 + data[q + np.uint64(6)] * x2
        y[j + one] += data[q + one] * x0 + data[q + np.uint64(4)] * x1 + data[q + np.uint64(7)] * x2
        y[j + np.uint64(2)] += data[q + np.uint64(2)] * x0 + data[q + np.uint64(5)] * x1 + data[q + np.uint64(8)] * x2
        m += one


@nb.njit(cache=True)
def block_forward_from_zero(indptr, indices, data, diag, b, x, ux):
    """``forward_from_zero`` over 3x3 blocks (``data`` the flat block array): x = (D + L)^-1 b, ux = U x."""
    nodes = indptr.size - 1
    for i in range(nodes):
        lo = np.uint64(indptr[i])
        dk = np.uint64(diag[i])
        r = np.uint64(3 * i)
        s0, s1, s2 = block_rows_dot(data, indices, x, lo, dk, True)
        q = np.uint64(9) * dk
        x0 = (b[r] - s0) / data[q]
        x1 = (b[r + one] - (s1 + data[q + np.uint64(3)] * x0)) / data[q + np.uint64(4)]
        x2 = (b[r + np.uint64(2)] - (s2 + data[q + np.uint64(6)] * x0 + data[q + np.uint64(7)] * x1)) / data[q + np.uint64(8)]
        x[r] = x0
        x[r + one] = x1
        x[r + np.uint64(2)] = x2
        # U x of this node's rows: its later rows' lower entries (in the diagonal block and below) add to it
        ux[r] = data[q + one] * x1 + data[q + np.uint64(2)] * x2
        ux[r + one] = data[q + np.uint64(5)] * x2
        ux[r + np.uint64(2)] = 0.0
        block_scatter_transposed(data, indices, ux, lo, dk, x0, x1, x2, True)


@nb.njit(cache=True)
def block_backward_with_product(indptr, indices, data, diag, b, x, ax):
    """``backward_with_product`` over 3x3 blocks: backward sweep on x in place, ax = A x of the result."""
    nodes = indptr.size - 1
    for m in range(nodes):
        i = nodes - 1 - m
        lo = np.uint64(indptr[i])
        dk = np.uint64(diag[i])
        hi = np.uint64(indptr[i + 1])
        r = np.uint64(3 * i)
        u0, u1, u2 = block_rows_dot(data, indices, x, dk + one, hi, False)     # final values
        l0, l1, l2 = block_rows_dot(data, indices, x, lo, dk, False)           # values before the sweep
        q = np.uint64(9) * dk
        d = data[q:q + np.uint64(9)]
        o0 = x[r]
        o1 = x[r + one]
        x2 = (b[r + np.uint64(2)] - (l2 + u2 + d[6] * o0 + d[7] * o1)) / d[8]
        x1 = (b[r + one] - (l1 + u1 + d[3] * o0 + d[5] * x2)) / d[4]
        x0 = (b[r] - (l0 + u0 + d[1] * x1 + d[2] * x2)) / d[0]
        x[r] = x0
        x[r + one] = x1
        x[r + np.uint64(2)] = x2
        ax[r] = u0 + (d[0] * x0 + d[1] * x1 + d[2] * x2)
        ax[r + one] = u1 + (d[3] * x0 + d[4] * x1 + d[5] * x2)
        ax[r + np.uint64(2)] = u2 + (d[6] * x0 + d[7] * x1 + d[8] * x2)
        block_scatter_transposed(data, indices, ax, dk + one, hi, x0, x1, x2, False)
