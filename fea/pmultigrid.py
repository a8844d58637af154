"""p-multigrid for quadratic elements: the P2 system's first coarse level is P1 on the same mesh.

Smoothed aggregation struggles with P2 stiffness matrices: their graph mixes vertex and mid-edge
couplings of very different strength, and on the 238k-dof shaft it needed 85 CG iterations. Linear
interpolation from the vertices (P1 -> P2, exact for linear fields) gives a geometric coarse level
with 1/7 of the unknowns on which the same aggregation works as designed. Measured on that system
(benchmarks/bench_fea.py, one core): SA alone 17.6 s / 85 its (theta 0), 9.8 s / 32 its (theta
0.05); P2 -> P1 -> SA 6.1 s / 26 its (theta 0.02), with a setup of 1.5 s.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

# Local mid-edge dofs of scikit-fem's P2 elements, in element_dofs order after the vertices:
# ElementTetP2 numbers its edges like MeshTet.t2e, ElementTriP2 like MeshTri.t2f.
EDGE_VERTICES = {10: ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)), 6: ((0, 1), (1, 2), (0, 2))}


def p1_prolongation(element_dofs: np.ndarray) -> tuple[sp.csr_matrix, int]:
    """Scalar interpolation P1 -> P2 on one mesh: (n_P2 x n_vertices) and the vertex count.

    Vertex dofs come first in scikit-fem's P2 numbering, so the vertex block is the identity; each
    mid-edge dof takes the mean of its edge's two vertices."""
    nloc = element_dofs.shape[0]
    if nloc not in EDGE_VERTICES:
        raise ValueError(f"p1_prolongation: {nloc} local dofs is not a P2 triangle or tetrahedron")
    nvloc = 4 if nloc == 10 else 3
    n_vert = int(element_dofs[:nvloc].max()) + 1
    n = int(element_dofs.max()) + 1
    mids = np.concatenate([element_dofs[nvloc + k] for k in range(nloc - nvloc)])
    a = np.concatenate([element_dofs[i] for i, _ in EDGE_VERTICES[nloc]])
    b = np.concatenate([element_dofs[j] for _, j in EDGE_VERTICES[nloc]])
    mids, first = np.unique(mids, return_index=True)
    rows = np.concatenate([np.arange(n_vert), mids, mids])
    cols = np.concatenate([np.arange(n_vert), a[first], b[first]])
    vals = np.concatenate([np.ones(n_vert), np.full(2 * mids.size, 0.5)])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n_vert)), n_vert


def vector_prolongation(scalar: sp.csr_matrix, dim: int, free: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Interleaved vector prolongation restricted to the free fine dofs and the free coarse dofs.

    A coarse (vertex) dof is free when the same dof of the fine system is free; a mid-edge dof next
    to a fixed vertex keeps only its free neighbour's weight, which is the right interpolation of a
    field that vanishes on the fixed dofs."""
    P = sp.kron(scalar, sp.identity(dim, format="csr"), format="csr")
    n_fine = P.shape[0]
    is_free = np.zeros(n_fine, bool)
    is_free[free] = True
    coarse_free = np.flatnonzero(is_free[:P.shape[1]])       # vertex dofs are the first fine dofs
    return P[free][:, coarse_free].tocsr(), coarse_free
