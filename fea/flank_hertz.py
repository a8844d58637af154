"""Plane-strain contact of the real flank pair (issue 48, item 3): the cup's tooth and the circular spline's tooth,
two elastic bodies, pressed together along their common normal at the tooth-mesh study's major-axis contact point.

Geometry: each tooth is the design's involute (``geometry/involute.half_angle_rad``, the ``ToothSpec`` of
``geometry/mesh_geometry``) on a piece of its rim one pitch wide: the cup's tooth held at its bore, the circular
spline's tooth held two modules outside its root circle (both held far from the contact: >= 25 half-widths at the
validated load). The contact flanks are the cup tooth's +theta flank and the facing circular-spline tooth's
-theta flank, at the study's major-axis pair (cup radius r_f at the middle of the radial overlap, spline radius
r_f + w0). Each body is carried into a common frame: contact point at the origin, common tangent x (outward, both
radii increase with x), the cup below (y < 0), the spline above.

Contact: the pressure is piecewise linear on a candidate zone of the flanks whose vertices stand at the same x on
both bodies (equal spacing, a vertex at x = 0); each hat function's consistent P2 nodal load gives one column of
each body's flexibility A = F^T K^-1 F (symmetric). The gap of the real involutes (exact points, not the mesh's)
at each vertex closes by the rigid approach delta; unknowns p >= 0 and delta with sum(w p) = P (the line load):
an active-set solve of the LCP (Signorini, weighted gap), exact for its active set. Meshes: gmsh with the zone's
segments fixed (no interior nodes) and a size field graded from the zone's spacing.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.tooth_mesh_fe import gmsh_triangles

__all__ = ["FlankPair", "ContactSolve", "BodyFlexibility", "flank_pair", "working_flank_mm", "surface_y", "initial_gap_mm",
           "body_flexibility", "hat_weights", "contact_lcp", "solve_contact"]

HELD_OUTSIDE_CS_ROOT_OVER_M = 2.0     # the spline's body held this many modules outside its root circle


@dataclass(frozen=True)
class FlankPair:
    """The contact configuration (lengths mm)."""

    fs: object                 # ToothSpec of the cup's teeth
    cs: object                 # ToothSpec of the circular spline's teeth (internal)
    r_fs_mm: float             # contact radius on the cup's tooth (its own centre)
    r_cs_mm: float             # contact radius on the spline's tooth
    rho_fs_mm: float           # the cup flank's radius of curvature there (convex, r_b tan alpha)
    rho_cs_mm: float           # the spline flank's (concave; its magnitude)
    r_bore_mm: float
    r_held_cs_mm: float
    module_mm: float


def flank_pair(params) -> FlankPair:
    """The study's major-axis pair (analytic/mesh_engagement: contact at the middle of the radial overlap)."""
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    depth = geo.fs.tip_radius_mm + geo.w0_mm - geo.cs_tip_mm
    r_f = geo.fs.tip_radius_mm - 0.5 * depth
    r_c = r_f + geo.w0_mm
    rho = lambda spec, r: math.sqrt(r * r - spec.base_radius_mm ** 2)  # noqa: E731
    m = geo.fs.module_mm
    return FlankPair(geo.fs, geo.cs_tooth, r_f, r_c, rho(geo.fs, r_f), rho(geo.cs_tooth, r_c), geo.r_bore_mm,
                     geo.cs_tooth.root_radius_mm + HELD_OUTSIDE_CS_ROOT_OVER_M * m, m)


def working_flank_mm(pair: FlankPair) -> tuple[float, float]:
    """(length of the cup flank inside the spline's tip circle at the major axis, along the involute; the distance
    from the contact point to the nearer end of it). Involute arc length between rolls: (rho_2^2 - rho_1^2)/(2 r_b)."""
    spec = pair.fs
    rb = spec.base_radius_mm
    r_low = 2.0 * pair.r_fs_mm - spec.tip_radius_mm      # the contact is the middle of the radial overlap
    arc = lambda r0, r1: ((r1 * r1 - rb * rb) - (r0 * r0 - rb * rb)) / (2.0 * rb)  # noqa: E731
    return arc(r_low, spec.tip_radius_mm), min(arc(r_low, pair.r_fs_mm), arc(pair.r_fs_mm, spec.tip_radius_mm))


def _flank_xy(spec, r: np.ndarray, side: int) -> np.ndarray:
    """Points of tooth 0's flank ``side`` (+1: +theta) at radii r, own frame (N, 2)."""
    from strainwave.geometry.involute import half_angle_rad
    a = side * half_angle_rad(spec, r)
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def _frame(spec, r_c: float, side: int, body: int) -> tuple[np.ndarray, np.ndarray]:
    """(contact point, rotation rows (t, y)) carrying the own frame into the common one: the body's outward normal
    is +y for the cup (body 0) and -y for the spline (body 1); x along the flank with the radius growing."""
    d = 1e-4
    p0, p1, pm = _flank_xy(spec, np.array([r_c, r_c + d, r_c - d]), side)
    tang = (p1 - pm) / np.linalg.norm(p1 - pm)                      # radius increasing
    normal = np.array([-tang[1], tang[0]])
    away = np.array([-p0[1], p0[0]]) * side      # from the tooth's centre line (half_angle_rad: the tooth, either kind)
    outward = normal if normal @ away > 0 else -normal
    y = outward if body == 0 else -outward
    x = np.array([y[1], -y[0]])                                      # right-handed (x, y)
    if x @ tang < 0:                                                 # a mirror would be needed: a geometry error
        raise ValueError("flank frames disagree in orientation")
    return p0, np.vstack([x, y])


def _radii_at(spec, r_c: float, side: int, body: int, xs: np.ndarray) -> np.ndarray:
    """Radii of the flank points whose common-frame x is ``xs`` (dense interpolation, two Newton polishes)."""
    p0, rot = _frame(spec, r_c, side, body)
    span = 3.0 * float(np.max(np.abs(xs))) + 1e-3
    rr = np.linspace(r_c - span, r_c + span, 4001)
    x = (_flank_xy(spec, rr, side) - p0) @ rot[0]
    r = np.interp(xs, x, rr)
    for _ in range(2):
        d = 1e-6
        f = (_flank_xy(spec, r, side) - p0) @ rot[0] - xs
        fp = ((_flank_xy(spec, r + d, side) - _flank_xy(spec, r - d, side)) @ rot[0]) / (2 * d)
        r = r - f / fp
    return r


def surface_y(pair: FlankPair, body: int, xs: np.ndarray) -> np.ndarray:
    """The exact flank's height y(x) in the common frame (0 at the contact point)."""
    spec, r_c, side = (pair.fs, pair.r_fs_mm, 1) if body == 0 else (pair.cs, pair.r_cs_mm, -1)
    p0, rot = _frame(spec, r_c, side, body)
    return (_flank_xy(spec, _radii_at(spec, r_c, side, body, xs), side) - p0) @ rot[1]


def initial_gap_mm(pair: FlankPair, xs: np.ndarray) -> np.ndarray:
    """The unloaded gap between the two real involutes along y at common x."""
    return surface_y(pair, 1, xs) - surface_y(pair, 0, xs)


def _arc(r: float, a0: float, a1: float, h: float) -> np.ndarray:
    n = max(2, int(math.ceil(abs(a1 - a0) * r / h)) + 1)
    a = np.linspace(a0, a1, n)
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def _flank_points(spec, r_c: float, side: int, body: int, zone_x: np.ndarray, r_lo: float, r_hi: float,
                  h_far: float) -> tuple[np.ndarray, np.ndarray]:
    """(flank points from r_lo to r_hi, own frame; a mask of the zone's points): the zone at its common x, the
    rest of the flank at about ``h_far``."""
    rz = _radii_at(spec, r_c, side, body, zone_x)
    n = max(3, int(math.ceil((r_hi - r_lo) / h_far)) + 1)
    rr = np.linspace(r_lo, r_hi, n)
    gap = 0.5 * abs(rz[1] - rz[0])
    rr = rr[(rr < rz.min() - gap) | (rr > rz.max() + gap)]
    r_all = np.concatenate([rr, rz])
    zone = np.concatenate([np.zeros(rr.size, bool), np.ones(rz.size, bool)])
    order = np.argsort(r_all)
    return _flank_xy(spec, r_all[order], side), zone[order]


def _body_loop(pair: FlankPair, body: int, zone_x: np.ndarray, h_far: float):
    """(closed outline in the common frame, mask of the zone's points, the held radius, the gear's centre in the
    common frame): body 0 the cup's tooth on its rim down to the bore, body 1 the spline's tooth on its ring."""
    if body == 0:
        spec, r_c, side = pair.fs, pair.r_fs_mm, 1
        lo, hi, r_held = spec.root_radius_mm, spec.tip_radius_mm, pair.r_bore_mm
    else:
        spec, r_c, side = pair.cs, pair.r_cs_mm, -1
        lo, hi, r_held = spec.tip_radius_mm, spec.root_radius_mm, pair.r_held_cs_mm
    from strainwave.geometry.involute import half_angle_rad
    half = math.pi / spec.teeth
    flank, zone = _flank_points(spec, r_c, side, body, zone_x, lo, hi, h_far)
    other = _flank_xy(spec, np.linspace(lo, hi, max(3, int(math.ceil((hi - lo) / h_far)) + 1)), -side)
    root, tip = (lo, hi) if body == 0 else (hi, lo)
    psi_root, psi_tip = float(half_angle_rad(spec, root)), float(half_angle_rad(spec, tip))
    # walk: other flank root -> tip, tip arc, contact flank tip -> root, root arc, side, held arc, side, root arc
    o = other if root == lo else other[::-1]                  # sampled from lo to hi
    f = flank[::-1] if root == lo else flank                  # contact flank tip -> root
    zf = zone[::-1] if root == lo else zone
    pieces = [o, _arc(tip, -side * psi_tip, side * psi_tip, h_far)[1:-1], f,
              _arc(root, side * psi_root, side * half, h_far)[1:], _arc(r_held, side * half, -side * half, h_far),
              _arc(root, -side * half, -side * psi_root, h_far)[:-1]]
    loop = np.vstack(pieces)
    mask = np.zeros(len(loop), bool)
    start = len(pieces[0]) + len(pieces[1])
    mask[start:start + len(f)] = zf
    p0, rot = _frame(spec, r_c, side, body)
    return (loop - p0) @ rot.T, mask, r_held, (-p0) @ rot.T


@dataclass(frozen=True)
class BodyFlexibility:
    """One body's answer to the zone's hat pressures: A[k, j] = the work of hat k's load on hat j's displacement
    (mm^2/MPa per mm of face: plane strain, unit thickness), with its mesh's size."""

    A: np.ndarray
    dofs: int
    triangles: int


def body_flexibility(pair: FlankPair, body: int, zone_x: np.ndarray, h_far: float, grade: float, lame):
    """Mesh, assemble, hold and load one body by each hat of the zone (consistent P2 loads along -y for the cup,
    +y for the spline: each pressure pushes into its body)."""
    from scipy.spatial import cKDTree
    from skfem import ElementTriP2, MeshTri

    from strainwave.fea.assembly import elasticity_stiffness, scalar_basis
    from strainwave.fea.solver import _direct
    loop, mask, r_held, centre = _body_loop(pair, body, zone_x, h_far)
    h_c, reach = float(zone_x[1] - zone_x[0]), float(np.abs(zone_x).max())
    p, t = gmsh_triangles([loop], lambda x, y: min(h_far, h_c + grade * max(0.0, math.hypot(x, y) - reach)), mask,
                     what="gmsh (flank contact)")
    mesh = MeshTri(p, t)
    basis = scalar_basis(mesh, ElementTriP2(), intorder=4)
    K = elasticity_stiffness(basis, lame)
    locs = basis.doflocs
    r = np.hypot(locs[0] - centre[0], locs[1] - centre[1])
    sag = h_far ** 2 / (4.0 * r_held) + 1e-9           # the held arc is a polygon: its chords' sagitta, twice
    held = np.flatnonzero(r < r_held + sag if body == 0 else r > r_held - sag)
    free = np.setdiff1d(np.arange(K.shape[0]), np.concatenate([2 * held, 2 * held + 1]))
    zone = loop[mask]
    tree = cKDTree(locs.T)
    dist_v, vert = tree.query(zone)
    dist_m, mid = tree.query(0.5 * (zone[1:] + zone[:-1]))
    if max(dist_v.max(), dist_m.max()) > 1e-9:
        raise ValueError(f"flank contact mesh: zone node not found ({max(dist_v.max(), dist_m.max()):.2g} mm)")
    seg = np.hypot(*(zone[1:] - zone[:-1]).T)
    F = np.zeros((K.shape[0], len(zone)))
    sign = -1.0 if body == 0 else 1.0
    for k in range(len(zone)):          # hat k: L/6 at its vertex from each side, L/3 at each side's midside
        for e in (k - 1, k):
            if 0 <= e < len(seg):
                F[2 * vert[k] + 1, k] += sign * seg[e] / 6.0
                F[2 * mid[e] + 1, k] += sign * seg[e] / 3.0
    Ff = F[free]
    # PARDISO solves the ~50 right-hand sides as one block (5x SuperLU's column-by-column solve here)
    U, _ = _direct(K[free][:, free].tocsr(), Ff, "flank-hertz")
    A = Ff.T @ U.reshape(Ff.shape)
    return BodyFlexibility(0.5 * (A + A.T), int(K.shape[0]), int(t.shape[1]))


def hat_weights(zone_x: np.ndarray) -> np.ndarray:
    """The integral of each hat over the zone (mm)."""
    seg = np.diff(zone_x)
    return 0.5 * (np.concatenate([[0.0], seg]) + np.concatenate([seg, [0.0]]))


def contact_lcp(A: np.ndarray, w: np.ndarray, gap: np.ndarray, load: float, max_iter: int = 200):
    """Hat pressures p >= 0 and the approach delta with sum(w p) = load and the weighted gap
    (A p)_k / w_k + gap_k - delta >= 0, complementary to p (active set; raises if it cycles)."""
    n = len(w)
    active = np.zeros(n, bool)
    active[np.argsort(gap)[:3]] = True
    for _ in range(max_iter):
        S = np.flatnonzero(active)
        M = np.zeros((S.size + 1, S.size + 1))
        M[:-1, :-1] = A[np.ix_(S, S)]
        M[:-1, -1] = -w[S]
        M[-1, :-1] = w[S]
        rhs = np.concatenate([-w[S] * gap[S], [load]])
        sol = np.linalg.solve(M, rhs)
        p = np.zeros(n)
        p[S], delta = sol[:-1], sol[-1]
        if p[S].min() < -1e-12 * abs(p).max():
            active[S[np.argmin(p[S])]] = False
            continue
        g = A @ p / w + gap - delta
        g[active] = 0.0
        if g.min() < -1e-12 * max(abs(delta), 1e-30):
            active[int(np.argmin(g))] = True
            continue
        return np.maximum(p, 0.0), float(delta)
    raise RuntimeError("flank contact: the active set did not settle")


@dataclass(frozen=True)
class ContactSolve:
    """One mesh's answer at line load ``load_N_per_mm``."""

    h_contact_mm: float        # the zone's node spacing
    load_N_per_mm: float
    x_mm: np.ndarray           # the zone's vertices (common frame)
    pressure_MPa: np.ndarray   # the hat pressures
    approach_mm: float         # the rigid approach delta
    dofs: int
    triangles: int

    @property
    def peak_pressure_MPa(self) -> float:
        """The peak of the parabola through the largest hat pressure and its neighbours (the elliptic crown)."""
        p, k = self.pressure_MPa, int(np.argmax(self.pressure_MPa))
        if 0 < k < len(p) - 1:
            a, b, c = p[k - 1], p[k], p[k + 1]
            den = a - 2 * b + c
            if den < 0:
                return float(b - 0.125 * (c - a) ** 2 / den)
        return float(p[k])

    def _moments(self) -> tuple[float, float, float]:
        """Exact integrals of the piecewise-linear pressure times 1, x, x^2."""
        x, p = self.x_mm, self.pressure_MPa
        x0, x1, p0, p1 = x[:-1], x[1:], p[:-1], p[1:]
        L = x1 - x0
        m0 = np.sum(0.5 * L * (p0 + p1))
        m1 = np.sum(L * (p0 * (2 * x0 + x1) + p1 * (x0 + 2 * x1)) / 6.0)
        m2 = np.sum(L * (p0 * (3 * x0 ** 2 + 2 * x0 * x1 + x1 ** 2) + p1 * (x0 ** 2 + 2 * x0 * x1 + 3 * x1 ** 2)) / 12.0)
        return float(m0), float(m1), float(m2)

    @property
    def half_width_mm(self) -> float:
        """Twice the pressure's standard deviation about its centre: Hertz's ellipse gives exactly b."""
        m0, m1, m2 = self._moments()
        return 2.0 * math.sqrt(max(m2 / m0 - (m1 / m0) ** 2, 0.0))

    @property
    def centre_mm(self) -> float:
        """The pressure's centroid: the teeth's tilt under load adds a linear term to the gap, which moves the contact
        (by theta R*) and leaves p0 and b as they are."""
        m0, m1, _ = self._moments()
        return m1 / m0

    @property
    def edge_half_width_mm(self) -> float:
        """Half the span of the loaded hats plus one spacing (the discrete edge, for the note)."""
        on = np.flatnonzero(self.pressure_MPa > 0)
        return 0.5 * float(self.x_mm[on[-1]] - self.x_mm[on[0]]) + 0.5 * self.h_contact_mm

    @property
    def zone_edge_loaded(self) -> bool:
        return bool(self.pressure_MPa[0] > 0 or self.pressure_MPa[-1] > 0)


def solve_contact(pair: FlankPair, lame, load_N_per_mm: float, zone_half_mm: float, h_contact_mm: float,
                  h_far_mm: float, grade: float = 0.25) -> ContactSolve:
    """The flank pair pressed by ``load_N_per_mm`` (per mm of face, plane strain) on one mesh."""
    k = int(math.ceil(zone_half_mm / h_contact_mm))
    x = h_contact_mm * np.arange(-k, k + 1)
    bodies = [body_flexibility(pair, b, x, h_far_mm, grade, lame) for b in (0, 1)]
    w = hat_weights(x)
    p, delta = contact_lcp(bodies[0].A + bodies[1].A, w, initial_gap_mm(pair, x), load_N_per_mm)
    return ContactSolve(h_contact_mm, load_N_per_mm, x, p, delta, sum(b.dofs for b in bodies),
                        sum(b.triangles for b in bodies))
