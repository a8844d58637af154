"""Sum symmetric dim x dim block contributions into a global block-sparse matrix, fast.

Each contribution is one block C of the pair (I, J) of scalar dofs, given by its symmetric part
(C + C^T)/2 (diagonal, then the a < b entries) and its antisymmetric part (C - C^T)/2 (a < b entries).
The global matrix is symmetric, so every contribution is oriented to the upper triangle (I <= J;
a swapped pair contributes C^T, i.e. the antisymmetric part changes sign), summed there and mirrored.

Why not np.unique + bincount: one np.sort of (key << b | index) packed in an int64 is several times faster
than np.argsort here (AVX2 sort), and the sum over equal keys is one sparse 0/1 matrix times the (m, k)
contribution array, which scipy does in one C pass (docs/decisions/004-assembly-kernels.md).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def component_pairs(dim: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """(a, b) of the symmetric components (diagonal first, then a < b) and of the antisymmetric ones."""
    off = [(a, b) for a in range(dim) for b in range(a + 1, dim)]
    return [(a, a) for a in range(dim)] + off, off


def split_matrix(dim: int) -> np.ndarray:
    """(dim^2, n_sym + n_anti) map from a row-major flattened block to its [sym, anti] components."""
    sym, anti = component_pairs(dim)
    M = np.zeros((dim * dim, len(sym) + len(anti)))
    for c, (a, b) in enumerate(sym):
        M[a * dim + b, c] += 0.5
        M[b * dim + a, c] += 0.5
    for c, (a, b) in enumerate(anti):
        M[a * dim + b, len(sym) + c] = 0.5
        M[b * dim + a, len(sym) + c] = -0.5
    return M


def sorted_groups(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stable sort of non-negative int64 keys (OVERWRITTEN): (order, group starts in sorted order, unique
    keys). In place where it can: fresh memory costs page faults the sort itself does not
    (docs/decisions/004-assembly-kernels.md)."""
    m = keys.size
    bits = max(int(m - 1).bit_length(), 1)
    top = int(keys.max()) if m else 0
    if top.bit_length() + bits <= 63:
        packed = keys
        packed <<= bits
        packed |= np.arange(m, dtype=np.int64)   # the index breaks ties: a stable sort
        packed.sort()
        order = packed & ((1 << bits) - 1)
        skeys = packed
        skeys >>= bits
    else:                                        # too many dofs to pack: plain (slower) argsort
        order = np.argsort(keys, kind="stable")
        skeys = keys[order]
    new = np.empty(m, bool)
    new[:1] = True
    np.not_equal(skeys[1:], skeys[:-1], out=new[1:])
    starts = np.flatnonzero(new)
    return order, starts, skeys[starts]


def pair_keys(I: np.ndarray, J: np.ndarray, n: int) -> np.ndarray:
    """int64 key min(I, J) * n + max(I, J) of the upper-triangle block of each pair."""
    keys = np.minimum(I, J).astype(np.int64)
    keys *= n
    keys += np.maximum(I, J)
    return keys


def _block_map(dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Maps (n_sym, dim^2), (n_anti, dim^2) from [sym, anti] components to the row-major block."""
    ps, pa = component_pairs(dim)
    Ms, Ma = np.zeros((len(ps), dim * dim)), np.zeros((len(pa), dim * dim))
    for c, (a, b) in enumerate(ps):
        Ms[c, a * dim + b] = Ms[c, b * dim + a] = 1.0
    for c, (a, b) in enumerate(pa):
        Ma[c, a * dim + b], Ma[c, b * dim + a] = 1.0, -1.0
    return Ms, Ma


def orient(I: np.ndarray, J: np.ndarray, W: np.ndarray, n_sym: int) -> None:
    """Orient contributions to the upper triangle, in place: a swapped pair (I > J) contributes C^T, so
    its antisymmetric part changes sign; a diagonal pair's C is symmetric (its antisymmetric part is
    round-off only) and is zeroed, so the diagonal blocks come out exactly symmetric.
    I, J : (...) dofs; W : (..., n_sym + n_anti) [sym, anti] components."""
    W[..., n_sym:] *= np.sign(np.subtract(J, I, dtype=np.int64)).astype(W.dtype)[..., None]


def upper_blocks(keys: np.ndarray, W: np.ndarray, n: int, dim: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sum ORIENTED block contributions (``orient``) into the upper block triangle.

    keys : (m,) ``pair_keys`` of each contribution (OVERWRITTEN; of a pair (I, J) / (J, I) of the same
    element only one is given). W : (m, n_sym + n_anti) [sym, anti] components (``component_pairs``)
    of the block of (min(I, J), max(I, J)). Returns the (row, col)-sorted block rows <= cols and the
    summed blocks B (nb, dim, dim)."""
    order, starts, ukeys = sorted_groups(keys)
    m = order.size
    itype = np.int32 if m < 2 ** 31 else np.int64     # scipy's own choice: no copy in the constructor
    order = order.astype(itype)
    S = sp.csr_matrix((np.ones(m), order, np.append(starts, m).astype(itype)), shape=(starts.size, m))
    del order, starts
    B = S @ W                                         # (nb, n_sym + n_anti)
    del S
    Ms, Ma = _block_map(dim)
    M = np.vstack([Ms, Ma])
    for r in range(0, B.shape[0], 1 << 16):          # to row-major blocks in place: no second (nb, 9)
        B[r:r + (1 << 16)] = B[r:r + (1 << 16)] @ M
    return ukeys // n, ukeys % n, B.reshape(-1, dim, dim)


def assemble_symmetric(I: np.ndarray, J: np.ndarray, W: np.ndarray, n: int, dim: int,
                       fmt: str = "csr") -> sp.spmatrix:
    """The symmetric matrix of unoriented contributions: ``orient`` (W is overwritten), ``upper_blocks``,
    ``symmetric_matrix``."""
    orient(I, J, W, len(component_pairs(dim)[0]))
    K = symmetric_matrix(*upper_blocks(pair_keys(I, J, n), W, n, dim), n, dim)
    return K if fmt == "bsr" else K.tocsr()


def symmetric_matrix(rows: np.ndarray, cols: np.ndarray, B: np.ndarray, n: int, dim: int) -> sp.bsr_matrix:
    """The full symmetric (n*dim square, interleaved dofs) BSR matrix of an upper block triangle.

    rows <= cols, sorted by (row, col), B (nb, dim, dim): as ``upper_blocks`` returns them. For the CSR,
    drop them before calling ``.tocsr()``, the peak of the memory. Block row r of the full matrix is its lower
    part (the transposed upper blocks of column r: all left of the diagonal) followed by its upper part,
    so the full block matrix is two block scatters, no merge; then scipy's C++ bsr -> csr.
    Faster than scipy's U + U^T or numpy writing the CSR rows directly (docs/decisions/004-assembly-kernels.md)."""
    strict = np.flatnonzero(rows < cols)
    n_up = np.bincount(rows, minlength=n)
    n_lo = np.bincount(cols[strict], minlength=n)
    bptr = np.zeros(n + 1, np.int64)
    np.cumsum(n_up + n_lo, out=bptr[1:])
    up_first = np.zeros(n + 1, np.int64)
    np.cumsum(n_up, out=up_first[1:])
    pos_up = bptr[rows] + n_lo[rows] + (np.arange(rows.size) - up_first[rows])
    # the transposed copies in (col, row) order: a stable sort of the strict upper blocks by column
    lo_order, lo_starts, lo_rows = sorted_groups(cols[strict])
    src = strict[lo_order]
    count = np.diff(np.append(lo_starts, src.size))
    pos_lo = np.repeat(bptr[lo_rows] - lo_starts, count) + np.arange(src.size)
    nb = int(bptr[-1])
    itype = np.int32 if nb < 2 ** 31 else np.int64
    data = np.empty((nb, dim, dim))
    indices = np.empty(nb, itype)
    data[pos_up] = B
    indices[pos_up] = cols
    data[pos_lo] = B[src].transpose(0, 2, 1)
    indices[pos_lo] = rows[src]
    return sp.bsr_matrix((data, indices, bptr.astype(itype)), shape=(n * dim, n * dim))
