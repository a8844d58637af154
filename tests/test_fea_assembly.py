"""Fast assembly path: scikit-fem numbering without scikit-fem, element geometry, symmetric block scatter."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from strainwave.fea.assembly import Lame, scalar_basis, stiffness
from strainwave.fea.block_scatter import assemble_symmetric, component_pairs, sorted_groups
from strainwave.fea.element_gradients import element_geometry, geometry_of_basis
from strainwave.fea.mesh_data import GMSH_EDGES, MeshData, to_skfem

E, NU = 2.1e5, 0.3


def _skfem_p2(dim):
    import skfem
    return (skfem.MeshTet2.init_ball(2), skfem.ElementTetP2()) if dim == 3 else \
        (skfem.MeshTri2.init_circle(2), skfem.ElementTriP2())


def _as_gmsh(mesh, dim) -> MeshData:
    """A P2 MeshData (gmsh node order, shuffled node numbering) of a curved scikit-fem P2 mesh."""
    b = scalar_basis(mesh, _skfem_p2(dim)[1])
    nodes = np.zeros((b.N, 3))
    nodes[:, :dim] = b.doflocs.T
    skfem_slot = {(0, 1): 4, (1, 2): 5, (0, 2): 6, (0, 3): 7, (1, 3): 8, (2, 3): 9} if dim == 3 else \
        {(0, 1): 3, (1, 2): 4, (0, 2): 5}
    cols = list(range(dim + 1)) + [skfem_slot[tuple(sorted(e))] for e in GMSH_EDGES[dim]]
    perm = np.random.default_rng(3).permutation(b.N)          # gmsh numbers nodes its own way
    inv = np.argsort(perm)
    return MeshData(nodes[perm], inv[b.element_dofs[cols].T], dim, 2)


@pytest.mark.parametrize("dim", [2, 3])
def test_to_skfem_numbering_is_scikit_fems_own(dim):
    import skfem
    md = _as_gmsh(_skfem_p2(dim)[0], dim)
    sk = to_skfem(md)
    # the mesh built from scratch by scikit-fem numbers edges / facets and P2 dofs identically
    fresh = type(sk.mesh)(sk.mesh.doflocs.copy(), sk.mesh.t.copy())
    if dim == 3:
        assert np.array_equal(fresh.edges, sk.mesh.edges) and np.array_equal(fresh.t2e, sk.mesh.t2e)
    else:
        assert np.array_equal(fresh.facets, sk.mesh.facets) and np.array_equal(fresh.t2f, sk.mesh.t2f)
    b = skfem.Basis(fresh, sk.element, intorder=2)
    assert np.array_equal(b.element_dofs, sk.element_dofs)
    # every MeshData node sits exactly on its scikit-fem dof (copied coordinates: exact)
    assert np.array_equal(b.doflocs.T[sk.node_to_dof], md.nodes_mm[:, :dim])


@pytest.mark.parametrize("dim,order", [(3, 1), (3, 2), (2, 1), (2, 2)])
def test_element_geometry_equals_cellbasis(dim, order):
    import skfem
    if order == 2:
        mesh, elem = _skfem_p2(dim)
    else:
        mesh, elem = (skfem.MeshTet1.init_ball(2), skfem.ElementTetP1()) if dim == 3 else \
            (skfem.MeshTri1.init_circle(2), skfem.ElementTriP1())
    b = scalar_basis(mesh, elem)
    g = element_geometry(b.doflocs, b.element_dofs, order)
    G0 = np.stack([b.basis[i][0].grad for i in range(b.element_dofs.shape[0])]).transpose(0, 1, 3, 2)
    # same formula on the same curved map; only the order of round-off differs
    assert np.abs(g.grad - G0).max() < 1e-13 * np.abs(G0).max()
    assert np.abs(g.dx - b.dx.T).max() < 1e-13 * b.dx.max()


def test_p1_field_on_curved_p2_geometry():
    import skfem
    mesh = skfem.MeshTet2.init_ball(2)
    b = skfem.Basis(mesh, skfem.ElementTetP1(), intorder=2)
    G0 = np.stack([b.basis[i][0].grad for i in range(4)]).transpose(0, 1, 3, 2)
    g = geometry_of_basis(b)
    assert np.abs(g.grad - G0).max() < 1e-13 * np.abs(G0).max()   # round-off only
    assert g.n_dofs == b.N


def test_curved_p2_stiffness_equals_stock_skfem_and_is_symmetric():
    import skfem
    from skfem.models.elasticity import linear_elasticity
    mesh, elem = _skfem_p2(3)
    lame = Lame.from_young(E, NU)
    md = _as_gmsh(mesh, 3)
    sk = to_skfem(md)
    K = stiffness(element_geometry(sk.doflocs, sk.element_dofs, 2), lame, chunk=33)   # odd chunk: exercise the loop
    vb = skfem.Basis(sk.mesh, skfem.ElementVector(elem), intorder=2)
    K0 = skfem.asm(linear_elasticity(lame.lam_MPa, lame.mu_MPa), vb)
    # same quadrature, same formula: only round-off of summation order may differ
    assert abs(K - K0).max() <= 1e-12 * abs(K0).max()
    assert abs(K - K.T).max() == 0.0                             # mirrored, so exactly symmetric
    K2 = K.copy()
    K2.has_sorted_indices = False
    K2.sort_indices()                                            # the flag we set must be true
    assert np.array_equal(K2.indices, K.indices) and np.array_equal(K2.data, K.data)


def test_symmetric_scatter_against_dense_sum():
    rng = np.random.default_rng(5)
    n, dim, m = 40, 3, 600
    I, J = rng.integers(0, n, m), rng.integers(0, n, m)
    C = rng.normal(size=(m, dim, dim))
    C[I == J] = C[I == J] + C[I == J].transpose(0, 2, 1)       # diagonal contributions are symmetric
    dense = np.zeros((n * dim, n * dim))
    for i, j, c in zip(I, J, C):
        dense[dim * i:dim * i + dim, dim * j:dim * j + dim] += c
        if i != j:
            dense[dim * j:dim * j + dim, dim * i:dim * i + dim] += c.T
    ps, pa = component_pairs(dim)
    sym = np.stack([0.5 * (C[:, a, b] + C[:, b, a]) for a, b in ps], axis=1)
    anti = np.stack([0.5 * (C[:, a, b] - C[:, b, a]) for a, b in pa], axis=1)
    for fmt in ("csr", "bsr"):
        K = assemble_symmetric(I, J, np.hstack([sym, anti]), n, dim, fmt)
        assert K.format == fmt
        assert np.abs(K.toarray() - dense).max() < 1e-12 * np.abs(dense).max()   # summation order only
    assert sp.csr_matrix(dense).nnz <= K.nnz


def test_sorted_groups_packed_and_argsort_agree():
    keys = np.random.default_rng(2).integers(0, 50, 1000).astype(np.int64)
    a = sorted_groups(keys.copy())                               # sorted_groups overwrites its input
    b = sorted_groups(keys + (1 << 60))                          # too large to pack: argsort fallback
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert np.array_equal(a[2] + (1 << 60), b[2])
    assert np.array_equal(a[0], np.argsort(keys, kind="stable"))

