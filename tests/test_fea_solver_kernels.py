"""Solver kernels: ``solver.condense`` is K[keep][:, keep]; ``pmultigrid.pcg`` with ``v_cycle`` solves SPD systems."""
import numpy as np
import pytest
import scipy.sparse as sp

from strainwave.fea.solver import condense


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
