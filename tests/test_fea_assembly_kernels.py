"""The compiled 3D stiffness (numba kernels, fea/assembly_kernels.py) against scikit-fem's stock assembly
and against the numpy path, on a small curved P2 ball."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.assembly import Lame, compiled_stiffness, stiffness
from strainwave.fea.element_gradients import element_geometry
from strainwave.fea.mesh_data import to_skfem
from strainwave.fea.static import p1_stiffness

from test_fea_assembly import _as_gmsh, _skfem_p2

E, NU = 2.1e5, 0.3


@pytest.fixture(scope="module")
def curved_ball():
    mesh, elem = _skfem_p2(3)
    return to_skfem(_as_gmsh(mesh, 3)), elem


def test_compiled_p2_stiffness_equals_stock_skfem(curved_ball):
    import skfem
    from skfem.models.elasticity import linear_elasticity
    sk, elem = curved_ball
    lame = Lame.from_young(E, NU)
    K = compiled_stiffness(sk.doflocs, sk.element_dofs, 2, lame)
    assert K.format == "bsr" and K.blocksize == (3, 3)
    vb = skfem.Basis(sk.mesh, skfem.ElementVector(elem), intorder=2)
    K0 = skfem.asm(linear_elasticity(lame.lam_MPa, lame.mu_MPa), vb)
    # same quadrature, same formula: only the summation order's round-off may differ
    assert abs(K.tocsr() - K0).max() <= 1e-12 * abs(K0).max()
    assert abs(K - K.T).max() == 0.0                  # upper blocks copied below: exactly symmetric
    K2 = K.copy()
    K2.has_sorted_indices = False
    K2.sort_indices()                                 # the flag we set must be true
    assert np.array_equal(K2.indices, K.indices) and np.array_equal(K2.data, K.data)


@pytest.mark.parametrize("field", ["p2", "p1 on curved p2"])
def test_compiled_equals_numpy_path_block_for_block(curved_ball, field):
    sk, _ = curved_ball
    lame = Lame.from_young(E, NU)
    if field == "p2":
        Kn = stiffness(element_geometry(sk.doflocs, sk.element_dofs, 2), lame, fmt="bsr")
        Kc = compiled_stiffness(sk.doflocs, sk.element_dofs, 2, lame)
    else:
        Kn = p1_stiffness(sk, lame)
        Kc = p1_stiffness(sk, lame, compiled=True)
        nv = int(sk.element_dofs[:4].max()) + 1
        assert Kc.shape == (3 * nv, 3 * nv)
    # the same block pattern, in the same (sorted) order, so the solver sees the same structure
    assert np.array_equal(Kc.indptr, Kn.indptr) and np.array_equal(Kc.indices, Kn.indices)
    assert np.abs(Kc.data - Kn.data).max() <= 1e-13 * np.abs(Kn.data).max()


def test_compiled_is_3d_only_and_refuses_a_degenerate_element(curved_ball):
    mesh, _ = _skfem_p2(2)
    sk2 = to_skfem(_as_gmsh(mesh, 2))
    with pytest.raises(ValueError, match="3D only"):
        compiled_stiffness(sk2.doflocs, sk2.element_dofs, 2, Lame.from_young(E, NU))
    sk, _ = curved_ball
    flat = sk.doflocs.copy()
    flat[:, sk.element_dofs[:, 5]] = flat[:, sk.element_dofs[0, 5]][:, None]   # one element crushed to a point
    with pytest.raises(ValueError, match="degenerate"):
        compiled_stiffness(flat, sk.element_dofs, 2, Lame.from_young(E, NU))


def test_condense_blocks_in_place_equals_the_copy(curved_ball):
    from strainwave.fea.solver import condense_blocks
    sk, _ = curved_ball
    K = compiled_stiffness(sk.doflocs, sk.element_dofs, 2, Lame.from_young(E, NU))
    keep = np.random.default_rng(4).random(K.shape[0] // 3) > 0.3
    want = condense_blocks(K, keep)
    K2 = K.copy()
    K2.has_sorted_indices = True                                # a copy forgets the flag; its rows are sorted
    got = condense_blocks(K2, keep, in_place=True)
    assert np.array_equal(got.indptr, want.indptr) and np.array_equal(got.indices, want.indices)
    assert np.array_equal(got.data, want.data)                 # the same blocks, moved: bit for bit
    assert got.shape == want.shape and got.has_sorted_indices


def test_solve_with_consumed_stiffness_equals_the_kept_one(curved_ball):
    from strainwave.fea.solver import solve_elasticity
    sk, _ = curved_ball
    lame = Lame.from_young(E, NU)
    K = compiled_stiffness(sk.doflocs, sk.element_dofs, 2, lame)
    x = sk.doflocs
    fixed_nodes = np.flatnonzero(x[2] < x[2].min() + 0.3)
    fixed = (3 * fixed_nodes[:, None] + np.arange(3)).ravel()
    f = np.zeros(K.shape[0])
    f[2::3] = np.where(x[2] > x[2].max() - 0.3, 1.0, 0.0)
    kw = dict(fixed_dofs=fixed, coords=x, dim=3, method="amg", p2_element_dofs=sk.element_dofs,
              p1_stiffness=lambda: p1_stiffness(sk, lame, compiled=True))
    u0, i0 = solve_elasticity(K.copy(), f, **kw)
    u1, i1 = solve_elasticity(K.copy(), f, consume_K=True, **kw)
    assert i0.iterations == i1.iterations and np.array_equal(u0, u1)


def test_the_mesher_loads_the_assembly_kernels_only_for_a_system_that_will_use_them():
    """A P2 tetrahedral mesh that will reach fused_sweeps.MIN_DOFS starts the kernels' load beside setOrder;
    a smaller one, or one meshed for another process (preload_kernels=False), does not. The dof estimate from
    the linear mesh's vertices errs low (it must not load numba for systems that never use it). A fresh
    interpreter: the load is once per process."""
    import ast
    import subprocess
    import sys
    import textwrap

    script = textwrap.dedent("""
        import warnings
        warnings.simplefilter("ignore")
        import numpy as np
        from strainwave.fea import fused_sweeps
        from strainwave.fea.meshing import expected_p2_dofs, mesh_part
        from strainwave.fea.session import gmsh_session
        from strainwave.geometry.parts import build_part
        from strainwave.params import load_params
        part = build_part("output-shaft", load_params())
        seen = []
        for size_mm, preload in ((3.2, False), (5.2, True), (3.2, True)):
            with gmsh_session() as model:
                md = mesh_part(model, part, size_mm=size_mm, order=2, preload_kernels=preload)
            dofs = 3 * md.nodes_mm.shape[0]
            estimate = expected_p2_dofs(len(np.unique(md.cells[:, :4])))
            seen.append((size_mm, preload, dofs, estimate, fused_sweeps._assembly_thread is not None))
        print(seen)
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    seen = ast.literal_eval(out.stdout.strip().splitlines()[-1])
    (big_dofs, big_estimate), (small_dofs, small_estimate) = seen[0][2:4], seen[1][2:4]
    assert big_dofs > 100_000 > small_dofs
    # the estimate errs low, by at most the spread of P2 nodes per vertex measured (5.9-6.9 against 6.0)
    for dofs, estimate in ((big_dofs, big_estimate), (small_dofs, small_estimate)):
        assert 0.8 * dofs <= estimate <= dofs
    assert [started for *_, started in seen] == [False, False, True]
