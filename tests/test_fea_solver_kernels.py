"""Solver kernels: ``solver.condense`` is K[keep][:, keep]; ``solver.upper_triangle`` is scipy's triu; ``pmultigrid.pcg`` with ``v_cycle`` solves SPD systems;
the fused fine level (``fused_sweeps``) equals the pyamg / scipy path it replaces."""
import numpy as np
import pytest
import scipy.sparse as sp

from strainwave.fea.solver import condense, upper_triangle


@pytest.mark.parametrize("n", [1, 7, 60, 300])
def test_condense_equals_fancy_indexing(n):
    rng = np.random.default_rng(n)
    A = sp.random(n, n, density=0.08, random_state=n, format="csr")
    A = (A + A.T).tocsr()
    for _ in range(4):
        keep = rng.random(n) < 0.6
        got, want = condense(A, keep), A[keep][:, keep]
        assert got.shape == want.shape
        assert abs(got - want).sum() == 0.0
        assert got.has_sorted_indices or got.nnz == 0



def _unsorted_with_duplicates_and_zeros(n: int) -> sp.csr_matrix:
    """A CSR matrix built from its arrays: unsorted indices, repeated entries and explicit zeros."""
    rng = np.random.default_rng(n)
    rows = np.sort(rng.integers(0, n, 6 * n))
    cols = rng.integers(0, max(1, n // 3), 6 * n) * 3 % n         # few distinct columns: repeats in a row
    vals = rng.standard_normal(6 * n)
    vals[::7] = 0.0
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))])
    A = sp.csr_matrix((vals, cols, indptr), shape=(n, n))
    assert n < 7 or not A.has_canonical_format
    return A


@pytest.mark.parametrize("n", [1, 7, 60, 300])
@pytest.mark.parametrize("make", ["sorted", "messy"])
def test_upper_triangle_is_scipys_triu_bit_for_bit(n, make):
    A = sp.random(n, n, density=0.08, random_state=n, format="csr") if make == "sorted" else \
        _unsorted_with_duplicates_and_zeros(n)
    got, want = upper_triangle(A), sp.triu(A, format="csr")
    want.sort_indices()
    assert got.has_canonical_format
    for name in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))


def test_upper_triangle_differs_from_a_perturbed_triangle():
    A = sp.random(60, 60, density=0.08, random_state=3, format="csr")
    got = upper_triangle(A).toarray()
    assert not np.array_equal(got, sp.triu(A, k=1).toarray())       # the diagonal is kept
    assert not np.array_equal(got, sp.tril(A).toarray())

def test_condense_with_empty_rows_last():
    A = sp.csr_matrix(np.diag([1.0, 2.0, 0.0, 0.0]))
    A.eliminate_zeros()
    np.testing.assert_array_equal(condense(A, np.array([True, False, True, True])).toarray(),
                                  [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    assert condense(sp.csr_matrix((3, 3)), np.array([True, True, False])).shape == (2, 2)


def _laplacian_3d(n):
    one = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    eye = sp.identity(n)
    return (sp.kron(sp.kron(one, eye), eye) + sp.kron(sp.kron(eye, one), eye) + sp.kron(sp.kron(eye, eye), one)).tocsr()


def test_pcg_with_the_v_cycle_matches_a_direct_solve():
    import pyamg
    import scipy.sparse.linalg as spla
    from strainwave.fea.pmultigrid import pcg, v_cycle
    A = _laplacian_3d(14)
    b = np.random.default_rng(0).random(A.shape[0])
    ml = pyamg.smoothed_aggregation_solver(A, max_coarse=50)
    x, its = pcg(A, b, v_cycle(ml.levels, ml.coarse_solver), rtol=1e-10, maxiter=200)
    exact = spla.spsolve(A.tocsc(), b)
    # rtol 1e-10 on the residual; kappa(A) ~ 100 here, so the error is below 1e-7 relative
    assert np.linalg.norm(x - exact) <= 1e-7 * np.linalg.norm(exact)
    # the V-cycle is a real preconditioner: far fewer iterations than plain CG needs (~60 here)
    _, plain = pcg(A, b, lambda r: r.copy(), rtol=1e-10, maxiter=1000)
    assert its < plain / 3


def test_pcg_stops_at_maxiter_without_converging():
    from strainwave.fea.pmultigrid import pcg
    A = _laplacian_3d(10)
    b = np.ones(A.shape[0])
    x, its = pcg(A, b, lambda r: r.copy(), rtol=1e-14, maxiter=3)
    assert its == 3 and np.linalg.norm(b - A @ x) > 1e-3 * np.linalg.norm(b)


def _random_block_spd(n_nodes, dim, seed):
    rng = np.random.default_rng(seed)
    A = sp.random(n_nodes * dim, n_nodes * dim, density=0.05, random_state=seed, format="csr")
    return (A + A.T + sp.identity(n_nodes * dim) * n_nodes).tobsr(blocksize=(dim, dim)), rng


@pytest.mark.parametrize("dim", [2, 3])
def test_condense_blocks_is_condense_of_the_csr(dim):
    from strainwave.fea.solver import condense_blocks
    K, rng = _random_block_spd(40, dim, dim)
    for _ in range(4):
        keep_nodes = rng.random(40) < 0.7
        got = condense_blocks(K, keep_nodes)
        want = condense(K.tocsr(), np.repeat(keep_nodes, dim))
        assert got.blocksize == (dim, dim)
        # the same entries in the same order: the fine level's CSR is the one the scalar path makes
        g = got.tocsr()
        assert np.array_equal(g.indptr, want.indptr) and np.array_equal(g.indices, want.indices)
        assert np.array_equal(g.data, want.data)


def _ball_system():
    """A small real system: the curved P2 stiffness of a ball with a clamped cap, condensed (CSR), and the
    p-multigrid solve's arguments."""
    import skfem
    from strainwave.fea.assembly import Lame, stiffness
    from strainwave.fea.element_gradients import element_geometry
    from strainwave.fea.mesh_data import to_skfem
    from strainwave.fea.solver import condense_blocks
    from tests.test_fea_assembly import _as_gmsh
    sk = to_skfem(_as_gmsh(skfem.MeshTet2.init_ball(2), 3))
    K = stiffness(element_geometry(sk.doflocs, sk.element_dofs, 2), Lame.from_young(2.1e5, 0.3), fmt="bsr")
    keep = np.ones(K.shape[0] // 3, bool)
    keep[np.argsort(sk.doflocs[2])[:40]] = False
    fixed = np.flatnonzero(np.repeat(~keep, 3))
    return sk, K, condense_blocks(K, keep).tocsr(), fixed


@pytest.mark.parametrize("blocks", [False, True])
def test_fine_sweeps_are_pyamgs_gauss_seidel_with_residual_and_product(blocks):
    """The fused forward sweep from zero is pyamg's forward sweep and returns U x (so b - A x = -U x);
    the fused backward sweep is pyamg's backward sweep and returns A x of its result; to round-off, over
    the CSR matrix and over its 3x3 node blocks."""
    from pyamg.relaxation.relaxation import gauss_seidel
    from strainwave.fea.fused_sweeps import FineSweeps
    A = _ball_system()[2]
    sweeps = FineSweeps(A.tobsr(blocksize=(3, 3)) if blocks else A)
    rng = np.random.default_rng(2)
    b = rng.random(A.shape[0])
    x, ux = sweeps.forward_from_zero(b)
    want = np.zeros_like(b)
    gauss_seidel(A, want, b, sweep="forward")
    np.testing.assert_allclose(x, want, rtol=1e-13, atol=0)
    np.testing.assert_allclose(b - A @ x, -ux, rtol=0, atol=1e-12 * abs(b).max())
    np.testing.assert_allclose(ux, sp.triu(A, 1) @ x, rtol=0, atol=1e-13 * abs(ux).max())
    x0 = rng.random(A.shape[0])
    ours, want = x0.copy(), x0.copy()
    ax = sweeps.backward(b, ours)
    gauss_seidel(A, want, b, sweep="backward")
    np.testing.assert_allclose(ours, want, rtol=1e-13, atol=0)
    np.testing.assert_allclose(ax, A @ ours, rtol=0, atol=1e-13 * abs(ax).max())


@pytest.mark.parametrize("blocks", [False, True])
def test_fused_pcg_equals_the_plain_v_cycle_pcg(blocks, monkeypatch):
    """The fused fine and P1 levels (fused_sweeps) and CG's product by recurrence: the same iterations and
    the same solution, to round-off, as pcg with pyamg's smoothers on the same hierarchy."""
    from strainwave.fea import solver
    monkeypatch.setattr(solver, "MAX_COARSE", 60)         # a P1 level that is swept, not solved
    from strainwave.fea.pmultigrid import pcg, pcg_with_products, v_cycle, v_cycle_fused
    sk, K, A, fixed = _ball_system()
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    plain = solver._amg_hierarchy(A, free, sk.doflocs, 3, sk.element_dofs)
    assert not hasattr(plain, "fused_sweeps")
    ml = solver._amg_hierarchy(A.tobsr(blocksize=(3, 3)) if blocks else A, free, sk.doflocs, 3, sk.element_dofs,
                               fused=True)
    b = np.random.default_rng(4).random(A.shape[0])
    x0, its0 = pcg(A, b, v_cycle(plain.levels, plain.coarse_solver), rtol=1e-10, maxiter=200)
    assert len(ml.fused_sweeps) == 2        # the fine and the P1 level
    x1, its1 = pcg_with_products(b, v_cycle_fused(ml.fused_sweeps, ml.levels, ml.coarse_solver), rtol=1e-10,
                                 maxiter=200)
    assert its1 == its0 and its0 < 40
    np.testing.assert_allclose(x1, x0, rtol=0, atol=1e-9 * abs(x0).max())
    assert np.linalg.norm(b - A @ x1) <= 2e-10 * np.linalg.norm(b)


def test_solve_takes_the_fused_fine_level_from_min_dofs(monkeypatch):
    """solve_elasticity from fused_sweeps.MIN_DOFS free dofs on: the same u as below it, to the CG tolerance."""
    from strainwave.fea import fused_sweeps, pmultigrid, solver
    sk, K, _, fixed = _ball_system()
    f = np.random.default_rng(5).random(K.shape[0])
    kw = dict(fixed_dofs=fixed, coords=sk.doflocs, dim=3, method="amg", rtol=1e-10, p2_element_dofs=sk.element_dofs)
    u0, i0 = solver.solve_elasticity(K, f, **kw)
    calls = []
    monkeypatch.setattr(fused_sweeps, "MIN_DOFS", 0)
    monkeypatch.setattr(pmultigrid, "pcg_with_products",
                        lambda *a, _f=pmultigrid.pcg_with_products, **k: calls.append(1) or _f(*a, **k))
    u1, i1 = solver.solve_elasticity(K, f, **kw)
    assert calls and i1.iterations == i0.iterations
    np.testing.assert_allclose(u1, u0, rtol=0, atol=1e-8 * abs(u0).max())


def test_solve_with_node_blocks_equals_the_scalar_path():
    """K in node blocks (condensed in blocks, static.py's path) and in CSR solve to the same u."""
    from strainwave.fea.solver import solve_elasticity
    K, rng = _random_block_spd(60, 3, 5)
    f = rng.random(180)
    fixed = np.arange(6 * 3)                              # whole nodes: the block path
    coords = rng.random((3, 60))
    u_csr, i_csr = solve_elasticity(K.tocsr(), f, fixed_dofs=fixed, coords=coords, dim=3, method="direct")
    u_bsr, i_bsr = solve_elasticity(K, f, fixed_dofs=fixed, coords=coords, dim=3, method="direct")
    np.testing.assert_allclose(u_bsr, u_csr, rtol=0, atol=1e-12 * abs(u_csr).max())
    assert np.all(u_bsr[fixed] == 0.0)
    # a fixed dof that is not a whole node falls back to the scalar condensation
    u_part, _ = solve_elasticity(K, f, fixed_dofs=np.array([0, 1, 4]), coords=coords, dim=3, method="direct")
    u_ref, _ = solve_elasticity(K.tocsr(), f, fixed_dofs=np.array([0, 1, 4]), coords=coords, dim=3, method="direct")
    np.testing.assert_allclose(u_part, u_ref, rtol=0, atol=1e-12 * abs(u_ref).max())
    # prescribed non-zero values go through f - K u on the blocks
    vals = np.linspace(0.01, 0.02, fixed.size)
    u_v, _ = solve_elasticity(K, f, fixed_dofs=fixed, fixed_values=vals, coords=coords, dim=3, method="direct")
    u_vr, _ = solve_elasticity(K.tocsr(), f, fixed_dofs=fixed, fixed_values=vals, coords=coords, dim=3, method="direct")
    np.testing.assert_allclose(u_v, u_vr, rtol=0, atol=1e-12 * abs(u_vr).max())
    assert np.array_equal(u_v[fixed], vals)


def test_p1_stiffness_is_the_galerkin_coarse_operator():
    """The p-multigrid's coarse operator assembled on P1 equals R K P of the curved P2 stiffness."""
    import skfem
    from strainwave.fea.assembly import Lame, stiffness
    from strainwave.fea.element_gradients import element_geometry
    from strainwave.fea.mesh_data import to_skfem
    from strainwave.fea.pmultigrid import p1_prolongation, vector_prolongation
    from strainwave.fea.solver import condense_blocks
    from strainwave.fea.static import p1_stiffness
    from tests.test_fea_assembly import _as_gmsh
    sk = to_skfem(_as_gmsh(skfem.MeshTet2.init_ball(2), 3))          # curved P2 elements
    lame = Lame.from_young(2.1e5, 0.3)
    K = stiffness(element_geometry(sk.doflocs, sk.element_dofs, 2), lame, fmt="bsr")
    # a clamped cap: the lowest vertices and the mid nodes between two of them
    n_vert = int(sk.element_dofs[:4].max()) + 1
    keep = np.ones(K.shape[0] // 3, bool)
    keep[np.argsort(sk.doflocs[2, :n_vert])[:12]] = False
    S = p1_prolongation(sk.element_dofs)[0]
    mids = np.arange(n_vert, keep.size)
    keep[mids[~np.any(S[mids].toarray()[:, keep[:n_vert]] != 0, axis=1)]] = False
    free = np.flatnonzero(np.repeat(keep, 3))
    P, coarse_free = vector_prolongation(p1_prolongation(sk.element_dofs)[0], 3, free)
    galerkin = (P.T @ condense_blocks(K, keep).tocsr() @ P).toarray()
    K1 = p1_stiffness(sk, lame)
    is_free = np.zeros(K1.shape[0], bool)
    is_free[coarse_free] = True
    ours = condense_blocks(K1, is_free.reshape(-1, 3)[:, 0]).toarray()
    assert np.abs(ours - galerkin).max() <= 1e-13 * np.abs(galerkin).max()


def test_p1_coarse_operator_only_where_it_is_the_galerkin_one():
    """A fixed mid node on an edge with a free vertex: the hierarchy falls back to R K P."""
    import skfem
    from strainwave.fea import solver
    from strainwave.fea.assembly import Lame, stiffness
    from strainwave.fea.element_gradients import element_geometry
    from strainwave.fea.mesh_data import to_skfem
    from strainwave.fea.static import p1_stiffness
    from tests.test_fea_assembly import _as_gmsh
    sk = to_skfem(_as_gmsh(skfem.MeshTet2.init_ball(2), 3))
    lame = Lame.from_young(2.1e5, 0.3)
    K = stiffness(element_geometry(sk.doflocs, sk.element_dofs, 2), lame, fmt="bsr")
    n_vert = int(sk.element_dofs[:4].max()) + 1
    fixed_nodes = np.concatenate([np.argsort(sk.doflocs[2, :n_vert])[:12], [n_vert + 3]])   # + a lone mid node
    fixed = (3 * fixed_nodes[:, None] + np.arange(3)).ravel()
    f = np.random.default_rng(0).random(K.shape[0])
    calls = []
    kw = dict(fixed_dofs=fixed, coords=sk.doflocs, dim=3, method="amg", rtol=1e-10, p2_element_dofs=sk.element_dofs)
    u1, _ = solver.solve_elasticity(K, f, p1_stiffness=lambda: calls.append(1) or p1_stiffness(sk, lame), **kw)
    u0, _ = solver.solve_elasticity(K, f, **kw)
    assert not calls
    np.testing.assert_allclose(u1, u0, rtol=0, atol=1e-8 * abs(u0).max())


def test_hierarchy_is_the_same_on_every_run_and_leaves_the_global_rng_alone():
    from strainwave.fea.solver import _aggregation
    A = _laplacian_3d(12).tobsr(blocksize=(1, 1))
    B = np.ones((A.shape[0], 1))
    np.random.seed(123)
    before = np.random.get_state()[1].copy()
    one, two = _aggregation(A, B), _aggregation(A, B)
    assert np.array_equal(np.random.get_state()[1], before)
    assert len(one.levels) == len(two.levels) > 1
    for a, b in zip(one.levels, two.levels):
        assert abs(a.A - b.A).max() == 0.0


def test_p1_prolongation_takes_each_mid_nodes_first_edge():
    """p1_prolongation's scatter for first occurrences gives the matrix np.unique(return_index) gave."""
    from strainwave.fea.pmultigrid import EDGE_VERTICES, p1_prolongation
    sk = _ball_system()[0]
    ed = sk.element_dofs
    P, n_vert = p1_prolongation(ed)
    mids = np.concatenate([ed[4 + k] for k in range(6)])
    a = np.concatenate([ed[i] for i, _ in EDGE_VERTICES[10]])
    b = np.concatenate([ed[j] for _, j in EDGE_VERTICES[10]])
    mids, first = np.unique(mids, return_index=True)
    want = sp.csr_matrix((np.concatenate([np.ones(n_vert), np.full(2 * mids.size, 0.5)]),
                          (np.concatenate([np.arange(n_vert), mids, mids]),
                           np.concatenate([np.arange(n_vert), a[first], b[first]]))), shape=P.shape)
    assert np.array_equal(P.indptr, want.indptr) and np.array_equal(P.indices, want.indices)
    assert np.array_equal(P.data, want.data)
