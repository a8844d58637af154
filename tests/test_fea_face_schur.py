"""The crack face's contact by one factorisation: the Schur complement on the face dofs (PARDISO and SuperLU)
equals the dense one, and every contact set held through it gives the direct constrained solve's displacement
and compliance (fea/face_schur.py ``FaceSystem``)."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp


def _elastic_like(n_side: int = 6) -> sp.csr_matrix:
    """SPD with three coupled dofs per node on a 3D grid."""
    lap1 = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n_side, n_side))
    eye = sp.identity(n_side)
    lap3 = sp.kron(sp.kron(lap1, eye), eye) + sp.kron(sp.kron(eye, lap1), eye) + sp.kron(sp.kron(eye, eye), lap1)
    coupling = np.array([[2.0, 0.5, 0.2], [0.5, 1.5, 0.3], [0.2, 0.3, 1.0]])
    return (sp.kron(lap3, coupling) + 1e-3 * sp.identity(3 * n_side ** 3)).tocsr()


@pytest.mark.parametrize("backend", ["pardiso", "splu"])
def test_schur_factor_gives_the_dense_schur_complement_and_full_solves(backend, monkeypatch):
    from strainwave.fea import solver
    A = _elastic_like()
    tail = np.array([5, 17, 18, 40, 300, 301, A.shape[0] - 1])
    if backend == "splu":
        factor = solver._schur_splu(A, tail, "test")
    else:
        pytest.importorskip("pypardiso")
        factor = solver.schur_factor(A, tail, "test")
    dense = A.toarray()
    inner = np.setdiff1d(np.arange(A.shape[0]), tail)
    S = dense[np.ix_(tail, tail)] - dense[np.ix_(tail, inner)] @ np.linalg.solve(dense[np.ix_(inner, inner)],
                                                                               dense[np.ix_(inner, tail)])
    b = np.random.default_rng(1).standard_normal((A.shape[0], 2))
    try:
        assert np.abs(factor.S - S).max() <= 1e-12 * np.abs(S).max()
        assert np.abs(factor.solve(b) - np.linalg.solve(dense, b)).max() <= 1e-10 * np.abs(np.linalg.solve(dense, b)).max()
        # the tail's own block of A (the elimination left out) misses it: the comparison can fail
        assert np.abs(factor.S - dense[np.ix_(tail, tail)]).max() > 1e-2 * np.abs(S).max()
    finally:
        factor.close()


def _cube():
    """Elastic unit cube (P1 tets): z = 0 holds its normal dofs at x > 0.5 (the ligament); x < 0.5 is the face;
    x = 0 holds u_x, one corner u_y; the top pulled by a z-load varying in y."""
    import skfem
    from skfem.models.elasticity import lame_parameters, linear_elasticity
    mesh = skfem.MeshTet.init_tensor(*(np.linspace(0.0, 1.0, 6),) * 3)
    basis = skfem.Basis(mesh, skfem.ElementVectorH1(skfem.ElementTetP1()))
    K = skfem.asm(linear_elasticity(*lame_parameters(2.0e5, 0.3)), basis).tocsr()
    x = mesh.p
    nodes = np.arange(mesh.p.shape[1])
    on_plane = np.isclose(x[2], 0.0)
    ligament, face = nodes[on_plane & (x[0] > 0.5)], nodes[on_plane & (x[0] < 0.5)]
    corner = int(np.flatnonzero(np.all(np.isclose(x.T, [0.0, 1.0, 0.0]), axis=1))[0])
    base = np.unique(np.concatenate([3 * ligament + 2, 3 * nodes[np.isclose(x[0], 0.0)], [3 * corner + 1]]))
    f = np.zeros(K.shape[0])
    top = nodes[np.isclose(x[2], 1.0)]
    f[3 * top + 2] = 1.0 - 2.0 * x[1, top]
    return K, f, base, 3 * face + 2, mesh


def _direct(K, f, fixed, mesh):
    from strainwave.fea.solver import solve_elasticity
    return solve_elasticity(K, f, fixed_dofs=fixed, fixed_values=0.0, coords=np.repeat(mesh.p, 3, axis=1),
                            dim=3, method="direct")[0]


def test_every_contact_set_through_the_schur_complement_is_the_direct_constrained_solve():
    from strainwave.fea.face_schur import FaceSystem, open_compliance
    from strainwave.fea.surface_crack import contact_state
    K, f, base, face_z, mesh = _cube()
    system = FaceSystem.of(K, base, face_z, "test")
    try:
        r = system.face_loads(f[:, None])[:, 0]
        shut = _direct(K, f, np.concatenate([base, face_z]), mesh)
        rng = np.random.default_rng(7)
        for active in (np.zeros(face_z.size, bool), np.ones(face_z.size, bool), rng.random(face_z.size) < 0.4):
            u = _direct(K, f, np.concatenate([base, face_z[active]]), mesh)
            assert np.abs(system.held(f, r, active) - u).max() <= 1e-10 * np.abs(u).max()
            assert open_compliance(system.factor.S, r, active) == pytest.approx(f @ u - f @ shut, rel=1e-9, abs=1e-14 * (f @ u))
        # the converged set: the bending presses the y > 1/2 half shut, no held point pulls, no open point overlaps
        active, iterations, u = contact_state(system, f, r, np.zeros(face_z.size, bool))
        # the same set after as many iterations as the rule applied to each iteration's full solution
        ref, ref_iterations = np.zeros(face_z.size, bool), 0
        while ref_iterations < 30:
            ref_iterations += 1
            v = system.held(f, r, ref)
            holds, enters = (K @ v - f)[face_z] >= -1e-9 * np.abs(f).max(), v[face_z] < -1e-9 * np.abs(v).max()
            new = (ref & holds) | (~ref & enters)
            if np.array_equal(new, ref):
                break
            ref = new
        assert np.array_equal(active, ref) and iterations == ref_iterations > 1
        y = mesh.p[1, face_z // 3]
        assert active[y > 0.7].all() and not active[y < 0.3].any()
        assert np.all((K @ u - f)[face_z[active]] >= -1e-9 * np.abs(f).max()) and np.all(u[face_z[~active]] >= 0.0)
        # a different contact set is another compliance: the comparison above can fail
        assert open_compliance(system.factor.S, r, ~active) != pytest.approx(open_compliance(system.factor.S, r, active),
                                                                             rel=1e-3)
    finally:
        system.factor.close()


def test_a_block_nothing_holds_with_the_face_free_is_refused():
    # without the ligament no dof holds u_z once the face is free: the factorisation must say so, not return S
    from strainwave.errors import StageError
    from strainwave.fea.face_schur import FaceSystem
    K, _, base, face_z, mesh = _cube()
    x, nodes = mesh.p, np.arange(mesh.p.shape[1])
    no_ligament = base[~np.isin(base, 3 * nodes[np.isclose(x[2], 0.0) & (x[0] > 0.5)] + 2)]
    FaceSystem.of(K, base, face_z, "test").factor.close()       # with it: factorised
    with pytest.raises(StageError, match="PARDISO"):
        FaceSystem.of(K, no_ligament, face_z, "test")
