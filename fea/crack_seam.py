"""Open an embedded crack surface: duplicate its nodes so that its two faces separate (same mesh).

The standard fracture-mechanics "seam" crack: the part is meshed uncracked with the crack surface as a
conforming internal surface (``meshing.mesh_part`` with a ``Part.crack_surface``, group "crack"); the
uncracked solve uses that mesh as is, and ``open_crack`` turns it into the cracked mesh by giving the
elements on the + side of the surface their own copies of the crack nodes. Nodes on the crack FRONT
(crack-surface boundary edges that are not on the exterior boundary of the volume) are shared by both
sides, so the crack closes there; the mouth edges, which lie on the exterior surface, open. Because both
solves see the identical mesh, their difference carries (almost) no discretization noise of the far field.
"""
from __future__ import annotations

import dataclasses

import numpy as np
from scipy.spatial import cKDTree

from strainwave.errors import StageError
from strainwave.fea.mesh_data import MeshData
from strainwave.fea.result import CrackRecord

_TET_FACES = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
_TRI_EDGES = ((0, 1, 3), (1, 2, 4), (2, 0, 5))       # vertex a, vertex b, mid-node column (triangle6)


def _keys(rows: np.ndarray, n: int) -> np.ndarray:
    """One int64 per row of sorted node indices (rows of 2 or 3 nodes)."""
    r = np.sort(rows, axis=1).astype(np.int64)
    k = r[:, 0]
    for j in range(1, r.shape[1]):
        k = k * n + r[:, j]
    return k


def crack_front_nodes(md: MeshData, group: str = "crack") -> np.ndarray:
    """Sorted node indices that stay shared: the vertices of the crack FRONT edges (crack-surface boundary
    edges that are not edges of the volume mesh's exterior boundary) and, for P2, the mid nodes of the
    crack edges between two such vertices."""
    n = md.nodes_mm.shape[0]
    if n ** 3 >= 2 ** 62:
        raise ValueError("crack_front_nodes: too many nodes for integer face keys")
    facets = md.groups[group]
    edges = np.vstack([facets[:, [a, b]] for a, b, _ in _TRI_EDGES])
    ekeys = _keys(edges, n)
    uniq, inv, cnt = np.unique(ekeys, return_inverse=True, return_counts=True)
    boundary = cnt[inv] == 1
    faces = np.vstack([md.cells[:, list(f)] for f in _TET_FACES])
    fk, first, fcnt = np.unique(_keys(faces, n), return_index=True, return_counts=True)
    crack_fk = _keys(facets[:, :3], n)
    pos = np.minimum(np.searchsorted(fk, crack_fk), fk.size - 1)
    if not (np.array_equal(fk[pos], crack_fk) and (fcnt[pos] == 2).all()):
        raise ValueError(f"group {group!r} is not a conforming internal surface of the tetrahedral mesh")
    ext_faces = faces[first[fcnt == 1]]          # faces of one element only: the exterior boundary
    ext_edges = np.unique(np.concatenate([_keys(ext_faces[:, [a, b]], n) for a, b in ((0, 1), (1, 2), (0, 2))]))
    front = boundary & ~np.isin(ekeys, ext_edges)
    verts = np.unique(edges[front])
    if facets.shape[1] != 6:
        return verts
    # P2: the mid node of every crack edge whose two vertices both stay shared stays shared too - the
    # front edges, and also an edge joining two front vertices across a corner facet: one edge has one
    # mid node (duplicating it alone would give the two sides different mid nodes on one edge)
    mids = np.concatenate([facets[:, m] for _, _, m in _TRI_EDGES])
    closed = np.isin(edges, verts).all(axis=1)
    return np.unique(np.concatenate([verts, mids[closed]]))


def _oriented_normals(md: MeshData, facets: np.ndarray) -> np.ndarray:
    """Unit facet normals flipped to agree with one reference: the seam cracks are planar (the geometry's
    ``Part.crack_plane``), so one orientation holds for every facet. The reference is the first facet's
    normal with its largest component made positive, so + is a fixed side (+y for a plane y = const)."""
    x = md.nodes_mm[facets[:, :3]]
    nrm = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    ref = nrm[0] * np.sign(nrm[0][np.argmax(np.abs(nrm[0]))])
    return nrm * np.where(nrm @ ref < 0, -1.0, 1.0)[:, None]


def element_sides(md: MeshData, cells: np.ndarray, group: str = "crack") -> np.ndarray:
    """+1 / -1 for each given cell: sign of its centroid's distance to the nearest crack facet's plane."""
    facets = md.groups[group]
    nrm = _oriented_normals(md, facets)
    x0 = md.nodes_mm[facets[:, :3]].mean(axis=1)
    c = md.nodes_mm[md.cells[cells, :4]].mean(axis=1)
    _, near = cKDTree(x0).query(c)
    sd = np.einsum("ij,ij->i", c - x0[near], nrm[near])
    return np.where(sd > 0, 1, -1)


def open_crack(md: MeshData, group: str = "crack") -> MeshData:
    """The cracked mesh: every crack node not on the front duplicated, + side elements renumbered.

    Elements touching a duplicated node go to the + side when their centroid lies on the positive side of
    the nearest crack facet's plane. Boundary groups whose facets touch duplicated nodes follow their
    owning element; the crack itself becomes "crack_minus" (original nodes) and "crack_plus" (copies).
    Works for P1 and P2 (tet10 / triangle6) meshes."""
    if group not in md.groups:
        raise KeyError(f"mesh has no crack group {group!r}; groups: {sorted(md.groups)}")
    n = md.nodes_mm.shape[0]
    facets = md.groups[group]
    dup = np.setdiff1d(np.unique(facets), crack_front_nodes(md, group))
    if dup.size == 0:    # e.g. two triangles whose corners all lie on the front: the crack stays shut
        raise ValueError(f"the mesh does not resolve the crack: all {np.unique(facets).size} nodes of group "
                         f"{group!r} lie on its front; refine the front below the crack size")
    new_id = np.full(n, -1, dtype=np.int64)
    new_id[dup] = n + np.arange(dup.size)
    is_dup = new_id >= 0
    touched = np.flatnonzero(is_dup[md.cells].any(axis=1))
    plus = touched[element_sides(md, touched, group) > 0]
    cells = md.cells.copy()
    sub = cells[plus]
    cells[plus] = np.where(is_dup[sub], new_id[sub], sub)
    # owner side of boundary facets that touch duplicated nodes: look their face up among touched cells
    owner = {}
    for c in touched:
        for f in _TET_FACES:
            owner[tuple(sorted(md.cells[c, list(f)]))] = c
    plus_set = set(plus.tolist())
    groups = {}
    for name, rows in md.groups.items():
        if name == group:
            continue
        rows = rows.copy()
        if rows.shape[1] >= 3:
            for i in np.flatnonzero(is_dup[rows].any(axis=1)):
                c = owner.get(tuple(sorted(rows[i, :3])))
                if c is not None and c in plus_set:
                    rows[i] = np.where(is_dup[rows[i]], new_id[rows[i]], rows[i])
        groups[name] = rows
    groups[f"{group}_minus"] = facets.copy()
    groups[f"{group}_plus"] = np.where(is_dup[facets], new_id[facets], facets)
    nodes = np.vstack([md.nodes_mm, md.nodes_mm[dup]])
    quality = None if md.quality is None else dataclasses.replace(
        md.quality, nodes=int(nodes.shape[0]), dofs=int(nodes.shape[0] * md.dim))
    return dataclasses.replace(md, nodes_mm=nodes, cells=cells, groups=groups, quality=quality)


def open_crack_for(md: MeshData, study: str, group: str = "crack") -> MeshData:
    """``open_crack`` for a study: an unresolved crack becomes ``StageError("mesh", study, ...)``."""
    try:
        return open_crack(md, group)
    except ValueError as exc:
        raise StageError("mesh", study, str(exc)) from exc


def seam_crack(depth_mm: float, part, what: str) -> CrackRecord:
    """A crack solved as a 3D seam; its plane's z (from the part) centres the report's close-up."""
    return CrackRecord(depth_mm, f"3D seam ({what}): one mesh per refinement, solved closed and opened",
                       part.meta.get("crack_z_mm"))
