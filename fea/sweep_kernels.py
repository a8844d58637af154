"""numba kernels of ``fused_sweeps``: the Gauss-Seidel sweeps that also return the residual / product.

Compiled once per machine (``cache=True``: the first call of a fresh install compiles and stores them,
later processes load them from ``__pycache__``). Imported only when a p-multigrid solve starts, so the
other commands do not pay numba's import.
"""
from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["diagonal_positions", "forward_from_zero", "backward_with_product"]

one = np.uint64(1)

# Indices are read as unsigned: with signed ones numba adds a negative-index wrap-around test to
# every access, which made the plain product 1.7x slower than scipy's (0.144 vs 0.089 s, 1M dofs).


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
    """Position of each row's diagonal entry in the CSR arrays, -1 where a row has none."""
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
