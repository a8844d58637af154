"""Solve K u = f with Dirichlet conditions: sparse direct for small systems, AMG-preconditioned CG above.

A sparse direct solve does not scale to 3D P2 systems, and AMG needs the rigid-body modes as near-nullspace
(docs/decisions/003-direct-vs-multigrid-solver.md).
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

from strainwave.errors import StageError

# Direct below this size for plain SA (P1, 2D); 3D P2 always p-multigrid (docs/decisions/003-direct-vs-multigrid-solver.md).
DIRECT_MAX_DOFS = 60_000
# CG residual: the compliance error is quadratic in it, so 1e-7 is round-off (docs/decisions/017-cg-tolerance.md).
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
    # all prescribed values zero (clamps): b = f[free], no product K u (docs/decisions/020-condensation-in-node-blocks.md)
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
    from strainwave.fea.fused_sweeps import MIN_DOFS
    fused = method == "amg" and p2_element_dofs is not None and dim == 3 and free.size >= MIN_DOFS
    if Kff_blocks is not None:
        # no CSR copy for the fused sweeps; blocks kept for the Galerkin product (docs/decisions/006-fused-sweeps.md)
        Kff = Kff_blocks if fused else Kff_blocks.tocsr()
        if fused or p1_stiffness is not None:
            Kff_blocks = None
    if method == "direct":
        del Kff_blocks
        x, name = _direct(Kff, b, study, node_blocks=dim == 3)
        its = 1
    else:
        blocks = [Kff_blocks]   # the list alone holds them, so the hierarchy can free them
        del Kff_blocks
        x, its = _iterative(Kff, b, free, coords, dim, p2_element_dofs, blocks, p1_stiffness, fused=fused,
                            in_place=consume_K, rtol=rtol, maxiter=maxiter)
        name = "amg-cg"
    residual = float(np.linalg.norm(b - Kff @ x) / nb)
    if not np.isfinite(residual) or residual > max(rtol * 100, 1e-6):
        raise StageError("solve", study, f"{name} did not converge: relative residual {residual:.2e} "
                                         f"after {its} iterations ({free.size} dofs)")
    u[free] = x
    return u, SolverInfo(name, int(free.size), int(its), residual, time.perf_counter() - t0)


def _iterative(Kff, b, free, coords, dim, p2_element_dofs, blocks, p1_stiffness, *, fused, in_place, rtol,
               maxiter) -> tuple[np.ndarray, int]:
    """CG preconditioned by one V-cycle of the (p-)multigrid hierarchy; ``blocks``: a list holding the node
    blocks, so the hierarchy frees them after its Galerkin product (docs/decisions/020-condensation-in-node-blocks.md)."""
    from strainwave.fea.pmultigrid import pcg, pcg_with_products, v_cycle, v_cycle_fused

    ml = _amg_hierarchy(Kff, free, coords, dim, p2_element_dofs, blocks, p1_stiffness, fused=fused, in_place=in_place)
    sweeps = getattr(ml, "fused_sweeps", None)
    if sweeps:
        return pcg_with_products(b, v_cycle_fused(sweeps, ml.levels, ml.coarse_solver), rtol=rtol, maxiter=maxiter)
    return pcg(ml.levels[0].A, b, v_cycle(ml.levels, ml.coarse_solver), rtol=rtol, maxiter=maxiter)


def condense_blocks(K: sp.bsr_matrix, keep_nodes: np.ndarray, *, in_place: bool = False) -> sp.bsr_matrix:
    """K[keep][:, keep] of a square BSR matrix whose kept dofs come in whole blocks (node blocks).

    The same entries, in the same order, as ``condense`` of K's CSR: one filter of the blocks instead of
    the scalar entries, and the blocks also serve the Galerkin product (docs/decisions/020-condensation-in-node-blocks.md).
    ``in_place``: formed over K's own arrays by a numba kernel (K is lost; numba must be wanted anyway),
    because mapping fresh memory was most of a copy's cost."""
    if in_place:
        from strainwave.fea.assembly_kernels import condense_blocks_in_place
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

    scipy's fancy indexing does rows and columns in two passes with index copies, slower
    (docs/decisions/020-condensation-in-node-blocks.md)."""
    counts = np.diff(K.indptr)
    entry_kept = np.repeat(keep, counts) & keep[K.indices]
    starts = np.minimum(K.indptr[:-1], max(K.nnz - 1, 0))       # reduceat needs in-range starts
    per_row = np.where(counts > 0, np.add.reduceat(entry_kept, starts, dtype=np.int64) if K.nnz else 0, 0)[keep]
    indptr = np.zeros(per_row.size + 1, dtype=K.indptr.dtype)
    np.cumsum(per_row, out=indptr[1:])
    new = (np.cumsum(keep) - 1).astype(K.indices.dtype)
    return sp.csr_matrix((K.data[entry_kept], new[K.indices[entry_kept]], indptr), shape=(per_row.size,) * 2)


def upper_triangle(A: sp.spmatrix) -> sp.csr_matrix:
    """The upper triangle of a square matrix, diagonal included, canonical CSR (PARDISO's symmetric input): the
    entries as ``sp.triu(A, format="csr")`` gives them, by one filter of the CSR entries (scipy's goes through
    COO and back, several times slower)."""
    A = A.tocsr()
    rows = np.repeat(np.arange(A.shape[0], dtype=A.indices.dtype), np.diff(A.indptr))
    kept = A.indices >= rows
    indptr = np.zeros(A.shape[0] + 1, dtype=A.indptr.dtype)
    np.cumsum(np.bincount(rows[kept], minlength=A.shape[0]), out=indptr[1:])
    upper = sp.csr_matrix((A.data[kept], A.indices[kept], indptr), shape=A.shape)
    upper.sum_duplicates()      # sorts the indices and sums repeated entries, as scipy's COO -> CSR does
    return upper


# Strength 0.02 drops the weak P2 couplings at the least cost (docs/decisions/018-multigrid-settings.md).
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
        # the rigid-body modes are the exact near-nullspace: no need to relax them (docs/decisions/018-multigrid-settings.md)
        improve_candidates=None,
        # forward GS before, backward after: a cheaper symmetric V-cycle (docs/decisions/018-multigrid-settings.md)
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
    from strainwave.fea.pmultigrid import p1_prolongation, vector_prolongation
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
    # The fine level smooths in CSR, cheaper than node blocks there (docs/decisions/018-multigrid-settings.md).
    fine.A = Kff if fused else Kff.tocsr()
    fine.P = P.tobsr(blocksize=(dim, dim))
    fine.R = fine.P.T.tobsr(blocksize=(dim, dim))
    if p1_stiffness is not None:
        # the P1 assembly: cheaper than the Galerkin product, same matrix (docs/decisions/018-multigrid-settings.md)
        K1 = p1_stiffness()
        is_free = np.zeros(K1.shape[0], bool)
        is_free[coarse_free] = True
        coarse_A = condense_blocks(K1, is_free.reshape(-1, dim)[:, 0], in_place=in_place and dim == 3)
        del K1
    else:
        A_blocks = blocks.pop() if blocks and blocks[0] is not None else Kff.tobsr(blocksize=(dim, dim))
        # Galerkin product in node blocks: faster than in CSR, same matrix (docs/decisions/018-multigrid-settings.md)
        AP = A_blocks @ fine.P
        del A_blocks
        coarse_A = (fine.R @ AP).tobsr(blocksize=(dim, dim))
        del AP
    coarse = _aggregation(coarse_A, B[coarse_free])
    ml = MultilevelSolver([fine] + coarse.levels, coarse_solver="splu")
    pyamg.relaxation.smoothing.change_smoothers(ml, presmoother=SMOOTHERS[0], postsmoother=SMOOTHERS[1])
    if fused:
        from strainwave.fea.fused_sweeps import FineSweeps
        # fused_sweeps on the fine and P1 levels; pyamg's smoothers stay for ml.solve (docs/decisions/006-fused-sweeps.md)
        p1 = ml.levels[1].A
        ml.fused_sweeps = [FineSweeps(fine.A)] + ([FineSweeps(p1)] if p1.format == "bsr" and p1.blocksize == (3, 3)
                                                  and len(ml.levels) > 2 else [])
    return ml


def _direct(A: sp.csr_matrix, b: np.ndarray, study: str, *, node_blocks: bool = False,
            iparm: dict[int, int] | None = None) -> tuple[np.ndarray, str]:
    """Sparse direct solve: MKL PARDISO (symmetric positive definite, upper triangle) when pypardiso is
    installed, else SuperLU, which is far slower (docs/decisions/003-direct-vs-multigrid-solver.md).
    ``node_blocks`` (3D elasticity): PARDISO with ``PARDISO_IPARM``, else with its defaults; ``iparm``: PARDISO
    settings on top of those (1: 1 for PARDISO to read them; SuperLU ignores them)."""
    try:
        with _mkl_rt_known():
            import pypardiso
    except ImportError:
        pypardiso = None
    if pypardiso is not None:
        solver = _pardiso_solver(pypardiso, tuned=node_blocks)
        for number, value in (iparm or {}).items():
            solver.set_iparm(number, value)
        upper = upper_triangle(A)
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


@dataclass
class SchurFactor:
    """One sparse factorisation of an SPD matrix A that also gave S, the Schur complement of A onto the dofs
    ``tail`` (A_tt - A_ti A_ii^-1 A_it, dense, in the order of ``tail``): a system solved for many sets of
    held ``tail`` dofs by dense solves of S's blocks, and ``solve`` for the full A with the same factors."""

    S: np.ndarray
    solve: Callable[[np.ndarray], np.ndarray]     # A^-1 b, b of shape (n,) or (n, k)
    close: Callable[[], None]                     # frees the factors
    method: str = "pardiso"                       # the sparse solver that made it: "pardiso" or "splu"
    # PARDISO's partial solves (phases 331 / 333): the forward substitution of b leaves on the tail the load
    # condensed there, b_t - A_ti A_ii^-1 b_i; the backward one, given the tail's values there, A's solution
    forward: Callable[[np.ndarray], np.ndarray] | None = None
    backward: Callable[[np.ndarray], np.ndarray] | None = None


def schur_factor(A: sp.csr_matrix, tail: np.ndarray, study: str) -> SchurFactor:
    """``SchurFactor`` of the SPD matrix A: PARDISO's Schur complement (iparm 36 = 2: the Schur complement in
    the factorisation step, and the full factors kept for solves) when pypardiso is installed, else SuperLU."""
    tail = np.asarray(tail, np.int64)
    try:
        with _mkl_rt_known():
            import pypardiso
    except ImportError:
        return _schur_splu(A, tail, study)
    solver = _pardiso_solver(pypardiso, tuned=True)   # iparm 1 = 1: PARDISO reads iparm 36
    n, m = A.shape[0], tail.size
    solver.set_iparm(36, 2 if m else 0)
    solver.perm = np.zeros(n, np.int32)
    solver.perm[tail] = 1
    upper = upper_triangle(A)

    def call(phase: int, b: np.ndarray) -> np.ndarray:
        solver.set_phase(phase)
        try:
            return solver._call_pardiso(upper, np.asfortranarray(b, dtype=float))
        except Exception as exc:   # a non-positive pivot: the matrix is singular (a rigid-body mode is free)
            solver.free_memory(everything=True)
            raise StageError("solve", study, f"PARDISO failed: {exc}") from exc

    # the Schur complement comes back in the first m^2 entries of the solution array
    x = call(12, np.zeros((n, max(1, -(-m * m // n)))))
    S = np.array(np.asarray(x).ravel(order="F")[:m * m].reshape(m, m))
    return SchurFactor(S, lambda b: call(33, b), lambda: solver.free_memory(everything=True),
                       forward=_pardiso_phase(solver, upper, 331, study),
                       backward=_pardiso_phase(solver, upper, 333, study))


def _pardiso_phase(solver, upper: sp.csr_matrix, phase: int, study: str) -> Callable[[np.ndarray], np.ndarray]:
    """b -> x of PARDISO's ``phase`` on ``solver``'s factors of ``upper``, whose 1-based index arrays are made
    once here: pypardiso's own call remakes them at every call, which costs as much as a partial solve."""
    import ctypes
    i32, f64 = ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_double)
    ia, ja = upper.indptr.astype(np.int32) + 1, upper.indices.astype(np.int32) + 1
    one = ctypes.byref(ctypes.c_int32(1))

    def run(b: np.ndarray) -> np.ndarray:
        b = np.asfortranarray(b, dtype=float)
        x, error = np.zeros_like(b), ctypes.c_int32(0)
        solver._mkl_pardiso(solver.pt.ctypes.data_as(ctypes.POINTER(solver._pt_type[0])), one, one,
                            ctypes.byref(ctypes.c_int32(solver.mtype)), ctypes.byref(ctypes.c_int32(phase)),
                            ctypes.byref(ctypes.c_int32(upper.shape[0])), upper.data.ctypes.data_as(f64),
                            ia.ctypes.data_as(i32), ja.ctypes.data_as(i32), solver.perm.ctypes.data_as(i32),
                            ctypes.byref(ctypes.c_int32(1 if b.ndim == 1 else b.shape[1])),
                            solver.iparm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(solver.msglvl)),
                            b.ctypes.data_as(f64), x.ctypes.data_as(f64), ctypes.byref(error))
        if error.value != 0:
            raise StageError("solve", study, f"PARDISO phase {phase} failed: error {error.value}")
        return x
    return run


def tail_solve(S: np.ndarray, r: np.ndarray, held: np.ndarray, values: np.ndarray | float = 0.0) -> np.ndarray:
    """The tail dofs' solution of the condensed system S u = r (``SchurFactor.S``) with the dofs ``held``
    prescribed to ``values``: a dense Cholesky solve of S's free block."""
    from scipy.linalg import cho_factor, cho_solve
    held = np.asarray(held, bool)
    u = np.zeros(r.shape)
    u[held] = np.broadcast_to(values, held.shape)[held] if np.ndim(values) else values
    free = ~held
    if free.any():
        rhs = r[free] - S[np.ix_(free, held)] @ u[held]
        u[free] = cho_solve(cho_factor(S[np.ix_(free, free)]), rhs)
    return u


def _schur_splu(A: sp.csr_matrix, tail: np.ndarray, study: str) -> SchurFactor:
    """``SchurFactor`` by SuperLU: S from one solve of A_ii per tail dof (far slower than PARDISO's)."""
    keep = np.ones(A.shape[0], bool)
    keep[tail] = False
    inner = np.flatnonzero(keep)
    try:
        lu, lu_ii = (spla.splu(M.tocsc(), permc_spec="COLAMD") for M in (A, condense(A.tocsr(), keep)))
    except RuntimeError as exc:   # singular: a rigid-body mode is not restrained
        raise StageError("solve", study, f"direct factorisation failed: {exc}") from exc
    A_it = A[inner][:, tail].toarray()
    S = A[tail][:, tail].toarray() - A_it.T @ lu_ii.solve(A_it)
    return SchurFactor(S, lu.solve, lambda: None, "splu")


# METIS, 3x3 node blocks, two-level factorisation: faster on the 3D matrices (docs/decisions/007-pardiso-settings.md).
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

    Without it, every PyPardisoSolver() runs find_library and globs the whole venv for mkl_rt, at every
    solve (docs/decisions/007-pardiso-settings.md). Set only for the constructor; a user's own setting is kept."""
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
