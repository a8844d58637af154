"""The p-multigrid's fine level in two passes over the matrix per CG iteration instead of four.

A CG iteration with the V-cycle (forward Gauss-Seidel from zero, residual, coarse correction, backward
Gauss-Seidel; then the CG product A p) read the fine matrix four times (docs/decisions/006-fused-sweeps.md).
Two facts of a symmetric matrix A = L + D + U (U = L^T) remove two of those passes:

- a forward sweep from x = 0 reads only L and solves (D + L) x = b, so the residual b - A x is -U x;
  and since row i's lower entries are column i's upper ones, U x is gathered by scattering each new x_i
  down its row's lower entries while they are in cache;
- the backward sweep reads each row's upper entries at their final values, which is (U z)_i; scattering
  z_i down the same entries gives (L z), so A z costs no pass of its own, and CG's A p follows from
  A p = A z + beta A p_old.

The sums run in four interleaved partial sums: one chain of dependent additions per row is what bounded
the plain loop (a row of ~80 entries, ~4 cycles per addition), not memory. The backward sweep walks the
arrays from the end to the start (rows and entries) so that every stream runs one way, as the hardware
prefetcher wants (pyamg's backward sweep, rows backwards and entries forwards, is much slower than its
forward one). The sums differ from pyamg's and scipy's only in their order (round-off), so the V-cycle
is the same preconditioner.

The kernels are ``sweep_kernels`` (numba).
"""
from __future__ import annotations

import threading

import numpy as np
import scipy.sparse as sp

__all__ = ["FineSweeps", "MIN_DOFS", "warm_up", "warm_up_assembly"]

# Free dofs from which the fused fine level repays numba's load (docs/decisions/006-fused-sweeps.md).
MIN_DOFS = 100_000

def _kernels():
    """The compiled kernels, imported on first use."""
    _join_warm_up()
    from strainwave.fea import sweep_kernels
    return sweep_kernels


_warm_thread: threading.Thread | None = None
_assembly_thread: threading.Thread | None = None


def warm_up() -> None:
    """Load numba and the kernels in a background thread, once per process.

    With the kernels cached on disk, numba's import and its first-call registries are all Python, holding the
    global lock. ``static.solve_static`` starts it once the assembly's own numba kernels are loaded (they run
    without the lock, so the two overlap), the bearing study before its assembly, for systems that will
    take the fused path; started beside gmsh's setOrder instead it was not faster (docs/decisions/006-fused-sweeps.md)."""
    global _warm_thread
    if _warm_thread is None:
        _warm_thread = threading.Thread(target=_call_each_kernel, name="strainwave-sweep-warm-up", daemon=True)
        _warm_thread.start()


def warm_up_assembly() -> None:
    """Load the assembly's kernels (``assembly_kernels.load``) in a background thread, once per process.

    The mesher starts it beside gmsh's setOrder (C++, the interpreter lock released) for a tetrahedral mesh
    that will reach MIN_DOFS, so that the assembly finds them loaded instead of paying their load itself;
    ``static.load_assembly_kernels`` waits for the import if it is still running (docs/decisions/006-fused-sweeps.md)."""
    global _assembly_thread
    if _assembly_thread is None:
        _assembly_thread = threading.Thread(target=_load_assembly_kernels, name="strainwave-assembly-warm-up",
                                            daemon=True)
        _assembly_thread.start()


def _load_assembly_kernels() -> None:
    try:
        from strainwave.fea import assembly_kernels
        assembly_kernels.load()
    except Exception:     # noqa: BLE001 - a failure here shows again, with its traceback, in the assembly
        pass


def _join_warm_up() -> None:
    thread = _warm_thread
    if thread is not None and thread is not threading.current_thread():
        thread.join()


def _call_each_kernel() -> None:
    try:
        from strainwave.fea import sweep_kernels as k
        A = sp.csr_matrix(np.array([[2.0, -1.0], [-1.0, 2.0]]))
        b = np.ones(2)
        x, ux, ax = np.zeros(2), np.zeros(2), np.zeros(2)
        diag = k.diagonal_positions(A.indptr, A.indices)
        k.forward_from_zero(A.indptr, A.indices, A.data, diag, b, x, ux)
        k.backward_with_product(A.indptr, A.indices, A.data, diag, b, x, ax)
        Ab = sp.bsr_matrix(np.eye(6) * 2.0, blocksize=(3, 3))        # the node-block kernels
        b, x, ux, ax = np.ones(6), np.zeros(6), np.zeros(6), np.zeros(6)
        diag = k.diagonal_positions(Ab.indptr, Ab.indices)
        k.block_forward_from_zero(Ab.indptr, Ab.indices, Ab.data.reshape(-1), diag, b, x, ux)
        k.block_backward_with_product(Ab.indptr, Ab.indices, Ab.data.reshape(-1), diag, b, x, ax)
    except Exception:     # noqa: BLE001 - a failure here shows again, with its traceback, in FineSweeps
        pass


class FineSweeps:
    """Forward sweep from zero with its residual, and backward sweep with its product, over one matrix:
    CSR, or BSR in 3x3 node blocks (the sweeps then run over the blocks, see sweep_kernels).

    ``A`` must be symmetric with every diagonal entry stored (a stiffness matrix, as CG requires anyway:
    an asymmetry of relative size e changes the products by e). Its arrays are used as they are."""

    def __init__(self, A):
        self.blocks = sp.issparse(A) and A.format == "bsr"
        if self.blocks and A.blocksize != (3, 3):
            raise ValueError(f"FineSweeps: blocks {A.blocksize}, only 3x3 node blocks are swept in blocks")
        if not self.blocks:
            A = A.tocsr()
        if not A.has_sorted_indices:
            A.sort_indices()
        self.A = A
        k = _kernels()
        self._data = A.data.reshape(-1)
        if self.blocks:
            self.diag = k.diagonal_positions(A.indptr, A.indices)
            self._forward, self._backward = k.block_forward_from_zero, k.block_backward_with_product
        else:
            self.diag = k.diagonal_positions(A.indptr, A.indices)
            self._forward, self._backward = k.forward_from_zero, k.backward_with_product
        if self.diag.size and self.diag.min() < 0:
            raise ValueError("FineSweeps: a row without a diagonal entry")

    def forward_from_zero(self, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(x, U x) with x = (D + L)^-1 b: pyamg's forward sweep from zero, and b - A x = -U x."""
        x = np.zeros_like(b)
        ux = np.zeros_like(b)
        self._forward(self.A.indptr, self.A.indices, self._data, self.diag, b, x, ux)
        return x, ux

    def backward(self, b: np.ndarray, x: np.ndarray) -> np.ndarray:
        """pyamg's backward sweep on ``x`` in place (up to the order of the sums); returns A x of the result."""
        ax = np.zeros_like(b)
        self._backward(self.A.indptr, self.A.indices, self._data, self.diag, b, x, ax)
        return ax
