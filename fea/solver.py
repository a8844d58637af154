"""Solve K u = f with Dirichlet conditions: sparse direct for small systems, AMG-preconditioned CG above.

Measured on this machine (issue 4): scipy's default sparse direct solve needed 619 s / 19.6 GB at 297k
P2 dofs, CG with smoothed-aggregation AMG (pyamg) using the rigid-body modes as near-nullspace 25 s,
and without those modes AMG took 5-10x more iterations. ``DIRECT_MAX_DOFS`` is the crossover measured
by benchmarks/bench_fea.py (see its output); below it SuperLU is both faster and exact.
"""
from __future__ import annotations

import contextlib
import functools
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import StageError

# Crossover for plain smoothed aggregation (P1, 2D), from benchmarks/bench_fea.py: PARDISO beats it up
# to about this size. For 3D P2 the p-multigrid wins at every size measured on the shaft (solve s,
# PARDISO vs p-MG): 6.6k dofs 1.07 vs 0.21, 11.8k 1.12 vs 0.24, 25k 1.33 vs 0.49, 59k 2.83 vs 1.27,
# so "auto" uses it for all 3D P2 systems. Thin-walled parts (the flexspline cup) pass method="direct":
# their graph is nearly 2D (94k dofs: PARDISO 4.0 s, p-MG 10.7 s / 118 iterations).
DIRECT_MAX_DOFS = 60_000
# Relative residual for CG. The compliance error is quadratic in the residual: with the p-multigrid
# on the 224k-dof shaft, against rtol 1e-10 (31 iterations) the compliance f.u moved by 1e-13 at
# 1e-8 (26), 5e-14 at 1e-7 (23) and 2e-14 at 1e-6 (21) - round-off. The smallest crack effect solved
# iteratively is the bearing's 0.1 mm crack, delta C / C = 4e-5, 1e8 times larger; 1e-7 keeps a
# decade of margin on the 1e-6 the measurements allow (stress fields are linear in the error).
DEFAULT_RTOL = 1e-7


@dataclass(frozen=True)
class SolverInfo:
    method: str             # "pardiso", "splu" or "amg-cg"
    dofs: int               # free unknowns
    iterations: int
    residual: float         # ||f - K u|| / ||f|| on the free dofs
    time_s: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def rigid_body_modes(coords: np.ndarray, dim: int) -> np.ndarray:
    """Near-nullspace of elasticity for interleaved dofs: (n*dim, 6) in 3D, (n*dim, 3) in 2D.

    coords : (dim, n) positions of the scalar dofs (scikit-fem ``basis.doflocs``)."""
    n = coords.shape[1]
    x = coords - coords.mean(axis=1, keepdims=True)   # centred: better conditioned modes
    if dim == 3:
        B = np.zeros((n, 3, 6))
        for a in range(3):
            B[:, a, a] = 1.0
        X, Y, Z = x
        B[:, 0, 3], B[:, 1, 3] = -Y, X
        B[:, 1, 4], B[:, 2, 4] = -Z, Y
        B[:, 0, 5], B[:, 2, 5] = Z, -X
    else:
        B = np.zeros((n, 2, 3))
        B[:, 0, 0] = B[:, 1, 1] = 1.0
        B[:, 0, 2], B[:, 1, 2] = -x[1], x[0]
    return B.reshape(n * dim, -1)


def solve_elasticity(K: sp.spmatrix, f: np.ndarray, *, fixed_dofs: np.ndarray, fixed_values: np.ndarray | float = 0.0,
                     coords: np.ndarray, dim: int, method: str = "auto", rtol: float = DEFAULT_RTOL,
                     maxiter: int = 2000, study: str = "fea",
                     p2_element_dofs: np.ndarray | None = None,
                     p1_stiffness: Callable[[], sp.bsr_matrix] | None = None,
                     consume_K: bool = False) -> tuple[np.ndarray, SolverInfo]:
    """Solve the condensed system for the free dofs; fixed dofs take ``fixed_values``.

    Parameters
    ----------
    K, f : global stiffness (interleaved vector dofs) and load vector.
    fixed_dofs, fixed_values : Dirichlet dofs and their prescribed displacements (mm).
    coords : (dim, n_scalar) scalar dof positions, for the rigid-body near-nullspace.
    method : "auto" (direct up to DIRECT_MAX_DOFS free dofs), "direct" or "amg".
    p2_element_dofs : (nloc, nel) scalar P2 element dofs (scikit-fem order); with them "amg" is a
        p-multigrid (P2 -> P1 on the same mesh -> smoothed aggregation), see ``pmultigrid``.
    p1_stiffness : makes the stiffness of the P1 field on the same (curved) mesh and quadrature, in node
        blocks over the vertex dofs (the first ones of the P2 numbering): the p-multigrid's coarse
        operator without the Galerkin product R K P, which equals it up to round-off (the P1 functions
        lie in the P2 space and the quadrature is the same).
    consume_K : K (3x3 node blocks) may be overwritten: the condensed matrix is formed in its own arrays
        by the numba kernel ``assembly_kernels.condense_blocks_in_place`` (the caller has loaded numba;
        ``static.solve_static`` for the systems it assembles with those kernels), and so is the P1
        level's. The same matrices as without.
    Raises StageError("solve", study, ...) when CG does not reach ``rtol`` in ``maxiter`` iterations.
    """
    t0 = time.perf_counter()
    N = K.shape[0]
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64))
    u = np.zeros(N)
    u[fixed] = _values_for(fixed_dofs, fixed_values, fixed)
    mask = np.ones(N, bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    # all prescribed values zero (clamps): b = f[free] without the product K u (0.09 s at 1M dofs)
    b = (f - K @ u)[free] if np.any(u[fixed]) else np.asarray(f, float)[free]
    Kff_blocks = None
    node_mask = mask.reshape(-1, dim) if N % dim == 0 else None
    if sp.issparse(K) and K.format == "bsr" and K.blocksize == (dim, dim) and node_mask is not None \
            and np.array_equal(node_mask.all(axis=1), node_mask.any(axis=1)):
        # whole nodes fixed: condense the 3x3 blocks (9x fewer index entries, see condense_blocks)
        Kff_blocks = condense_blocks(K, node_mask[:, 0], in_place=consume_K and dim == 3)
    else:
        Kff = condense(K.tocsr(), mask)
    nb = np.linalg.norm(b)
    if nb == 0.0:
        return u, SolverInfo("none", free.size, 0, 0.0, time.perf_counter() - t0)
    if method == "auto":
        pmg = p2_element_dofs is not None and dim == 3
        method = "amg" if pmg or free.size > DIRECT_MAX_DOFS else "direct"
    from .fused_sweeps import MIN_DOFS
    fused = method == "amg" and p2_element_dofs is not None and dim == 3 and free.size >= MIN_DOFS
    if Kff_blocks is not None:
        # the fused fine level sweeps the blocks as they are (no CSR copy: ~1 s and 0.9 GB at 1M dofs);
        # the other paths take CSR, and keep the blocks for the Galerkin product unless p1_stiffness
        # makes the coarse operator
        Kff = Kff_blocks if fused else Kff_blocks.tocsr()
        if fused or p1_stiffness is not None:
            Kff_blocks = None
    if method == "direct":
        del Kff_blocks
        x, name = _direct(Kff, b, study, node_blocks=dim == 3)
        its = 1
    else:
        from .pmultigrid import pcg, pcg_with_products, v_cycle, v_cycle_fused
        # handed over in a list so that the hierarchy frees the blocks after its Galerkin product, before
        # the rest of its set-up (0.7 GB less at the peak, 1M dofs)
        blocks = [Kff_blocks]
        del Kff_blocks
        ml = _amg_hierarchy(Kff, free, coords, dim, p2_element_dofs, blocks, p1_stiffness, fused=fused,
                            in_place=consume_K)
        sweeps = getattr(ml, "fused_sweeps", None)
        if sweeps:
            x, its = pcg_with_products(b, v_cycle_fused(sweeps, ml.levels, ml.coarse_solver), rtol=rtol,
                                       maxiter=maxiter)
        else:
            x, its = pcg(ml.levels[0].A, b, v_cycle(ml.levels, ml.coarse_solver), rtol=rtol, maxiter=maxiter)
        name = "amg-cg"
    residual = float(np.linalg.norm(b - Kff @ x) / nb)
    if not np.isfinite(residual) or residual > max(rtol * 100, 1e-6):
        raise StageError("solve", study, f"{name} did not converge: relative residual {residual:.2e} "
                                         f"after {its} iterations ({free.size} dofs)")
    u[free] = x
    return u, SolverInfo(name, int(free.size), int(its), residual, time.perf_counter() - t0)


def condense_blocks(K: sp.bsr_matrix, keep_nodes: np.ndarray, *, in_place: bool = False) -> sp.bsr_matrix:
    """K[keep][:, keep] of a square BSR matrix whose kept dofs come in whole blocks (node blocks).

    The same entries, in the same order, as ``condense`` of K's CSR: one filter of the blocks instead
    of the scalar entries. 957k-dof shaft (9.6M blocks, one core): K -> CSR 0.2 s + ``condense`` 2.4 s,
    against this 0.5 s + the condensed BSR -> CSR 0.2 s; the blocks also serve the Galerkin product.
    ``in_place``: formed over K's own arrays by a numba kernel (K is lost; numba must be wanted anyway):
    the copy of the blocks was mostly the cost of mapping fresh memory."""
    if in_place:
        from .assembly_kernels import condense_blocks_in_place
        indptr, m = condense_blocks_in_place(K.indptr, K.indices, K.data, np.ascontiguousarray(keep_nodes, bool))
        n = (indptr.size - 1) * K.blocksize[0]
        out = sp.bsr_matrix((K.data[:m], K.indices[:m], indptr.astype(K.indptr.dtype)), shape=(n, n))
        out.has_sorted_indices = K.has_sorted_indices
        return out
    r, c = K.blocksize
    counts = np.diff(K.indptr)
    block_kept = np.repeat(keep_nodes, counts) & keep_nodes[K.indices]
    per_row = np.add.reduceat(block_kept, np.minimum(K.indptr[:-1], max(K.indices.size - 1, 0)),
                              dtype=np.int64) if K.indices.size else np.zeros(counts.size, np.int64)
    per_row = np.where(counts > 0, per_row, 0)[keep_nodes]
    indptr = np.zeros(per_row.size + 1, dtype=K.indptr.dtype)
    np.cumsum(per_row, out=indptr[1:])
    new = (np.cumsum(keep_nodes) - 1).astype(K.indices.dtype)
    return sp.bsr_matrix((K.data[block_kept], new[K.indices[block_kept]], indptr),
                         shape=(per_row.size * r, per_row.size * c))


def condense(K: sp.csr_matrix, keep: np.ndarray) -> sp.csr_matrix:
    """K[keep][:, keep] of a square CSR matrix by one boolean filter of its entries.

    scipy's fancy indexing does rows and columns in two passes with index copies: 0.87-1.36 s against
    0.23-0.72 s here for the 300k-dof shaft (23.6M entries, CPU time, 2 shared cores)."""
    counts = np.diff(K.indptr)
    entry_kept = np.repeat(keep, counts) & keep[K.indices]
    starts = np.minimum(K.indptr[:-1], max(K.nnz - 1, 0))       # reduceat needs in-range starts
    per_row = np.where(counts > 0, np.add.reduceat(entry_kept, starts, dtype=np.int64) if K.nnz else 0, 0)[keep]
    indptr = np.zeros(per_row.size + 1, dtype=K.indptr.dtype)
    np.cumsum(per_row, out=indptr[1:])
    new = (np.cumsum(keep) - 1).astype(K.indices.dtype)
    return sp.csr_matrix((K.data[entry_kept], new[K.indices[entry_kept]], indptr), shape=(per_row.size,) * 2)


# Symmetric-strength threshold of the aggregation. theta = 0 aggregates across every coupling and
# needed 85 iterations on the 238k-dof P2 shaft; 0.02 drops the weak P2 couplings: 42 (plain SA) and
# 26 (P2 -> P1 -> SA), at the same operator complexity (1.10). 0.05 saves 3 more iterations but
# its setup costs more than they save; 0.1 adds a level and doubles the setup.
STRENGTH_THETA = 0.02
MAX_COARSE = 500          # unknowns of the last level, solved by splu


@contextlib.contextmanager
def _seeded_global_rng(seed: int = 0):
    """numpy's global RNG seeded inside, its state restored after.

    pyamg estimates the spectral radius for the prolongation smoothing from np.random.rand: two
    hierarchies of the same matrix differed from their second level on, and the solution by ~1e-13
    relative from run to run (validate --quick GCIs by up to 3e-11 relative, the bearing's delta
    radial compliance by 3e-10). Seeded, every run gives the same numbers."""
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


def _aggregation(A, B):
    """pyamg smoothed aggregation with the rigid-body near-nullspace ``B`` (deterministic: seeded)."""
    import pyamg
    with _seeded_global_rng():
        return _sa_solver(pyamg, A, B)


def _sa_solver(pyamg, A, B):
    return pyamg.smoothed_aggregation_solver(
        A, B=B, symmetry="hermitian", strength=("symmetric", {"theta": STRENGTH_THETA}),
        smooth="jacobi", max_coarse=MAX_COARSE, coarse_solver="splu",
        # the rigid-body modes are the exact near-nullspace: relaxing them first halved the setup
        # (9.5 -> 4.7 s, 150k) for 0 iterations
        improve_candidates=None,
        # one forward GS sweep before, one backward after: a symmetric V-cycle at 1/3 the cost of
        # pyamg's default symmetric sweeps (0.10 vs 0.37 s per cycle at 150k dofs; 1.4x the
        # iterations, 2.5x faster overall)
        presmoother=SMOOTHERS[0], postsmoother=SMOOTHERS[1])


SMOOTHERS = (("gauss_seidel", {"sweep": "forward"}), ("gauss_seidel", {"sweep": "backward"}))


def _amg_hierarchy(Kff, free, coords, dim, p2_element_dofs, blocks=None, p1_stiffness=None, fused=False,
                   in_place=False):
    """Smoothed aggregation with the rigid-body modes; for P2, preceded by the P1 level (p-multigrid).

    Node blocks (BSR dim x dim) when the free dofs come in whole nodes: pyamg then aggregates nodes,
    not single components. ``fused``: the p-multigrid's fine level is ``Kff`` as given (CSR or 3x3
    blocks), and it and the P1 level are swept by ``fused_sweeps`` (``ml.fused_sweeps``, one per level)."""
    import pyamg
    from pyamg.multilevel import MultilevelSolver
    node_complete = free.size % dim == 0 and np.array_equal(
        free.reshape(-1, dim) % dim, np.tile(np.arange(dim), (free.size // dim, 1)))
    B = rigid_body_modes(coords, dim)
    if p2_element_dofs is None or not node_complete:
        return _aggregation(Kff.tobsr(blocksize=(dim, dim)) if node_complete else Kff, B[free])
    from .pmultigrid import p1_prolongation, vector_prolongation
    scalar_P = p1_prolongation(p2_element_dofs)[0]
    P, coarse_free = vector_prolongation(scalar_P, dim, free)
    if p1_stiffness is not None:
        # R K P is the P1 stiffness only when no fixed mid-edge node sits on an edge with a free vertex
        # (true for clamped faces); otherwise the coarse hat functions lose that mid node's part
        fixed_node = np.ones(scalar_P.shape[0], bool)
        fixed_node[free[::dim] // dim] = False
        rows = scalar_P[fixed_node]
        if not np.all(fixed_node[rows.indices]):
            p1_stiffness = None
    fine = MultilevelSolver.Level()
    # The fine level smooths in CSR: pyamg's Gauss-Seidel sweep over the P2 matrix costs 0.025 s in CSR
    # and 0.060 s in 3x3 blocks (300k-dof shaft, CPU time), with the same 23 CG iterations (the V-cycle
    # went from 0.36 to 0.23 s). Node blocks stay where they pay: the Galerkin product and below.
    fine.A = Kff if fused else Kff.tocsr()
    fine.P = P.tobsr(blocksize=(dim, dim))
    fine.R = fine.P.T.tobsr(blocksize=(dim, dim))
    if p1_stiffness is not None:
        # the P1 assembly: 0.8 s against the Galerkin product's 2.0 s (308k dofs, both at load ~8),
        # the same matrix to 6e-16 relative with the same blocks
        K1 = p1_stiffness()
        is_free = np.zeros(K1.shape[0], bool)
        is_free[coarse_free] = True
        coarse_A = condense_blocks(K1, is_free.reshape(-1, dim)[:, 0], in_place=in_place and dim == 3)
        del K1
    else:
        A_blocks = blocks.pop() if blocks and blocks[0] is not None else Kff.tobsr(blocksize=(dim, dim))
        # Galerkin product in node blocks: 0.18 s against 1.14 s in CSR (238k dofs), same matrix to 3e-16
        AP = A_blocks @ fine.P
        del A_blocks
        coarse_A = (fine.R @ AP).tobsr(blocksize=(dim, dim))
        del AP
    coarse = _aggregation(coarse_A, B[coarse_free])
    ml = MultilevelSolver([fine] + coarse.levels, coarse_solver="splu")
    pyamg.relaxation.smoothing.change_smoothers(ml, presmoother=SMOOTHERS[0], postsmoother=SMOOTHERS[1])
    if fused:
        from .fused_sweeps import FineSweeps
        # the fine level's sweeps, residual and CG product in two passes over its matrix, the P1 level's
        # sweeps with their residual (fused_sweeps); pyamg's smoothers stay on the levels for ml.solve.
        # 957k dofs: CG 5.54 -> 4.80 s (medians of 5 alternating pairs, load 2.6-2.8) against pyamg's block
        # Gauss-Seidel and residual on the P1 level
        p1 = ml.levels[1].A
        ml.fused_sweeps = [FineSweeps(fine.A)] + ([FineSweeps(p1)] if p1.format == "bsr" and p1.blocksize == (3, 3)
                                                  and len(ml.levels) > 2 else [])
    return ml


def _direct(A: sp.csr_matrix, b: np.ndarray, study: str, *, node_blocks: bool = False) -> tuple[np.ndarray, str]:
    """Sparse direct solve: MKL PARDISO (symmetric positive definite, upper triangle) when pypardiso is
    installed, else SuperLU. Measured on the 54k-dof flexspline cup: PARDISO 3.0 s / 0.4 GB, SuperLU
    22 s (COLAMD) to 80 s (MMD), AMG-CG 38 s (470 iterations: thin walls are hard for aggregation).
    ``node_blocks`` (3D elasticity): PARDISO with ``PARDISO_IPARM``, else with its defaults."""
    try:
        with _mkl_rt_known():
            import pypardiso
    except ImportError:
        pypardiso = None
    if pypardiso is not None:
        solver = _pardiso_solver(pypardiso, tuned=node_blocks)
        upper = sp.triu(A, format="csr")
        upper.sort_indices()
        try:
            x = solver.solve(upper, b)
        except Exception as exc:   # PARDISO reports a non-positive pivot / singular matrix as an error code
            raise StageError("solve", study, f"PARDISO failed: {exc}") from exc
        finally:
            solver.free_memory(everything=True)
        return np.asarray(x).ravel(), "pardiso"
    try:
        lu = spla.splu(A.tocsc(), permc_spec="COLAMD")
    except RuntimeError as exc:   # singular: a rigid-body mode is not restrained
        raise StageError("solve", study, f"direct factorisation failed: {exc}") from exc
    return lu.solve(b), "splu"


# PARDISO's settings (1-based iparm numbers) instead of its defaults (iparm(1) = 0): the same METIS ordering
# and two steps of iterative refinement, plus the matrix read in variable 3 x 3 node blocks (iparm(37) = -80:
# blocks of rows whose patterns agree to 80 %) and the two-level factorisation (iparm(24) = 1). The quick
# validation's matrices (18k-90k dofs, one MKL thread), alternating with the defaults at load 3.8-4.2: the
# cup's 90k 2.94-3.18 -> 2.40-2.42 s (analysis 0.7-0.86 -> 0.27-0.29 s, factorisation 2.09-2.19 -> 1.93 s),
# the bearing's 39k 0.97-1.11 -> 0.85-0.86 s, the ring's 61k 1.44-1.52 -> 1.13 s; residuals as with the
# defaults, solutions within 1e-10 of theirs. 3D only: the 2D ring sections (54k dofs) factor in 0.04 s,
# their analysis would save 0.05 s per solve, and their solution, at a residual of 1.5e-8 either way, moved
# by 7e-9, and with it the ring's smallest GCIs (1.4e-6) in their third digit.
PARDISO_IPARM = {1: 1, 2: 2, 8: 2, 24: 1, 37: -80}


def _pardiso_solver(pypardiso, *, tuned: bool = False):
    """A PyPardisoSolver for real symmetric positive definite matrices (mtype 2), told where mkl_rt is;
    ``tuned``: with ``PARDISO_IPARM`` instead of PARDISO's defaults."""
    with _mkl_rt_known():
        solver = pypardiso.PyPardisoSolver(mtype=2)
    if tuned:
        for number, value in PARDISO_IPARM.items():
            solver.set_iparm(number, value)
    return solver


@contextlib.contextmanager
def _mkl_rt_known():
    """PYPARDISO_MKL_RT set to the environment's mkl_rt while a PyPardisoSolver is made.

    Without it, every PyPardisoSolver() runs ctypes' find_library (ldconfig and gcc subprocesses) and
    then globs the whole venv recursively for the library: 0.47 s per solve, 2.8 s of a 30 s quick cup
    case (six solves, cProfile). ``import pypardiso`` makes one at import (its scipy aliases' solver):
    0.47-0.50 s of every case child that solves directly (cup, ring), 0.0 s with the variable. The library
    sits in the environment's lib/ (the mkl wheel), so one non-recursive look finds it; the variable is set
    only for the constructor (a user's own setting is kept)."""
    import os
    path = _mkl_rt()
    if path is None or "PYPARDISO_MKL_RT" in os.environ:
        yield
        return
    os.environ["PYPARDISO_MKL_RT"] = path
    try:
        yield
    finally:
        del os.environ["PYPARDISO_MKL_RT"]


@functools.lru_cache(maxsize=1)
def _mkl_rt() -> str | None:
    import glob
    import sys
    hits = sorted(glob.glob(f"{sys.prefix}/lib/libmkl_rt.so*") + glob.glob(f"{sys.prefix}/Library/bin/mkl_rt*.dll"),
                  key=len)
    return hits[0] if hits else None


def _values_for(fixed_dofs, fixed_values, fixed_sorted) -> np.ndarray:
    """Prescribed values aligned with the sorted unique ``fixed_sorted`` dofs."""
    fd = np.asarray(fixed_dofs, dtype=np.int64)
    fv = np.broadcast_to(np.asarray(fixed_values, float), fd.shape)
    out = np.zeros(fixed_sorted.size)
    out[np.searchsorted(fixed_sorted, fd)] = fv
    return out
