"""Integrals over named boundary groups straight from MeshData's (curved) facets.

scikit-fem's FacetBasis on an isoparametric mesh locates each facet quadrature point inside its element
by Newton iteration, which fails on strongly curved or sliver P2 tets (coarse meshes of thin walls,
elements at a crack slot). A facet's own shape functions need no inversion: the trace of a P2 (P1)
element on a facet is the 6-node (3-node) triangle, or the 3-node (2-node) line in 2D, so tractions and
face averages are integrated on the facets themselves, in gmsh node order.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.fea.mesh_data import MeshData


def _shape(kind: str, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions (nq, k) and their reference derivatives (nq, k, rdim), gmsh node order."""
    if kind == "tri6":
        x, y = X
        l1 = 1 - x - y
        N = np.stack([l1 * (2 * l1 - 1), x * (2 * x - 1), y * (2 * y - 1), 4 * l1 * x, 4 * x * y, 4 * y * l1], 1)
        dx = np.stack([-(4 * l1 - 1), 4 * x - 1, 0 * x, 4 * (l1 - x), 4 * y, -4 * y], 1)
        dy = np.stack([-(4 * l1 - 1), 0 * x, 4 * y - 1, -4 * x, 4 * x, 4 * (l1 - y)], 1)
        return N, np.stack([dx, dy], 2)
    if kind == "tri3":
        x, y = X
        N = np.stack([1 - x - y, x, y], 1)
        one = np.ones_like(x)
        return N, np.stack([np.stack([-one, one, 0 * x], 1), np.stack([-one, 0 * x, one], 1)], 2)
    s = X[0]
    if kind == "line3":
        N = np.stack([(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)], 1)
        return N, np.stack([4 * s - 3, 4 * s - 1, 4 - 8 * s], 1)[:, :, None]
    N = np.stack([1 - s, s], 1)
    return N, np.stack([-np.ones_like(s), np.ones_like(s)], 1)[:, :, None]


@dataclass(frozen=True)
class SurfaceQuadrature:
    nodes: np.ndarray      # (nf, k) MeshData node indices of each facet
    N: np.ndarray          # (nq, k) shape functions at the quadrature points
    x: np.ndarray          # (nf, nq, 3) quadrature points, mm
    dA: np.ndarray         # (nf, nq) weights times area (2D: length, per unit thickness)

    @classmethod
    def of(cls, md: MeshData, group: str, *, order: int = 4) -> "SurfaceQuadrature":
        from skfem.quadrature import get_quadrature
        from skfem.refdom import RefLine, RefTri
        facets = md.groups[group] if group in md.groups else None
        if facets is None:
            raise KeyError(f"mesh has no group {group!r}; groups: {sorted(md.groups)}")
        k = facets.shape[1]
        kind = {(3, 6): "tri6", (3, 3): "tri3", (2, 3): "line3", (2, 2): "line2"}[(md.dim, k)]
        X, W = get_quadrature(RefTri if md.dim == 3 else RefLine, order)
        N, dN = _shape(kind, X)
        xn = md.nodes_mm[facets]                                  # (nf, k, 3)
        x = np.einsum("qk,fkc->fqc", N, xn)
        T = np.einsum("qkr,fkc->fqrc", dN, xn)                     # tangents
        if md.dim == 3:
            jac = np.linalg.norm(np.cross(T[:, :, 0], T[:, :, 1]), axis=-1)
        else:
            jac = np.linalg.norm(T[:, :, 0], axis=-1)
        return cls(facets, N, x, jac * W[None, :])

    @property
    def area(self) -> float:
        return float(self.dA.sum())

    def integrate(self, values: np.ndarray) -> float:
        """int f dA for f given at the quadrature points (nf, nq)."""
        return float((values * self.dA).sum())

    def interpolate(self, nodal: np.ndarray) -> np.ndarray:
        """Nodal field (N, c) -> quadrature values (nf, nq, c)."""
        return np.einsum("qk,fkc->fqc", self.N, nodal[self.nodes])

    def load_vector(self, traction, node_to_dof: np.ndarray, dim: int, n_dofs: int) -> np.ndarray:
        """Consistent nodal forces f = int t(x) N_k dA (interleaved dofs: dim * scalar_dof + c).

        traction : x (dim, nf, nq) -> t (dim, nf, nq) in MPa (same convention as the skfem forms)."""
        xt = np.moveaxis(self.x[..., :dim], -1, 0)
        t = np.asarray(traction(xt))                                 # (dim, nf, nq)
        fk = np.einsum("cfq,qk,fq->fkc", t, self.N, self.dA)          # (nf, k, dim)
        dofs = node_to_dof[self.nodes]                                # (nf, k)
        f = np.zeros(n_dofs)
        for c in range(dim):
            f += np.bincount((dim * dofs + c).ravel(), weights=fk[..., c].ravel(), minlength=n_dofs)
        return f
