"""What leaves a gmsh session: nodes, cells and named boundary groups as plain arrays.

``MeshData`` keeps gmsh's node order inside each cell (tet10: vertices 0-3, then the mid-edge nodes of
edges 01, 12, 20, 30, 32, 31; triangle6: 01, 12, 20). ``to_skfem`` turns it into a scikit-fem mesh whose
P2 mid-edge dofs sit exactly on gmsh's (curved, geometry-following) mid nodes, and returns the map from
MeshData node index to scikit-fem scalar dof so boundary groups and fields can be translated.
Its own numbering makes ``to_skfem`` several times faster than scikit-fem's (docs/decisions/004-assembly-kernels.md).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from strainwave.fea.result import MeshQuality

# gmsh local vertex pairs of the mid-edge nodes, in gmsh's node order after the vertices
GMSH_EDGES = {
    3: ((0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)),   # tet10
    2: ((0, 1), (1, 2), (2, 0)),                           # triangle6
    1: ((0, 1),),                                           # line3
}


@dataclass(frozen=True)
class MeshData:
    """A simplex mesh in millimetres.

    nodes_mm : (N, 3) coordinates (z = 0 for plane meshes).
    cells : (M, k) gmsh-ordered node indices; k = 4/10 (tets) or 3/6 (triangles).
    dim, order : 3 or 2; 1 or 2.
    groups : name -> (F, kf) node indices of the boundary facets of a physical group
             (triangles in 3D, edges in 2D, (F, 1) for point groups = node sets).
    quality : element count and gmsh minSICN summary.
    h_mm : nominal element size it was meshed with.
    """

    nodes_mm: np.ndarray
    cells: np.ndarray
    dim: int
    order: int
    groups: dict[str, np.ndarray] = field(default_factory=dict)
    quality: MeshQuality | None = None
    h_mm: float = float("nan")

    @property
    def n_vertices_per_cell(self) -> int:
        return self.dim + 1

    def dofs(self, components: int | None = None) -> int:
        """Number of vector unknowns (``dim`` components per node unless told)."""
        return self.nodes_mm.shape[0] * (self.dim if components is None else components)

    def group_nodes(self, name: str) -> np.ndarray:
        """Sorted unique node indices of a named group."""
        if name not in self.groups:
            raise KeyError(f"mesh has no group {name!r}; groups: {sorted(self.groups)}")
        return np.unique(self.groups[name])


@dataclass(frozen=True)
class SkfemMesh:
    """A scikit-fem mesh plus the translation from MeshData nodes to its scalar dofs."""

    mesh: object                 # skfem MeshTet1/MeshTet2/MeshTri1/MeshTri2
    node_to_dof: np.ndarray      # (N,) MeshData node -> skfem scalar dof index
    element: object              # the scalar skfem element matching the order
    element_dofs: np.ndarray | None = None   # (nloc, nel) scalar dofs of each cell, scikit-fem local order

    @property
    def doflocs(self) -> np.ndarray:
        """(dim, n) positions of the scalar dofs (P2: vertices, then the curved mid-edge nodes)."""
        return self.mesh.doflocs


def _pair_keys(pairs: np.ndarray, n: int) -> np.ndarray:
    lo = np.minimum(pairs[0], pairs[1]).astype(np.int64)
    hi = np.maximum(pairs[0], pairs[1]).astype(np.int64)
    return lo * n + hi


def _edge_numbering(t: np.ndarray, pairs, n: int) -> tuple[np.ndarray, np.ndarray]:
    """scikit-fem's edge (3D) / facet (2D) numbering: the sorted vertex pairs in lexicographic order
    (what ``Mesh.build_entities`` gives), as (edges (2, ne) int32, t2e (len(pairs), nel)).

    One np.unique of int64 keys, about ten times faster than scikit-fem's np.unique(axis=1) on pairs
    (docs/decisions/004-assembly-kernels.md)."""
    keys = _pair_keys(np.stack([np.stack([t[a], t[b]]) for a, b in pairs], axis=1).reshape(2, -1), n)
    ukeys, t2e = np.unique(keys, return_inverse=True)
    edges = np.ascontiguousarray(np.vstack([ukeys // n, ukeys % n]).astype(np.int32))
    return edges, t2e.reshape(len(pairs), t.shape[1])


def to_skfem(md: MeshData) -> SkfemMesh:
    """Convert to scikit-fem, P2 mid-edge dofs placed on gmsh's curved mid nodes.

    scikit-fem numbers P2 scalar dofs as vertices first, then one dof per mesh edge (3D) / facet (2D)
    in its lexicographic (sorted vertex pair) order; the P2 mesh is built directly from those dof
    positions, with that numbering cached in it so scikit-fem does not compute it again.
    """
    import skfem

    from strainwave.fea.element_gradients import SKFEM_EDGES

    nv = md.n_vertices_per_cell
    vert_nodes = np.flatnonzero(np.bincount(md.cells[:, :nv].ravel(), minlength=md.nodes_mm.shape[0]))  # = np.unique
    node_to_dof = np.full(md.nodes_mm.shape[0], -1, dtype=np.int64)
    node_to_dof[vert_nodes] = np.arange(vert_nodes.size)
    p = md.nodes_mm[vert_nodes, :md.dim].T.copy()
    t = np.ascontiguousarray(node_to_dof[md.cells[:, :nv]].T.astype(np.int32))
    three = md.dim == 3
    if md.order == 1:
        mesh = (skfem.MeshTet1 if three else skfem.MeshTri1)(p, t)
        return SkfemMesh(mesh, node_to_dof, skfem.ElementTetP1() if three else skfem.ElementTriP1(), t)
    n = vert_nodes.size
    edges, t2e = _edge_numbering(t, SKFEM_EDGES[md.dim], n)
    mids = md.cells[:, nv + np.array(_gmsh_to_skfem(md.dim))].T          # (n_edges_per_cell, nel)
    edge_node = np.empty(edges.shape[1], np.int64)
    edge_node[t2e] = mids
    if not np.array_equal(edge_node[t2e], mids):
        raise ValueError("to_skfem: cells sharing an edge disagree on its mid node")
    node_to_dof[edge_node] = n + np.arange(edges.shape[1])
    if (node_to_dof < 0).any():
        raise ValueError("to_skfem: mesh nodes not used by any cell")
    doflocs = np.vstack([p.T, md.nodes_mm[edge_node, :md.dim]]).T.copy()
    element_dofs = np.vstack([t, n + t2e])
    mesh = (skfem.MeshTet2 if three else skfem.MeshTri2)(doflocs, t)
    # scikit-fem caches its entities in these attributes; setting them skips recomputing the same
    # numbering (checked against scikit-fem's own in tests/test_fea_assembly.py)
    if three:
        mesh._edges, mesh._t2e = edges, t2e
    else:
        mesh._facets, mesh._t2f = edges, t2e
    return SkfemMesh(mesh, node_to_dof, skfem.ElementTetP2() if three else skfem.ElementTriP2(), element_dofs)


def _gmsh_to_skfem(dim: int) -> list[int]:
    """For each scikit-fem P2 edge slot, the gmsh mid-node slot of the same vertex pair."""
    from strainwave.fea.element_gradients import SKFEM_EDGES
    gmsh_slot = {tuple(sorted(e)): j for j, e in enumerate(GMSH_EDGES[dim])}
    return [gmsh_slot[p] for p in SKFEM_EDGES[dim]]


def facet_indices(sk: SkfemMesh, md: MeshData, name: str) -> np.ndarray:
    """scikit-fem facet indices of the named boundary group (matched by sorted vertex tuples)."""
    mesh = sk.mesh
    nv = md.dim            # vertices per facet
    facets = md.groups[name][:, :nv] if name in md.groups else None
    if facets is None:
        raise KeyError(f"mesh has no group {name!r}; groups: {sorted(md.groups)}")
    verts = np.sort(sk.node_to_dof[facets].T, axis=0).astype(np.int64)
    n = np.int64(mesh.nvertices)
    if n ** nv >= 2 ** 62:
        raise ValueError("facet_indices: too many vertices for integer facet keys")

    def key(v):
        k = v[0]
        for row in v[1:]:
            k = k * n + row
        return k

    mesh_keys = key(np.sort(mesh.facets, axis=0).astype(np.int64))
    order = np.argsort(mesh_keys)
    wanted = key(verts)
    pos = np.minimum(np.searchsorted(mesh_keys, wanted, sorter=order), order.size - 1)
    idx = order[pos]
    if not np.array_equal(mesh_keys[idx], wanted):
        raise ValueError(f"facet_indices: group {name!r} has facets that are not mesh facets")
    return idx


def group_dofs(sk: SkfemMesh, md: MeshData, name: str) -> np.ndarray:
    """scikit-fem scalar dofs (vertex and mid-edge) on a named group."""
    return np.unique(sk.node_to_dof[md.group_nodes(name)])
