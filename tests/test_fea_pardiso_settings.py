"""The direct solver's PARDISO settings (node-block reading, two-level factorisation) solve as its defaults do."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

pypardiso = pytest.importorskip("pypardiso")


def _elastic_like(n_side: int = 9) -> sp.csr_matrix:
    """SPD, three coupled dofs per node on a 3D grid (the node-block pattern of an elasticity matrix)."""
    lap1 = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n_side, n_side))
    eye = sp.identity(n_side)
    lap3 = (sp.kron(sp.kron(lap1, eye), eye) + sp.kron(sp.kron(eye, lap1), eye) + sp.kron(sp.kron(eye, eye), lap1))
    coupling = np.array([[2.0, 0.5, 0.2], [0.5, 1.5, 0.3], [0.2, 0.3, 1.0]])
    return (sp.kron(lap3, coupling) + 1e-3 * sp.identity(3 * n_side ** 3)).tocsr()


def test_direct_solve_with_the_settings_matches_the_defaults_and_superlu():
    from strainwave.fea.solver import PARDISO_IPARM, _direct, _mkl_rt_known, _pardiso_solver

    A = _elastic_like()
    b = np.random.default_rng(3).standard_normal(A.shape[0])
    x, method = _direct(A, b, "test", node_blocks=True)
    assert method == "pardiso"
    reference = spla.spsolve(A.tocsc(), b)
    assert np.abs(x - reference).max() <= 1e-10 * np.abs(reference).max()
    with _mkl_rt_known():
        default = pypardiso.PyPardisoSolver(mtype=2)
    upper = sp.triu(A, format="csr")
    upper.sort_indices()
    x_default = np.asarray(default.solve(upper, b)).ravel()
    default.free_memory(everything=True)
    assert np.abs(x - x_default).max() <= 1e-10 * np.abs(x_default).max()
    solver = _pardiso_solver(pypardiso, tuned=True)
    assert all(solver.get_iparm(k) == v for k, v in PARDISO_IPARM.items())
    assert solver.get_iparm(1) == 1          # PARDISO reads the settings only when iparm(1) says so
    assert not _pardiso_solver(pypardiso).get_iparm(1)      # 2D systems keep PARDISO's defaults


def test_only_3d_elasticity_takes_the_tuned_settings(monkeypatch):
    """solve_elasticity asks for the node-block settings in 3D and PARDISO's defaults in 2D."""
    from strainwave.fea import solver as solver_module

    seen = []
    original = solver_module._direct

    def spy(A, b, study, *, node_blocks=False):
        seen.append(node_blocks)
        return original(A, b, study, node_blocks=node_blocks)
    monkeypatch.setattr(solver_module, "_direct", spy)
    for dim in (3, 2):
        n_nodes = 27 if dim == 3 else 25
        A = _elastic_like(3) if dim == 3 else (sp.kron(sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n_nodes, n_nodes)),
                                                        np.eye(2)) + sp.identity(2 * n_nodes)).tocsr()
        f = np.ones(A.shape[0])
        coords = np.zeros((dim, n_nodes))
        u, info = solver_module.solve_elasticity(A, f, fixed_dofs=np.arange(dim), coords=coords, dim=dim,
                                                 method="direct")
        assert info.method == "pardiso"
        assert np.abs(A @ u - f)[dim:].max() <= 1e-9 * np.abs(f).max()
    assert seen == [True, False]
