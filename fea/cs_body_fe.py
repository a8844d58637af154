"""The circular spline body under the two mesh zones by FE (decision 069, item 3): a plane-stress annulus
(scikit-fem, P2 triangles on a polar grid) from the internal teeth's root to the outer diameter, the face width
thick. Loads per unit output torque: (a) tangential patches on the bore at the two major axes (+-``patch_deg``),
reacted by a uniform tangential shear on the outer surface (the bolts); (b) two outward radial patches F_r =
tan(alpha) / (2 r_p) each. Compliance by work (f . u / T^2; the loads are self-equilibrated, so rigid motions do no
work); the radial opening u is closed by a twist u tan(alpha) / r_p (the rack's flank gap)."""
from __future__ import annotations

import math

import numpy as np
from skfem import Basis, ElementTriP2, ElementVector, FacetBasis, LinearForm, MeshTri, asm, condense, solve
from skfem.models.elasticity import lame_parameters, linear_elasticity

__all__ = ["annulus", "cs_body_fe_twist_rad_per_Nmm", "traction_forms", "PATCH_DEG"]

PATCH_DEG = 5.0


def annulus(ri, ro, nr, nt):
    r = np.linspace(ri, ro, nr + 1)
    t = np.linspace(0.0, 2.0 * math.pi, nt, endpoint=False)
    R, T = np.meshgrid(r, t, indexing="ij")
    p = np.vstack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()])
    idx = np.arange((nr + 1) * nt).reshape(nr + 1, nt)
    a, b = idx[:-1, :], idx[:-1, np.r_[1:nt, 0]]
    c, d = idx[1:, np.r_[1:nt, 0]], idx[1:, :]
    tri = np.hstack([np.vstack([a.ravel(), b.ravel(), c.ravel()]), np.vstack([a.ravel(), c.ravel(), d.ravel()])])
    return MeshTri(p, tri)


def traction_forms(mask):
    """(unit tangential, unit radial) traction about the z axis times ``mask(x)``, as load forms (2D or 3D)."""
    @LinearForm
    def tangential(v, w):
        th = np.arctan2(w.x[1], w.x[0])
        return mask(w.x) * (-np.sin(th) * v[0] + np.cos(th) * v[1])

    @LinearForm
    def radial(v, w):
        th = np.arctan2(w.x[1], w.x[0])
        return mask(w.x) * (np.cos(th) * v[0] + np.sin(th) * v[1])
    return tangential, radial


def cs_body_fe_twist_rad_per_Nmm(ri, ro, E, b, r_p, alpha_deg, nr, nt):
    """({"tangential", "radial"} twist per N mm, dofs) of the annulus ri..ro on nr x nt polar cells."""
    m = annulus(ri, ro, nr, nt)
    e = ElementVector(ElementTriP2())
    ib = Basis(m, e)
    lam, mu = lame_parameters(E, 0.3)
    lam = 2.0 * lam * mu / (lam + 2.0 * mu)                 # plane stress
    K = b * asm(linear_elasticity(lam, mu), ib)
    tol = 0.5 * (ro - ri) / nr                              # facet midpoints of the polygon lie inside the circle
    inner = FacetBasis(m, e, facets=m.facets_satisfying(lambda x: np.hypot(x[0], x[1]) < ri + tol))
    outer = FacetBasis(m, e, facets=m.facets_satisfying(lambda x: np.hypot(x[0], x[1]) > ro - tol))

    def patch(x):
        th = np.arctan2(x[1], x[0])
        return (np.abs(np.sin(th)) < math.sin(math.radians(PATCH_DEG))).astype(float)

    tang_in, rad_in = traction_forms(patch)
    tang_out, _ = traction_forms(lambda x: 1.0)

    ux, uy = ib.split_indices()
    x, y = ib.doflocs[0], ib.doflocs[1]
    rot = np.zeros(ib.N)                                    # the rigid rotation field: a load's torque is f . rot
    rot[ux], rot[uy] = -y[ux], x[uy]
    fi, fo = asm(tang_in, inner), asm(tang_out, outer)
    f_t = fi / (fi @ rot) - fo / (fo @ rot)                # torque +1 at the teeth, -1 at the bolts
    fr = asm(rad_in, inner)
    radial_field = np.zeros(ib.N)
    radial_field[ux], radial_field[uy] = x[ux] / np.hypot(x[ux], y[ux]), y[uy] / np.hypot(x[uy], y[uy])
    F_r = math.tan(math.radians(alpha_deg)) / (2.0 * r_p)
    f_r = fr / (fr @ radial_field) * 2.0 * F_r              # two patches, F_r each
    # a statically determinate support: both dofs of the node at (ro, 0), the tangential dof at (-ro, 0)
    pA = np.argmin(np.hypot(m.p[0] - ro, m.p[1]))
    pB = np.argmin(np.hypot(m.p[0] + ro, m.p[1]))
    D = np.array([ib.nodal_dofs[0][pA], ib.nodal_dofs[1][pA], ib.nodal_dofs[1][pB]])
    out = {}
    for name, f in (("tangential", f_t), ("radial", f_r)):
        u = solve(*condense(K, f, D=D))
        work = float(f @ u)
        out[name] = work if name == "tangential" else (work / (2.0 * F_r)) * math.tan(math.radians(alpha_deg)) / r_p
    return out, ib.N


