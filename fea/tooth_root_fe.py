"""The flexspline tooth's root stress from its mesh load: a plane-strain FE of a sector of the toothed rim whose
middle tooth has the cup's root fillets (the study's whole rim has sharp roots: its compliance converges there,
a stress does not).

The sector: tooth 0 and ``TEETH_EACH_SIDE`` teeth either side on the rim down to the bore; the bore held radially
(the rigid wave generator, as the study's rim), the sector's two radial cuts clamped (the rest of the rim, a few
rim thicknesses away). The fillets are circles tangent to the root circle and the flank
(geometry/involute._fitted_fillet, the CAD's). One flank load (the study's parabolic band) on tooth 0; the
stress is the L2 projection of the P2 field onto P2, read on the two fillets of tooth 0: the peak max-principal
(tensile) stress per newton of flank load. Linear, so the study scales it by its most loaded tooth's load.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.fea import tooth_mesh_fe as fe

__all__ = ["fillet_geometry", "sector_outline", "root_stress_per_N"]

TEETH_EACH_SIDE = 3
TOOTH_H_RATIO = 0.25              # element size in the loaded tooth over the rim's
# element size at the fillets over the rim's (the study's h): rho/8 at the finest (1/6 read non-monotone)
FILLET_H_RATIO = 0.1


def fillet_geometry(spec) -> dict:
    """rho, the fillet centre's angle off the tooth centre (dphi), its centre radius, the flank foot radius r_t."""
    from strainwave.geometry.involute import _fitted_fillet
    rho, dphi, r_t, psi_t = _fitted_fillet(spec)
    if psi_t is None:
        raise ValueError("tooth root: the cup's fillet does not fit its tooth space")
    return {"rho_mm": rho, "dphi_rad": dphi, "centre_radius_mm": spec.root_radius_mm + rho, "r_t_mm": r_t}


def _arc(c: np.ndarray, rho: float, p0: np.ndarray, p1: np.ndarray, n: int) -> np.ndarray:
    """Points of the short circular arc about ``c`` from p0 to p1 (ends excluded)."""
    a0, a1 = (math.atan2(*(p - c)[::-1]) for p in (p0, p1))
    da = (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
    a = a0 + da * np.linspace(0.0, 1.0, n)[1:-1]
    return c + rho * np.column_stack([np.cos(a), np.sin(a)])


def _tooth(spec, th: float, fil: dict, n_flank: int, n_fillet: int, filleted: bool) -> np.ndarray:
    """One tooth's outline in increasing angle, from root circle to root circle (filleted or sharp)."""
    from strainwave.geometry.involute import half_angle_rad
    r_f, r_a = spec.root_radius_mm, spec.tip_radius_mm
    pol = lambda r, a: np.column_stack([r * np.cos(a), r * np.sin(a)])  # noqa: E731
    if not filleted:
        radii = np.linspace(r_f, r_a, n_flank)
        up = radii[::-1]
        return np.vstack([pol(radii, th - half_angle_rad(spec, radii)), pol(up, th + half_angle_rad(spec, up))])
    radii = np.linspace(fil["r_t_mm"], r_a, n_flank)
    psi = half_angle_rad(spec, radii)
    out = []
    for side in (-1, 1):
        at = np.array([math.cos(th + side * fil["dphi_rad"]), math.sin(th + side * fil["dphi_rad"])])
        c, root = fil["centre_radius_mm"] * at, r_f * at
        foot = pol(radii[0], th + side * psi[0])[0]
        arc = _arc(c, fil["rho_mm"], root, foot, n_fillet)
        flank = pol(radii, th + side * psi)
        out.append(np.vstack([root[None], arc, flank]) if side < 0 else np.vstack([flank[::-1], arc[::-1], root[None]]))
    return np.vstack(out)


def sector_outline(spec, r_bore_mm: float, h_mm: float, h_fillet_mm: float) -> np.ndarray:
    """The closed sector: root circle and teeth in increasing angle (tooth 0 filleted), then the bore arc back."""
    pitch = 2 * math.pi / spec.teeth
    fil = fillet_geometry(spec)
    n_flank = max(6, int(math.ceil(2.5 * spec.module_mm / (TOOTH_H_RATIO * h_mm))))
    n_fillet = max(8, int(math.ceil(0.5 * math.pi * fil["rho_mm"] / h_fillet_mm)) + 2)
    a0, a1 = -(TEETH_EACH_SIDE + 0.5) * pitch, (TEETH_EACH_SIDE + 0.5) * pitch
    pts = [spec.root_radius_mm * np.array([[math.cos(a0), math.sin(a0)]])]
    for j in range(-TEETH_EACH_SIDE, TEETH_EACH_SIDE + 1):
        pts.append(_tooth(spec, j * pitch, fil, n_flank, n_fillet, filleted=j == 0))
    pts.append(spec.root_radius_mm * np.array([[math.cos(a1), math.sin(a1)]]))
    n_bore = max(8, int(math.ceil((a1 - a0) * r_bore_mm / h_mm)))
    a = np.linspace(a1, a0, n_bore)
    pts.append(r_bore_mm * np.column_stack([np.cos(a), np.sin(a)]))
    return np.vstack(pts)


def _model(spec, r_bore_mm: float, h_mm: float, lame, thickness_mm: float) -> tuple:
    """The factorised sector (a RimSolve: tooth 0 on +x) and the fillets' centres."""
    import scipy.sparse as sp
    fil = fillet_geometry(spec)
    hf = FILLET_H_RATIO * h_mm
    outline = sector_outline(spec, r_bore_mm, h_mm, hf)
    centres = [fil["centre_radius_mm"] * np.array([math.cos(s * fil["dphi_rad"]), math.sin(s * fil["dphi_rad"])])
               for s in (-1, 1)]

    ht, reach = TOOTH_H_RATIO * h_mm, spec.tip_radius_mm - spec.root_radius_mm + spec.module_mm

    def size(x, y):
        d = min(abs(math.hypot(x - c[0], y - c[1]) - fil["rho_mm"]) for c in centres)
        # the loaded tooth finer too: its flank band's resultant and lever set the root's moment
        dt = max(0.0, math.hypot(x - spec.root_radius_mm, y) - reach)
        return min(h_mm, hf + 0.4 * d, ht + 0.4 * dt)
    p, t = fe.gmsh_triangles([outline], size)
    mesh, basis, K = fe._assemble(p, t, lame, thickness_mm)
    locs = basis.doflocs
    r, ang = np.hypot(*locs), np.arctan2(locs[1], locs[0])
    a1 = (TEETH_EACH_SIDE + 0.5) * 2 * math.pi / spec.teeth
    on_bore = np.flatnonzero(r < r_bore_mm * (1 + 1e-9))
    cut = np.flatnonzero(np.abs(np.abs(ang) - a1) < 1e-9 * a1 + 1e-9)
    T = fe._rotation(locs, on_bore, K.shape[0]) if on_bore.size else sp.identity(K.shape[0], format="csr")
    fixed = np.unique(np.concatenate([2 * on_bore, 2 * cut, 2 * cut + 1]))
    free, solve = fe._factorise(K, T, fixed)
    model = fe.RimSolve(h_mm, mesh, basis, T, free, solve, thickness_mm, lame, 0.0, spec.teeth, False, {})
    return model, centres, fil


def _max_principal_nodal(model, u: np.ndarray) -> np.ndarray:
    """The max-principal stress (MPa) at the P2 dofs: each stress component L2-projected onto P2."""
    b, lame = model.basis, model.lame
    grad = np.stack([b.interpolate(u[c::2]).grad for c in (0, 1)])
    eps = 0.5 * (grad + grad.transpose(1, 0, 2, 3))
    tr = eps[0, 0] + eps[1, 1]
    sxx, syy = (lame.lam_MPa * tr + 2 * lame.mu_MPa * eps[k, k] for k in (0, 1))
    sxy = 2 * lame.mu_MPa * eps[0, 1]
    sx, sy, s_xy = (b.project(s) for s in (sxx, syy, sxy))
    return 0.5 * (sx + sy) + np.sqrt((0.5 * (sx - sy)) ** 2 + s_xy ** 2)


def root_stress_per_N(spec, r_bore_mm: float, h_mm: float, lame, thickness_mm: float, contact_radius_mm: float,
                      side: int, band_mm: float) -> dict:
    """The peak max-principal stress on tooth 0's fillets per newton of flank load (side ``side``, at
    ``contact_radius_mm``), MPa/N, and where it sits (its angle on the fillet arc from the tooth's centre line)."""
    model, centres, fil = _model(spec, r_bore_mm, h_mm, lame, thickness_mm)
    F, _ = fe.flank_loads(model, np.array([0]), np.array([contact_radius_mm]), band_mm, side)
    u = model.T @ fe.displacements(model, F)[:, 0]
    s1 = _max_principal_nodal(model, u)
    locs = model.basis.doflocs
    on = np.zeros(locs.shape[1], bool)
    for c in centres:
        on |= np.abs(np.hypot(locs[0] - c[0], locs[1] - c[1]) - fil["rho_mm"]) < 1e-6 * fil["rho_mm"] + 1e-9
    on &= np.hypot(*locs) < fil["r_t_mm"] + 1e-9
    if not on.any():
        raise RuntimeError("tooth root: no dofs on the fillets")
    k = np.flatnonzero(on)[int(np.argmax(s1[on]))]
    return {"stress_MPa_per_N": float(s1[k]), "at_xy_mm": locs[:, k].tolist(), "rho_mm": fil["rho_mm"],
            "elements": int(model.mesh.t.shape[1])}
