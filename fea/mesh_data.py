"""What leaves a gmsh session: nodes, cells and named boundary groups as plain arrays.

``MeshData`` keeps gmsh's node order inside each cell (tet10: vertices 0-3, then the mid-edge nodes of
edges 01, 12, 20, 30, 32, 31; triangle6: 01, 12, 20). ``to_skfem`` turns it into a scikit-fem mesh whose
P2 mid-edge dofs sit exactly on gmsh's (curved, geometry-following) mid nodes, and returns the map from
MeshData node index to scikit-fem scalar dof so boundary groups and fields can be translated.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .result import MeshQuality

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


def _pair_keys(pairs: np.ndarray, n: int) -> np.ndarray:
    lo = np.minimum(pairs[0], pairs[1]).astype(np.int64)
    hi = np.maximum(pairs[0], pairs[1]).astype(np.int64)
    return lo * n + hi


def to_skfem(md: MeshData) -> SkfemMesh:
    """Convert to scikit-fem, P2 mid-edge dofs placed on gmsh's curved mid nodes.

    scikit-fem numbers P2 scalar dofs as vertices first, then one dof per mesh edge in ``mesh.edges``
    order; the mid node of each gmsh cell edge is looked up by its (sorted) vertex pair.
    """
    import skfem

    nv = md.n_vertices_per_cell
    vert_nodes = np.unique(md.cells[:, :nv])
    node_to_dof = np.full(md.nodes_mm.shape[0], -1, dtype=np.int64)
    node_to_dof[vert_nodes] = np.arange(vert_nodes.size)
    p = md.nodes_mm[vert_nodes, :md.dim].T.copy()
    t = node_to_dof[md.cells[:, :nv]].T.copy()
    if md.dim == 3:
        p1 = skfem.MeshTet1(p, t)
        mesh_cls, elem = skfem.MeshTet2, (skfem.ElementTetP1() if md.order == 1 else skfem.ElementTetP2())
    else:
        p1 = skfem.MeshTri1(p, t)
        mesh_cls, elem = skfem.MeshTri2, (skfem.ElementTriP1() if md.order == 1 else skfem.ElementTriP2())
    if md.order == 1:
        return SkfemMesh(p1, node_to_dof, elem)
    mesh2 = mesh_cls.from_mesh(p1)
    n = vert_nodes.size
    edges_of = p1.edges if md.dim == 3 else p1.facets      # P2 edge dofs: one per edge (3D) / facet (2D)
    edge_keys = _pair_keys(np.sort(edges_of, axis=0), n)
    order = np.argsort(edge_keys)
    doflocs = mesh2.doflocs.copy()
    for j, (a, b) in enumerate(GMSH_EDGES[md.dim]):
        keys = _pair_keys(np.vstack([t[a], t[b]]), n)
        pos = np.searchsorted(edge_keys, keys, sorter=order)
        edges = order[np.minimum(pos, order.size - 1)]
        if not np.array_equal(edge_keys[edges], keys):
            raise ValueError("to_skfem: a gmsh cell edge is not an edge of the scikit-fem mesh")
        mid = md.cells[:, nv + j]
        node_to_dof[mid] = n + edges
        doflocs[:, n + edges] = md.nodes_mm[mid, :md.dim].T
    from dataclasses import replace
    mesh2 = replace(mesh2, doflocs=doflocs)
    if (node_to_dof < 0).any():
        raise ValueError("to_skfem: mesh nodes not used by any cell")
    return SkfemMesh(mesh2, node_to_dof, elem)


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
