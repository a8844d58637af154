"""The circular spline's body bolted face-on to a rigid housing, in 3D (issue 48, decision 070).

The body is the ring from the internal teeth's root ``ri`` to the outer radius ``ro``, ``b`` wide (z from 0,
the mounting face, to b). Loads per unit output torque, as decision 069 section 3: at the two major axes the
tangential F_t = 1 / (2 r_p) and the radial F_r = F_t tan(alpha) of each zone, as tractions on the bore over
+-``PATCH_DEG`` and the whole face width. Restraint (``Restraint``): FREE, the body held only against rotation
by a uniform shear on its outer surface (the soft bound, as fea/cs_body_fe.py in plane stress); FACE, every
node of the mounting face z = 0 with ``clamp_r`` (r_lo, r_hi) fixed to a rigid housing (the whole face: the
stiff bound of a one-face mounting; a band: the bolt annulus).

Mesh: as fea/ring_solid.py, a structured (theta, r, z) lattice of hexahedra split into six Kuhn tetrahedra, P2.
The two zones are opposite, so the body is solved on one quarter, theta in [0, pi/2]: the tangential load is
antisymmetric about y = 0 and x = 0 (u_x = u_z = 0 on y = 0; u_y = u_z = 0 on x = 0), the radial load symmetric
(u_y = 0 on y = 0; u_x = 0 on x = 0); the quarter carries a quarter of the torque and of the work. Compliance by
work (f . u / T^2, the loads' rigid motions are held or do no work); the radial opening u is closed by a twist
u tan(alpha) / r_p (the rack's flank gap), as in the plane model.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np
from skfem import Basis, ElementTetP2, ElementVector, FacetBasis, MeshTet, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

from strainwave.fea.cs_body_fe import PATCH_DEG, traction_forms
from strainwave.fea.solver import solve_elasticity

__all__ = ["Restraint", "BodyCase", "quarter_lattice", "cs_housing_twist_rad_per_Nmm", "PATCH_DEG", "levels"]

NU = 0.3
# the six Kuhn tetrahedra of the unit cube (vertex bits: theta, r, z): all share the 0-7 diagonal, so the
# split is conforming across every face of the lattice
_KUHN = ((0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7))


class Restraint(str, Enum):
    FREE = "free"           # held against rotation only (a shear reaction on the outer surface)
    FACE = "face"           # the mounting face (within clamp_r) clamped to a rigid housing
    BOLTS = "bolts"         # only the bolt heads' footprints on the mounting face clamped, the face free between
    HOUSING = "housing"     # the face bonded to an elastic housing flange (the same annulus, housing_mm thick,
                            # housing_E_MPa), whose far face is clamped


@dataclass(frozen=True)
class BodyCase:
    ri_mm: float            # the internal teeth's root radius
    ro_mm: float            # the outer radius
    b_mm: float             # the body's (and the engaged teeth's) width
    r_p_mm: float           # the pitch radius, where the tooth loads act
    alpha_deg: float
    E_MPa: float
    restraint: Restraint = Restraint.FACE
    clamp_r: tuple[float, float] = (0.0, 1.0)   # the clamped band on the face, as fractions of ro - ri from ri
    n_bolts: int = 16       # BOLTS: a multiple of 4, at (j + 1/2) 2 pi / n (the quarter's symmetry)
    footprint: float = 0.25  # BOLTS: the footprint's radius over ro - ri, centred mid-body
    housing_mm: float = 0.0  # HOUSING: the flange's thickness (z from -housing_mm to 0)
    housing_E_MPa: float = 2.1e5

    def __post_init__(self):
        if not 0.0 < self.ri_mm < self.ro_mm:
            raise ValueError(f"the body's root radius {self.ri_mm:g} mm must lie inside its outer radius {self.ro_mm:g}")
        if self.restraint is Restraint.BOLTS and (self.n_bolts < 4 or self.n_bolts % 4):
            raise ValueError(f"n_bolts = {self.n_bolts}: a multiple of 4 (the quarter model's symmetry)")
        if self.restraint is Restraint.HOUSING and not self.housing_mm > 0.0:
            raise ValueError(f"housing_mm = {self.housing_mm:g}: a flange thickness > 0")


def levels(k: int) -> tuple[int, int, int]:
    """(n_theta on the quarter, n_r, n_z) of refinement level k: the patch edge lies on a lattice line (5 / k deg)."""
    return 18 * k, k, 2 * k


def quarter_lattice(ri, ro, b, nt, nr, nz, housing_mm: float = 0.0) -> MeshTet:
    """The quarter body theta in [0, pi/2] as a Kuhn-split hexahedral lattice (straight-sided tetrahedra); with
    ``housing_mm`` the lattice continues below z = 0 at the same spacing (the housing flange)."""
    t = np.linspace(0.0, 0.5 * math.pi, nt + 1)
    r = np.linspace(ri, ro, nr + 1)
    z = np.linspace(0.0, b, nz + 1)
    if housing_mm > 0.0:
        nh = max(1, int(round(housing_mm / b * nz)))
        z = np.concatenate([np.linspace(-housing_mm, 0.0, nh + 1)[:-1], z])
        nz = len(z) - 1
    T, R, Z = np.meshgrid(t, r, z, indexing="ij")
    p = np.vstack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel(), Z.ravel()])
    idx = np.arange(p.shape[1]).reshape(nt + 1, nr + 1, nz + 1)
    corners = [idx[i:nt + i, j:nr + j, k:nz + k].ravel() for k in (0, 1) for j in (0, 1) for i in (0, 1)]
    # corner bit order: bit 0 theta, bit 1 r, bit 2 z
    tets = np.hstack([np.vstack([corners[a] for a in kuhn]) for kuhn in _KUHN])
    return MeshTet(p, tets)


def _facets_at_radius(m, r_mm: float):
    """The boundary facets whose three vertices lie on the cylinder r = ``r_mm`` (lattice vertices lie on it)."""
    rv = np.hypot(m.p[0], m.p[1])
    on = np.abs(rv - r_mm) < 1e-9 * r_mm
    f = m.boundary_facets()
    return f[np.all(on[m.facets[:, f]], axis=0)]


def _loads(ib, m, case: BodyCase):
    """(tangential load of torque 1/4, its reaction as a uniform outer shear, radial load of F_r / 2): the quarter's
    share of the two zones' loads per unit output torque."""
    e = ib.elem
    inner = FacetBasis(m, e, facets=_facets_at_radius(m, case.ri_mm))
    outer = FacetBasis(m, e, facets=_facets_at_radius(m, case.ro_mm))
    s = math.sin(math.radians(PATCH_DEG))
    # the patch at theta 0 on the body's bore (not the housing flange's, z < 0)
    tang_in, rad_in = traction_forms(lambda x: (np.abs(np.sin(np.arctan2(x[1], x[0]))) < s) * (x[2] > -1e-9))
    tang_out, _ = traction_forms(lambda x: 1.0)

    ux, uy, _ = ib.split_indices()
    x, y = ib.doflocs[0], ib.doflocs[1]
    rot = np.zeros(ib.N)                                    # the rigid rotation: a load's torque is f . rot
    rot[ux], rot[uy] = -y[ux], x[uy]
    radial = np.zeros(ib.N)
    radial[ux], radial[uy] = x[ux] / np.hypot(x[ux], y[ux]), y[uy] / np.hypot(x[uy], y[uy])
    fi, fo, fr = asm(tang_in, inner), asm(tang_out, outer), asm(rad_in, inner)
    F_r = math.tan(math.radians(case.alpha_deg)) / (2.0 * case.r_p_mm)
    return 0.25 * fi / (fi @ rot), 0.25 * fo / (fo @ rot), fr / (fr @ radial) * 0.5 * F_r


def _fixed(ib, case: BodyCase, load: str) -> np.ndarray:
    """The symmetry planes' dofs for ``load`` and the restraint's (the clamped face, or a determinate support)."""
    ux, uy, uz = ib.split_indices()
    x, y, z = ib.doflocs
    eps = 1e-9 * case.ro_mm
    on_y0, on_x0 = np.abs(y) < eps, np.abs(x) < eps          # the planes y = 0 (theta 0) and x = 0 (theta 90 deg)
    if load == "tangential":        # antisymmetric: the in-plane components along each plane vanish
        parts = [ux[on_y0[ux]], uz[on_y0[uz]], uy[on_x0[uy]], uz[on_x0[uz]]]
    else:                           # symmetric: the normal component vanishes
        parts = [uy[on_y0[uy]], ux[on_x0[ux]]]
    r = np.hypot(x, y)
    h = case.ro_mm - case.ri_mm
    if case.restraint is Restraint.FACE:
        lo, hi = case.ri_mm + case.clamp_r[0] * h - eps, case.ri_mm + case.clamp_r[1] * h + eps
        face = (np.abs(z) < eps) & (r > lo) & (r < hi)
        parts += [ux[face[ux]], uy[face[uy]], uz[face[uz]]]
    elif case.restraint is Restraint.HOUSING:
        far = np.abs(z + case.housing_mm) < eps
        parts += [ux[far[ux]], uy[far[uy]], uz[far[uz]]]
    elif case.restraint is Restraint.BOLTS:
        th = np.arctan2(y, x)
        c = 0.5 * (case.ri_mm + case.ro_mm)
        pitch = 2.0 * math.pi / case.n_bolts
        near = (np.floor(th / pitch) + 0.5) * pitch                # the nearest bolt's angle
        dist = np.hypot(x - c * np.cos(near), y - c * np.sin(near))
        face = (np.abs(z) < eps) & (dist < case.footprint * h + eps)
        parts += [ux[face[ux]], uy[face[uy]], uz[face[uz]]]
    else:                           # held against rotation (tangential) or z-translation (radial) at one node
        node = np.flatnonzero((np.abs(r - case.ro_mm) < eps) & (np.abs(z) < eps)
                              & (np.abs(y - r * math.sin(math.pi / 4)) < 1e-6 * r))
        a = node[0] if node.size else int(np.argmin(np.abs(z) + np.abs(r - case.ro_mm)))
        parts.append(np.array([(uy if load == "tangential" else uz)[a]]))
    return np.unique(np.concatenate(parts))


def cs_housing_twist_rad_per_Nmm(case: BodyCase, k: int) -> tuple[dict, int]:
    """({"tangential", "radial"} output twist per N mm of output torque, dofs) on refinement level ``k``."""
    nt, nr, nz = levels(k)
    housing = case.housing_mm if case.restraint is Restraint.HOUSING else 0.0
    m = quarter_lattice(case.ri_mm, case.ro_mm, case.b_mm, nt, nr, nz, housing)
    e = ElementVector(ElementTetP2())
    ib = Basis(m, e)
    lam, mu = lame_parameters(case.E_MPa, NU)
    K = asm(linear_elasticity(lam, mu), ib).tocsr()
    if housing > 0.0:               # the housing's elements at their own modulus
        below = np.flatnonzero(m.p[2, m.t].mean(axis=0) < 0.0)
        K = K + (case.housing_E_MPa / case.E_MPa - 1.0) * asm(linear_elasticity(lam, mu),
                                                              Basis(m, e, elements=below)).tocsr()
    f_t, f_o, f_r = _loads(ib, m, case)
    loads = {"tangential": f_t - f_o if case.restraint is Restraint.FREE else f_t, "radial": f_r}
    out = {}
    for name, f in loads.items():
        D = _fixed(ib, case, name)
        u, _ = solve_elasticity(K, f, fixed_dofs=D, coords=ib.doflocs[:, ::3], dim=3, method="direct",
                                study="cs-housing")
        work = 4.0 * float(f @ u)                           # four quarters
        if name == "radial":                                # mean opening at the patches, closed by a twist
            F_r = math.tan(math.radians(case.alpha_deg)) / (2.0 * case.r_p_mm)
            work = work / (2.0 * F_r) * math.tan(math.radians(case.alpha_deg)) / case.r_p_mm
        out[name] = work
    return out, ib.N
