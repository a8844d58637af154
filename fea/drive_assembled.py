"""The drive assembled as it carries torque (issue 48, item 4): the teeth, the cup's wall and the wave generator
solved together, condensed onto the flank pairs in contact at the rated torque (decision 073-assembled48).

Members, each the project's own FE (nothing fitted):
- the teeth: the tooth-mesh study's pair compliance C (FS toothed rim on a radially held bore + CS teeth, along
  the lines of action) of the pairs loaded at rated on the headline WG angle (its rated contact set, linearised);
- the cup's wall: the quarter wall of ``fea/wg_band`` (bore to the tooth root, held round at the diaphragm's
  mid-plane, band = face width at the open end) on the rigid elliptical cam with the linear insertion's active set,
  loaded at the band's outer surface by each pair's unit normal force: its tangential part (moment = the pair's
  lever) and its radial part (sin alpha, inward), each spread by a hat one pitch either side;
- the rim's plane body, subtracted: C already holds the plane annulus under the teeth (bore held radially,
  loads balanced by a uniform bore shear); the same annulus by plane FE under the same hat loads is taken out,
  so the rim's body is counted once, in 3D;
- the wave generator: each lobe a radial spring K_G (the wg-bearing FE's), pushed by its teeth's radial loads
  along its axis; a pair loses sin(alpha) cos(phi) of its lobe's travel along its line of action.

Every pair loaded at rated is its own force (both lobes; an odd tooth count puts them half a pitch apart). The
quarter wall (even / odd split about phi = 0, as ``fea/cup_zone_load``) holds the period-pi part of their loads; the
part unlike on the two lobes (odd harmonics, nil for an even tooth count) stays with the plane rim in C.
The twist is the circular spline's against the wall's held end: K = L^T (C + G_3D - G_2D + G_WG)^-1 L.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.assembly import Lame

__all__ = ["RatedSet", "rated_set", "generalized", "mode_map", "wall_modes", "annulus_modes", "wg_flexibility",
           "stiffness", "lobe_of", "AssembledMesh", "assemble_once", "assemble", "zone_members", "zone_terms"]


@dataclass(frozen=True)
class RatedSet:
    """The flank pairs in contact at rated (both lobes), each with its own normal force."""

    phi_rad: np.ndarray          # FS tooth angle from the major axis
    side: np.ndarray             # flank side (+1 / -1)
    lever_mm: np.ndarray         # signed lever (base radius) of the normal force about the axis
    alpha_rad: np.ndarray        # pressure angle at the CS contact radius
    compliance_mm_per_N: np.ndarray   # the study's C on these pairs, (n, n)
    forces_N: np.ndarray         # the study's flank loads at rated


def rated_set(meta: dict) -> RatedSet:
    """The tooth-mesh study's rated contact set from its record ``meta`` (pairs, forces at rated and
    ``rated_compliance``: the set's indices and C)."""
    rec = meta["rated_compliance"]
    on = np.asarray(rec["index"], int)
    C = np.asarray(rec["compliance_mm_per_N"], float)
    pairs = {k: np.asarray(v)[on] for k, v in meta["pairs"].items()}
    lever = pairs["lever_mm"].astype(float)
    alpha = np.arccos(np.clip(np.abs(lever) / pairs["cs_radius_mm"].astype(float), -1.0, 1.0))
    F = np.asarray(meta["forces_at_rated_N"], float)[on]
    return RatedSet(pairs["phi_rad"].astype(float), pairs["side"], lever, alpha, 0.5 * (C + C.T), F)


def generalized(C: np.ndarray, lever_mm: np.ndarray) -> float:
    """K = L^T C^-1 L (N mm/rad): the pairs' twist stiffness when each pair closes by its lever times the twist."""
    L = np.asarray(lever_mm, float)
    return float(L @ np.linalg.solve(C, L))


def stiffness(s: RatedSet, G3: np.ndarray, G2: np.ndarray, Gwg: np.ndarray) -> float:
    """The assembled drive's stiffness at rated (N mm/rad)."""
    return generalized(s.compliance_mm_per_N + G3 - G2 + Gwg, s.lever_mm)


def lobe_of(phi_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the lobe, 0 or 1, each angle belongs to; the angle from that lobe's axis)."""
    phi = np.asarray(phi_rad, float)
    folded = np.mod(phi + 0.5 * math.pi, math.pi) - 0.5 * math.pi
    return np.round((phi - folded) / math.pi).astype(int) % 2, folded


def wg_flexibility(s: RatedSet, K_G_N_per_mm: float) -> np.ndarray:
    """The two lobes as radial springs K_G: a lobe travels its teeth's inward radial resultant along its axis over
    K_G; pair j loses sin(alpha_j) cos(phi_j) of its own lobe's travel along its line of action."""
    lobe, folded = lobe_of(s.phi_rad)
    a = np.sin(s.alpha_rad) * np.cos(folded)
    return np.where(lobe[:, None] == lobe[None, :], np.outer(a, a), 0.0) / K_G_N_per_mm


def mode_map(phi_rad: np.ndarray, tangential_N: np.ndarray, harmonics: int) -> np.ndarray:
    """P (modes, pairs): the Fourier coefficients, period pi (1, cos 2k phi, sin 2k phi, k = 1..K), of the
    tangential force per radian a pair's unit normal force puts on the wall, with Lanczos' sigma factors (no Gibbs
    ringing); the modes' order is [1, cos 2phi, .., cos 2K phi, sin 2phi, .., sin 2K phi]. The odd harmonics (a
    load unlike on the two lobes) are left to the plane rim in C: the quarter wall holds period pi only."""
    k = np.arange(1, harmonics + 1)
    sigma = np.sinc(k / (harmonics + 1.0))
    t = np.asarray(tangential_N, float)
    a = 2.0 * np.asarray(phi_rad, float)[None, :] * k[:, None]                       # 2 k phi
    c = sigma[:, None] * t[None, :] / math.pi
    return np.vstack([t[None, :] / (2.0 * math.pi), c * np.cos(a), c * np.sin(a)])


def _mode(phi: np.ndarray, a: int, harmonics: int) -> np.ndarray:
    if a == 0:
        return np.ones_like(phi)
    k = (a - 1) % harmonics + 1
    return np.cos(2 * k * phi) if a <= harmonics else np.sin(2 * k * phi)


def _held_many(tube, system, B: np.ndarray, active: np.ndarray) -> np.ndarray:
    """``wg_band.held_solve`` of every column of B at once (held at 0): one dense factor of S's free block per
    pass instead of one per load, the same refinement step."""
    fs, on = system.faces, system.on_face
    act = np.asarray(active, bool)[on]
    f = tube.rot_t @ B
    x = fs.held(f, fs.face_loads(f), act, 0.0)
    res = f - fs.K @ x
    res[fs.base] = 0.0
    res[fs.face_z[act]] = 0.0
    x += fs.held(res, fs.face_loads(res), act)
    return tube.rot @ x


def wall_modes(tube_geo, n_theta: int, lame: Lame, w0_mm: float, harmonics: int, contact: bool = True) -> dict:
    """The quarter wall on the cam (linear insertion's active set) under a tangential shear on the band's outer
    surface of each mode (force per radian of circumference = the mode): ``g`` the modes' work matrix over the whole
    circle (the cos modes are even about phi = 0: antisymmetric plane conditions; the sin modes odd: symmetric),
    and the cam's held fraction of the band's bore (``contact`` False: the whole band bore held radially, the
    prescribed-shape limit)."""
    from strainwave.fea import wg_band as wb
    tube = wb.tube_mesh(tube_geo, n_theta)
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    systems = {sym: wb.bore_system(tube, K0, symmetric=sym) for sym in (True, False)}
    try:
        active = wb.insert(tube, lame, w0_mm, contact=contact, nonlinear=False, K0=K0, system=systems[True]).active
        cb, x, r, dA = wb.band_outer_quadrature(tube, 8)
        phi = np.arctan2(x[1], x[0])
        e_t = np.stack([-x[1], x[0]]) / r
        N = np.stack([cb.basis[a][0].value for a in range(len(cb.basis))])
        dofs = cb.element_dofs.ravel()
        n = 2 * harmonics + 1
        g = np.zeros((n, n))
        for sym, idx in ((False, range(0, harmonics + 1)), (True, range(harmonics + 1, n))):
            if not len(idx):
                continue
            B = np.zeros((tube.dofs, len(idx)))
            for col, a in enumerate(idx):
                # force per radian q -> per unit area q / (r_o b) on the band's outer surface
                q = _mode(phi, a, harmonics) * dA / (tube_geo.r_o_mm * tube_geo.band_mm)
                for k in (0, 1):
                    B[:, col] += np.bincount(3 * dofs + k, (N * q * e_t[k]).sum(axis=2).ravel(), minlength=tube.dofs)
            U = _held_many(tube, systems[sym], B, active)
            g[np.ix_(list(idx), list(idx))] = 4.0 * B.T @ U       # the quarter holds a quarter of the work
        return {"g": 0.5 * (g + g.T), "held_fraction": float(active.sum()) / active.size, "dofs": tube.dofs}
    finally:
        for sys_ in systems.values():
            sys_.close()


def annulus_modes(r_i_mm: float, r_o_mm: float, thickness_mm: float, h_mm: float, lame: Lame,
                  harmonics: int) -> np.ndarray:
    """The plane annulus under the teeth as the study's rim holds it (plane strain, bore held radially, free
    tangentially, each load balanced by a uniform bore shear): the modes' work matrix (``wall_modes``' modes on
    its outer circle)."""
    from skfem import ElementVector, FacetBasis, LinearForm
    from strainwave.fea import tooth_mesh_fe as fe
    p, t = fe.gmsh_triangles([fe._circle(r_o_mm, h_mm), fe._circle(r_i_mm, h_mm)], lambda x, y: h_mm,
                             what="gmsh (drive-assembled annulus)")
    mesh, basis, K = fe._assemble(p, t, lame, thickness_mm)
    locs = basis.doflocs
    on_bore = np.flatnonzero(np.hypot(*locs) < r_i_mm * (1 + 1e-6))
    T = fe._rotation(locs, on_bore, K.shape[0])
    pin = on_bore[np.argmin(np.abs(np.arctan2(locs[1, on_bore], locs[0, on_bore]) - 0.5 * math.pi))]
    free, solve = fe._factorise(K, T, np.concatenate([2 * on_bore, [2 * pin + 1]]))
    model = fe.RimSolve(h_mm, mesh, basis, T, free, solve, thickness_mm, lame, 0.0, 0, False, {})
    bf = mesh.boundary_facets()
    r_mid = np.hypot(*mesh.p[:, mesh.facets[:, bf]].mean(axis=1))
    fb = FacetBasis(mesh, ElementVector(basis.elem), facets=bf[r_mid > r_o_mm * (1 - 1e-3)], intorder=8)
    shear = fe.bore_shear(model, r_i_mm)
    x, y = locs
    cols = []
    for a in range(2 * harmonics + 1):
        @LinearForm
        def mode(v, w, a=a):
            r = np.sqrt(w.x[0] ** 2 + w.x[1] ** 2)
            q = _mode(np.arctan2(w.x[1], w.x[0]), a, harmonics) / (r_o_mm * thickness_mm)
            return q * (-w.x[1] * v[0] + w.x[0] * v[1]) / r
        f = mode.assemble(fb) * thickness_mm
        cols.append(T.T @ f - shear * float((x * f[1::2] - y * f[0::2]).sum()))
    return fe.compliance(model, np.column_stack(cols))


HARMONICS = 6                  # Fourier modes 2k phi, k <= 6, of the teeth's load on the wall: the coarsest wall (6
#                                elements a quarter) holds two elements a wavelength of the highest
WALL_ELEMENTS = (11, 8, 6)     # elements round the quarter wall, finest first (x1.375, x1.33)


def _subset(g: np.ndarray, harmonics: int, fewer: int) -> np.ndarray:
    """The modes' matrix of the first ``fewer`` harmonics (the modes are nested)."""
    idx = list(range(fewer + 1)) + list(range(harmonics + 1, harmonics + 1 + fewer))
    return g[np.ix_(idx, idx)]


@dataclass(frozen=True)
class AssembledMesh:
    """One wall mesh of the assembly: its stiffness, and the members' work-conjugate flexibilities at the study's
    rated loads (rad/(N mm)), each loaded alone: the chain of the same members."""

    n_theta: int
    K_assembled_Nmm_per_rad: float
    K_assembled_half_harmonics: float   # the same with K/2 harmonics (the truncation's estimate)
    K_chain_half_harmonics: float
    lambda_teeth: float           # 1 / L^T C^-1 L: the study's teeth and plane rim, linearised at rated
    lambda_wall_uniform: float    # the wall under a uniform band shear
    lambda_zone_net: float        # the wall under the rated loads minus the uniform, minus the plane annulus's share
    lambda_zone_gross: float      # the same without the annulus taken out (decision 067's cup-zone term)
    lambda_wg_lobes: float        # the lobe springs at the rated loads
    held_fraction: float
    dofs: int

    @property
    def K_chain_Nmm_per_rad(self) -> float:
        return 1.0 / (self.lambda_teeth + self.lambda_wall_uniform + self.lambda_zone_net + self.lambda_wg_lobes)


def assemble_once(s: RatedSet, tube_geo, n_theta: int, lame: Lame, w0_mm: float, K_G_N_per_mm: float,
                  face_width_mm: float, harmonics: int = HARMONICS, contact: bool = True,
                  g2: np.ndarray | None = None) -> AssembledMesh:
    """The assembly and its members on one wall mesh (``g2``: the annulus's modes, by default on a plane mesh of
    half the wall, which resolves every mode)."""
    wall = wall_modes(tube_geo, n_theta, lame, w0_mm, harmonics, contact)
    if g2 is None:
        g2 = annulus_modes(tube_geo.r_i_mm, tube_geo.r_o_mm, face_width_mm, 0.5 * tube_geo.wall_mm, lame, harmonics)
    t = -np.asarray(s.lever_mm) / tube_geo.r_o_mm
    Gwg = wg_flexibility(s, K_G_N_per_mm)

    # the members are loaded as the teeth alone share the load (the tangent of C on the rated set): the chain's
    # own distribution, so the assembly's coupled solve can only be stiffer (complementary energy)
    L = np.asarray(s.lever_mm, float)
    f = np.linalg.solve(s.compliance_mm_per_N, L)
    T = float(L @ f)
    work = lambda G: float(f @ G @ f) / T ** 2       # noqa: E731
    lam_teeth = 1.0 / generalized(s.compliance_mm_per_N, s.lever_mm)

    def K_of(k: int) -> tuple[float, float, np.ndarray, np.ndarray]:
        P = mode_map(s.phi_rad, t, k)
        G3, G2 = P.T @ _subset(wall["g"], harmonics, k) @ P, P.T @ _subset(g2, harmonics, k) @ P
        return stiffness(s, G3, G2, Gwg), 1.0 / (lam_teeth + work(G3 - G2) + work(Gwg)), G3, G2

    K = K_of(harmonics)[0]
    K_half, chain_half = K_of(harmonics // 2)[:2]
    uniform, gross, net = zone_members(wall["g"], g2, s.phi_rad, s.lever_mm, f, tube_geo.r_o_mm)
    return AssembledMesh(n_theta, K, K_half, chain_half, lam_teeth, uniform, net, gross, work(Gwg),
                         wall["held_fraction"], wall["dofs"])


def zone_members(g3: np.ndarray, g2: np.ndarray, phi_rad, lever_mm, forces_N, r_o_mm: float) -> tuple[float, ...]:
    """(uniform, gross, net) work-conjugate flexibilities (rad/(N mm)) of the wall under flank pair forces
    ``forces_N``: the wall under a uniform band shear; its extra under the pairs' load (decision 067's cup-zone term);
    that extra net of the plane annulus under the same load, which a mesh model's rim already holds (decisions
    073-assembled48 and 075-catzone48: the validate chain and the catalogue chain both add only ``net``)."""
    harmonics = (len(g3) - 1) // 2
    L, f = np.asarray(lever_mm, float), np.asarray(forces_N, float)
    P = mode_map(phi_rad, -L / r_o_mm, harmonics)
    load = P @ f                                    # the load's modes (force per radian on the wall's outer circle)
    T = float(L @ f)
    uniform = float(g3[0, 0]) / (2.0 * math.pi * r_o_mm) ** 2
    gross = float(load @ g3 @ load) / T ** 2 - uniform
    return uniform, gross, gross - float(load @ g2 @ load) / T ** 2


def zone_terms(tube_geo, n_theta: int, lame: Lame, w0_mm: float, phi_rad, lever_mm, forces_N, face_width_mm: float,
               g2: np.ndarray | None = None, harmonics: int = HARMONICS, contact: bool = True) -> dict:
    """The wall's members (``zone_members``) under given flank loads on one wall mesh, with the cam's held fraction:
    the catalogue chain's cup-zone term from its reduced mesh model's loads (decision 075-catzone48)."""
    wall = wall_modes(tube_geo, n_theta, lame, w0_mm, harmonics, contact)
    if g2 is None:
        g2 = annulus_modes(tube_geo.r_i_mm, tube_geo.r_o_mm, face_width_mm, 0.5 * tube_geo.wall_mm, lame, harmonics)
    uniform, gross, net = zone_members(wall["g"], g2, phi_rad, lever_mm, forces_N, tube_geo.r_o_mm)
    return {"uniform": uniform, "gross": gross, "net": net, "held_fraction": wall["held_fraction"]}


def assemble(meta: dict, params, K_G_N_per_mm: float, elements: tuple[int, int, int] = WALL_ELEMENTS) -> dict:
    """The assembly of a gear on three wall meshes (finest first): ``K`` (a Quantity with its GCI), the finest
    mesh's members (``finest``), every mesh's record, and the CPU seconds."""
    import time
    from strainwave.fea import wg_band as wb
    from strainwave.fea.refinement import converged_quantity
    from strainwave.geometry.mesh_geometry import mesh_geometry
    t0 = time.process_time()
    s = rated_set(meta)
    geo = mesh_geometry(params)
    m = params.material
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)
    tube = wb.tube_geometry(params)
    g2 = annulus_modes(tube.r_i_mm, tube.r_o_mm, geo.face_width_mm, 0.5 * tube.wall_mm, lame, HARMONICS)
    runs = [assemble_once(s, tube, n, lame, params.gear.radial_deformation_mm, K_G_N_per_mm, geo.face_width_mm,
                          g2=g2) for n in elements]
    h = [0.5 * math.pi * tube.r_m_mm / n for n in elements]
    K = converged_quantity("assembled_drive_stiffness_Nmm_per_rad", "N*mm/rad", h,
                           [r.K_assembled_Nmm_per_rad for r in runs])
    # the wall is in both the assembly and its chain: the comparison's mesh error is the ratio's
    ratio = converged_quantity("assembled_over_chain", "1", h, [r.K_assembled_Nmm_per_rad / r.K_chain_Nmm_per_rad
                                                               for r in runs])
    zone = converged_quantity("wall_zone_net_flexibility_rad_per_Nmm", "rad/(N*mm)", h,
                              [r.lambda_zone_net for r in runs])
    return {"K": K, "ratio": ratio, "zone": zone, "finest": runs[0], "runs": runs, "rated_set": s,
            "cpu_s": time.process_time() - t0}
