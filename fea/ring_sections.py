"""Reading a solved ring: diameter changes of the mid-layer, hoop stress at a section, tooth-root peaks.

Seed 003 states its results at the mid-layer (eqs 3-5) and at the fibres of sections B (phi = 0, +x)
and D (phi = 90 deg, under the load, +y). The FEA field is sampled at exactly those points with the
element's own gradient (no nodal averaging, which would smear the bending stress through a thin wall).
Works for 2D (plane stress, points in xy) and 3D (points at a chosen z) vector bases.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.fea.assembly import Lame

__all__ = ["MidLayer", "Probes", "boundary_stress_MPa", "fibre_points", "find_cells", "hoop", "hoop_at", "mid_layer",
           "mid_layer_points", "peak_near", "section_hoop_MPa", "signed_principal", "stress_at_points"]

# Sampling a fibre exactly on the boundary could land on an element edge from outside the mesh;
# a relative inset of 1e-7 of the wall thickness is far below any stress gradient that matters.
_INSET = 1e-7


def _stress_from_grad(grad: np.ndarray, lame: Lame) -> np.ndarray:
    """Cauchy stress (dim, dim, ...) from the displacement gradient (dim, dim, ...); plane-stress Lame in 2D."""
    eps = 0.5 * (grad + np.swapaxes(grad, 0, 1))
    tr = np.einsum("ii...->...", eps)
    eye = np.eye(grad.shape[0]).reshape(grad.shape[:2] + (1,) * (grad.ndim - 2))
    return lame.lam_MPa * tr * eye + 2 * lame.mu_MPa * eps


def find_cells(mesh, points_mm: np.ndarray) -> np.ndarray:
    """Cell index containing each point (dim, n).

    scikit-fem has no point search on quadratic meshes; the straight-sided mesh of the same vertices finds
    the cell, and the curved mapping's inverse then gives the exact reference point (a point in the thin
    sliver between a chord and its arc gets reference coordinates marginally outside the triangle, where
    the element polynomial is still the right field to first order in the sliver width).
    """
    import skfem

    linear = skfem.MeshTri1 if mesh.dim() == 2 else skfem.MeshTet1
    verts = np.ascontiguousarray(mesh.p[:, :mesh.nvertices])
    straight = linear(verts, np.ascontiguousarray(mesh.t))
    finder = straight.element_finder()
    centroids = verts[:, mesh.t].mean(axis=1)
    cells = []
    for pt in points_mm.T:
        try:
            cells.append(int(finder(*pt[:, None])[0]))
        except ValueError:
            # in the sliver outside the chord: the cell at the nearest vertex whose centroid is closest
            near = np.argmin(((verts - pt[:, None]) ** 2).sum(axis=0))
            around = np.nonzero((mesh.t == near).any(axis=0))[0]
            cells.append(int(around[np.argmin(((centroids[:, around] - pt[:, None]) ** 2).sum(axis=0))]))
    return np.array(cells)


@dataclass(frozen=True)
class Probes:
    """A field's own element at each of n points: one CellBasis over the n containing cells with the n reference
    points as its quadrature, read on its diagonal (cell i at point i); every solution on the mesh reads it."""

    basis: object

    @classmethod
    def at(cls, basis, points_mm: np.ndarray, *, vector: bool = False) -> "Probes":
        """Probes of ``basis``' element (``vector``: of its vector element, no vector basis of the whole mesh made)
        at points (dim, n): the global dofs shared, no dof locations made."""
        from skfem import CellBasis, ElementVector
        from skfem.assembly import Dofs
        elem = ElementVector(basis.elem) if vector else basis.elem
        cells = find_cells(basis.mesh, points_mm)
        ref = basis.mapping.invF(points_mm[:, :, None], tind=cells)[:, :, 0]      # (dim, n)
        return cls(CellBasis(basis.mesh, elem, mapping=basis.mapping, elements=cells,
                             quadrature=(ref, np.ones(cells.size)),
                             dofs=Dofs(basis.mesh, elem) if vector else basis.dofs, disable_doflocs=True))

    def values(self, u: np.ndarray) -> np.ndarray:
        """The field at the points, (dim, n)."""
        i = np.arange(self.basis.nelems)
        return np.asarray(self.basis.interpolate(u))[:, i, i]

    def stresses(self, u: np.ndarray, lame: Lame) -> np.ndarray:
        """Stress tensors (n, dim, dim) at the points."""
        i = np.arange(self.basis.nelems)
        return np.moveaxis(_stress_from_grad(self.basis.interpolate(u).grad[:, :, i, i], lame), -1, 0)


def stress_at_points(basis, u: np.ndarray, points_mm: np.ndarray, lame: Lame) -> np.ndarray:
    """Stress tensors (n, dim, dim) at points (dim, n), from the element containing each point."""
    return Probes.at(basis, points_mm).stresses(u, lame)


def hoop(sigma: np.ndarray, angle_rad: float) -> np.ndarray:
    """sigma_theta_theta from Cartesian (n, dim, dim) stresses at polar angle ``angle_rad``."""
    s, c = np.sin(angle_rad), np.cos(angle_rad)
    return sigma[:, 0, 0] * s * s + sigma[:, 1, 1] * c * c - 2.0 * sigma[:, 0, 1] * s * c


def fibre_points(angle_rad: float, r_inner_mm: float, r_outer_mm: float, z_mm: float | None = None) -> np.ndarray:
    """(outer, inner) fibre points of the section at ``angle_rad``, just inside the material."""
    inset = _INSET * (r_outer_mm - r_inner_mm)
    radii = np.array([r_outer_mm - inset, r_inner_mm + inset])
    pts = [radii * np.cos(angle_rad), radii * np.sin(angle_rad)]
    if z_mm is not None:
        pts.append(np.full(2, z_mm))
    return np.array(pts)


def section_hoop_MPa(basis, u, angle_rad: float, r_inner_mm: float, r_outer_mm: float, lame: Lame,
                     z_mm: float | None = None) -> tuple[float, float]:
    """(outer, inner) fibre hoop stress at a section (seed 003, eqs 8 and 9 give their thin-ring values)."""
    pts = fibre_points(angle_rad, r_inner_mm, r_outer_mm, z_mm)
    h = hoop(stress_at_points(basis, u, pts, lame), angle_rad)
    return float(h[0]), float(h[1])


@dataclass(frozen=True)
class MidLayer:
    """Displacements of the mid-layer at C (-y), D (+y), A (-x), B (+x) and the diameter changes."""

    u_C_mm: np.ndarray
    u_D_mm: np.ndarray
    u_A_mm: np.ndarray
    u_B_mm: np.ndarray

    @property
    def delta_cd_mm(self) -> float:
        """Shortening of the loaded diameter CD (seed 003, eq 3)."""
        return float(self.u_C_mm[1] - self.u_D_mm[1])

    @property
    def delta_ab_mm(self) -> float:
        """Lengthening of the perpendicular diameter AB (seed 003, eq 4)."""
        return float(self.u_B_mm[0] - self.u_A_mm[0])


def mid_layer_points(r_m_mm: float, z_mm: float | None = None) -> np.ndarray:
    """The mid-layer points C, D, A, B (dim, 4)."""
    xy = np.array([[0.0, 0.0, -r_m_mm, r_m_mm], [-r_m_mm, r_m_mm, 0.0, 0.0]])
    return xy if z_mm is None else np.vstack([xy, np.full(4, z_mm)])


def mid_layer(basis, u, r_m_mm: float, z_mm: float | None = None) -> MidLayer:
    """Displacement of the mid-layer points C, D, A, B (probes: the FE interpolant at the exact points)."""
    return MidLayer(*Probes.at(basis, mid_layer_points(r_m_mm, z_mm)).values(u).T)


def boundary_stress_MPa(facet_basis, u, lame: Lame) -> tuple[np.ndarray, np.ndarray]:
    """Stress tensors (n, dim, dim) and positions (dim, n) at every facet quadrature point."""
    grad = facet_basis.interpolate(u).grad                       # (dim, dim, nf, nq)
    sig = np.moveaxis(_stress_from_grad(grad, lame), (0, 1), (-2, -1))
    dim = sig.shape[-1]
    return sig.reshape(-1, dim, dim), facet_basis.global_coordinates().value.reshape(dim, -1)


def signed_principal(sigma: np.ndarray) -> np.ndarray:
    """Largest-magnitude principal stress, signed, of (n, dim, dim) tensors.

    On a free surface (tooth-root fillet) the stress is uniaxial along the surface, so this is the
    root stress a fatigue check uses."""
    eig = np.linalg.eigvalsh(sigma)
    return np.take_along_axis(eig, np.abs(eig).argmax(axis=-1)[:, None], axis=-1)[:, 0]


def hoop_at(sigma: np.ndarray, xyz: np.ndarray) -> np.ndarray:
    """Hoop stress of (n, dim, dim) tensors at their own polar angles."""
    ang = np.arctan2(xyz[1], xyz[0])
    s, c = np.sin(ang), np.cos(ang)
    return sigma[:, 0, 0] * s * s + sigma[:, 1, 1] * c * c - 2.0 * sigma[:, 0, 1] * s * c


def peak_near(values: np.ndarray, xyz: np.ndarray, angle_rad: float, window_rad: float) -> float:
    """The signed value of largest magnitude among points within +/- window of a polar angle."""
    ang = np.arctan2(xyz[1], xyz[0])
    d = np.abs(np.angle(np.exp(1j * (ang - angle_rad))))
    sel = values[d <= window_rad]
    if sel.size == 0:
        raise ValueError(f"no boundary points within {window_rad:.3g} rad of {angle_rad:.3g} rad")
    return float(sel[np.abs(sel).argmax()])
