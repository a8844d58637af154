"""A through-wall crack's local patch as a tip-graded plane mesh extruded through the wall.

A straight through-wall front carries the r^1/2 field across it but varies slowly along it (only near the
two free faces). So the patch's plane (the wall unrolled: in-plane coordinates x, y) is meshed once in 2D,
its sizes growing linearly with the distance from each tip (rings of elements in geometric progression),
and extruded through the wall in layers on a cosine spacing (thinnest at the free faces, where the field
turns from plane strain to the faces' corner field). Each prism becomes three tets whose diagonals agree
across shared faces; mid-edge nodes follow, at the quarter point of the edges leaving the front if asked
(they draw the r^1/2 field); then ``to_xyz`` maps the slab (x, y, w), w through the wall, onto the part.
Groups: "cut" (the patch's four side faces, held at the global field), "crack", "faces" (w = +-t/2).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from strainwave.fea.mesh_data import GMSH_EDGES, MeshData

__all__ = ["PlaneGrading", "cosine_layers", "cosine_planes", "crack_tips_xy", "cylinder_map", "extruded_patch",
           "plane_patch_mesh"]

_TET_FACES = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
_TRI_EDGES = ((0, 1), (1, 2), (2, 0))      # triangle6 mid-node order


@dataclass(frozen=True)
class PlaneGrading:
    """The patch's 2D mesh and layers in units of the crack half-length a, for refinement factor f = 1
    (finest): tip size ``tip_over_a`` a, growing by ``growth`` per unit distance from the nearest tip up to
    ``far_over_a`` a, and ``layers`` through the wall; a coarser mesh multiplies the sizes and the growth by
    f and divides the layers by f."""

    tip_over_a: float
    growth: float
    far_over_a: float
    layers: int
    quarter_point: bool = True
    # ``layers`` is the most: the finest mesh takes the fewest whose layer at each face is no thicker than the
    # tip (the faces' corner zone scales with a; a thin wall's field hardly varies through it)
    face_layer_to_tip: bool = False

    def sizes(self, a_mm: float, f: float, wall_mm: float | None = None) -> tuple[float, float, float, int]:
        """(tip, far, growth, layers) of the mesh at refinement factor ``f`` >= 1 through a wall of ``wall_mm``
        (needed with ``face_layer_to_tip``)."""
        finest = self.layers
        if self.face_layer_to_tip:
            finest = cosine_layers(wall_mm, self.tip_over_a * a_mm, self.layers)
        layers = max(2, int(round(finest / f)))
        return f * self.tip_over_a * a_mm, f * self.far_over_a * a_mm, min(1.0, f * self.growth), layers


def cosine_planes(wall_mm: float, layers: int) -> np.ndarray:
    """The ``layers`` + 1 node planes w through the wall [-t/2, t/2] on a cosine spacing (thinnest at the faces)."""
    return -0.5 * wall_mm * np.cos(np.pi * np.arange(layers + 1) / layers)


def cosine_layers(wall_mm: float, face_mm: float, most: int) -> int:
    """The fewest layers (2 to ``most``) of ``cosine_planes`` through ``wall_mm`` whose outermost,
    t/2 (1 - cos(pi/n)), is at most ``face_mm``."""
    if not (wall_mm > 0.0 and face_mm > 0.0 and math.isfinite(wall_mm) and math.isfinite(face_mm)):
        raise ValueError(f"cosine_layers: wall {wall_mm!r} and face layer {face_mm!r} mm must be finite and > 0")
    n = math.ceil(math.pi / math.acos(max(-1.0, 1.0 - 2.0 * face_mm / wall_mm)) - 1e-9)
    return int(min(most, max(2, n)))


def plane_patch_mesh(model, half_size_mm: float, tips_xy: np.ndarray, *, tip_mm: float, far_mm: float,
                     growth: float) -> MeshData:
    """Linear triangles of the square |x|, |y| <= L with the crack segment between ``tips_xy`` (2, 2)
    embedded (group "crack", edges) and the square's sides (group "cut"); sizes ``tip_mm`` within one tip
    size of each tip, growing by ``growth`` per mm of distance to ``far_mm``."""
    from strainwave.fea.meshing import Refine, extract, generate
    L = half_size_mm
    rect = model.occ.addRectangle(-L, -L, 0.0, 2 * L, 2 * L)
    p = [model.occ.addPoint(float(x), float(y), 0.0) for x, y in tips_xy]
    crack = model.occ.addLine(p[0], p[1])
    model.occ.fragment([(2, rect)], [(1, crack)])
    model.occ.synchronize()
    inside = [t for _, t in model.getEntities(1)
              if max(abs(c) for c in model.occ.getCenterOfMass(1, t)[:2]) < L * (1 - 1e-9)]
    sides = [t for _, t in model.getEntities(1) if t not in inside]
    groups = {"crack": (1, inside), "cut": (1, sides)}
    refine = [Refine(tip_mm, tip_mm, tip_mm + (far_mm - tip_mm) / growth,
                     points_mm=tuple((float(x), float(y), 0.0) for x, y in tips_xy))]
    generate(model, 2, 1, size_mm=far_mm, refine=refine, preload_kernels=False)
    return extract(model, 2, 1, groups, far_mm)


def _prism_tets(tri: np.ndarray, n2: int, layers: int) -> np.ndarray:
    """(3 layers ntri, 4) tets of the prisms over ``tri`` between node planes k and k + 1 (node id k n2 + i).
    Vertices sorted per triangle: every quad face is cut from its higher-numbered bottom vertex to its
    lower-numbered top vertex, the same rule on both sides of the face, so the tets conform."""
    v0, v1, v2 = np.sort(tri, axis=1).T
    out = []
    for k in range(layers):
        b, t = k * n2, (k + 1) * n2
        out += [np.stack([v0 + b, v1 + b, v2 + b, v0 + t], 1), np.stack([v1 + b, v2 + b, v0 + t, v1 + t], 1),
                np.stack([v2 + b, v0 + t, v1 + t, v2 + t], 1)]
    return np.vstack(out)


def _oriented(tets: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Tets with positive volume in the slab's coordinates (two vertices swapped where negative)."""
    e = x[tets[:, 1:]] - x[tets[:, :1]]
    neg = np.einsum("ij,ij->i", np.cross(e[:, 0], e[:, 1]), e[:, 2]) < 0
    tets = tets.copy()
    tets[neg, 1], tets[neg, 2] = tets[neg, 2], tets[neg, 1].copy()
    return tets


def _mid_nodes(tets: np.ndarray, x: np.ndarray, front: np.ndarray, quarter_point: bool):
    """(mid-node coordinates, key -> mid-node index function): one node per tet edge, at the edge's middle
    or, for an edge with exactly one end on the front, at its quarter point next to the front."""
    n = x.shape[0]
    pairs = np.concatenate([tets[:, [a, b]] for a, b in GMSH_EDGES[3]])
    keys = np.minimum(pairs[:, 0], pairs[:, 1]) * n + np.maximum(pairs[:, 0], pairs[:, 1])
    ukeys, first = np.unique(keys, return_index=True)
    a, b = pairs[first, 0], pairs[first, 1]
    t = np.full(a.size, 0.5)
    if quarter_point:
        on = np.isin(a, front), np.isin(b, front)
        t[on[0] & ~on[1]], t[on[1] & ~on[0]] = 0.25, 0.75
    mids = x[a] + t[:, None] * (x[b] - x[a])

    def index(p, q):
        k = np.minimum(p, q) * n + np.maximum(p, q)
        return n + np.searchsorted(ukeys, k)
    return mids, index


def _facets(tets: np.ndarray, label: np.ndarray, pick: Callable[[np.ndarray], np.ndarray], index) -> np.ndarray:
    """(F, 6) triangle6 facets of the tets picked by ``pick`` (on their vertices' ``label``), each once."""
    faces = np.concatenate([tets[:, list(f)] for f in _TET_FACES])
    faces = faces[pick(label[faces])]
    faces = faces[np.unique(np.sort(faces, axis=1), axis=0, return_index=True)[1]]
    return np.hstack([faces] + [index(faces[:, a], faces[:, b])[:, None] for a, b in _TRI_EDGES])


def _on_edges(edges: np.ndarray, n2: int) -> Callable[[np.ndarray], np.ndarray]:
    """Picks the vertical faces whose three 2D ids are the two ends of one of ``edges`` (E, 2)."""
    keys = np.unique(np.minimum(edges[:, 0], edges[:, 1]) * n2 + np.maximum(edges[:, 0], edges[:, 1]))

    def pick(ids):
        s = np.sort(ids, axis=1)
        two = (s[:, 1] != s[:, 0]) ^ (s[:, 2] != s[:, 1])     # exactly two distinct ids: a vertical face
        return two & np.isin(s[:, 0] * n2 + s[:, 2], keys)
    return pick


def extruded_patch(plane: MeshData, wall_mm: float, layers: int, to_xyz: Callable[[np.ndarray], np.ndarray], *,
                   quarter_point: bool = True, h_mm: float = float("nan")) -> MeshData:
    """The P2 tet mesh of ``plane`` (linear triangles with groups "crack" and "cut") extruded through
    w in [-t/2, t/2] in ``layers`` on a cosine spacing, mapped by ``to_xyz`` ((n, 3) slab -> (n, 3) mm)."""
    xy, tri = plane.nodes_mm[:, :2], plane.cells[:, :3]
    n2 = xy.shape[0]
    w = cosine_planes(wall_mm, layers)
    x = np.hstack([np.tile(xy, (layers + 1, 1)), np.repeat(w, n2)[:, None]])
    plane_id = np.tile(np.arange(n2), layers + 1)
    tets = _oriented(_prism_tets(tri, n2, layers), x)
    crack = plane.groups["crack"][:, :2]
    ends, counts = np.unique(crack, return_counts=True)
    front = np.flatnonzero(np.isin(plane_id, ends[counts == 1]))
    mids, index = _mid_nodes(tets, x, front, quarter_point)
    cells = np.hstack([tets] + [index(tets[:, a], tets[:, b])[:, None] for a, b in GMSH_EDGES[3]])
    groups = {"crack": _facets(tets, plane_id, _on_edges(crack, n2), index),
              "cut": _facets(tets, plane_id, _on_edges(plane.groups["cut"][:, :2], n2), index)}
    level = np.repeat(np.arange(layers + 1), n2)
    groups["faces"] = _facets(tets, level, lambda lv: (lv == lv[:, :1]).all(axis=1) & np.isin(lv[:, 0], (0, layers)),
                              index)
    nodes = to_xyz(np.vstack([x, mids]))
    return MeshData(nodes_mm=nodes, cells=cells, dim=3, order=2, groups=groups, h_mm=h_mm)


def cylinder_map(r_mid_mm: float, theta_rad: float, z_mm: float) -> Callable[[np.ndarray], np.ndarray]:
    """Slab (x along the arc at r_m, y axial, w radial from r_m) -> (x, y, z) mm on the tube wall centred
    at angle ``theta_rad``, height ``z_mm``: the unrolled wall rolled back onto its cylinder."""
    def to_xyz(p):
        r, phi = r_mid_mm + p[:, 2], theta_rad + p[:, 0] / r_mid_mm
        return np.stack([r * np.cos(phi), r * np.sin(phi), z_mm + p[:, 1]], axis=1)
    return to_xyz


def crack_tips_xy(half_length_mm: float, angle_deg: float) -> np.ndarray:
    """(2, 2) tips of a crack of half-length a through the slab's centre at ``angle_deg`` from the y axis."""
    d = np.array([math.sin(math.radians(angle_deg)), math.cos(math.radians(angle_deg))])
    return np.stack([-half_length_mm * d, half_length_mm * d])
