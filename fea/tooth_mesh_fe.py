"""Plane-stress FE of a toothed rim: the flank compliance matrix along the lines of action.

The flexspline's toothed rim (bore d1/2 - delta to the tooth tips, the cup's involute teeth as
geometry/involute.py draws them, no root fillet: the compliance converges at a sharp corner, the stress
there does not) is meshed whole with P2 triangles, thickness = the engaged face width. The wave generator
holds the bore radially (u_r = 0: a rigid WG; its own compliance is a separate member of the chain); the
bore's tangential motion is free except one pin against the rigid rotation. Each unit flank load is balanced
in torque by a uniform tangential shear on the bore (the cup wall that carries the torque to the diaphragm),
so every load vector is self-equilibrated in moment and the matrix C_ij = f_i . K^-1 f_j is the flank
displacement along the normal relative to the bore's mean rotation, whatever the pin.

A unit load is a parabolic pressure over a band of the flank (half-width ``band_mm`` in radius around the
contact radius): a point load in 2D has a log-infinite displacement, a smooth band converges.

The circular spline's teeth sit on a thick rim (outer diameter ~1.25 pitch diameter): a sector of its
internal teeth, held at the outer radius, gives each CS tooth's own flank compliance (``cs_compliance``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from strainwave.fea.assembly import Lame, elasticity_stiffness, scalar_basis

__all__ = ["RimSolve", "gmsh_triangles", "rim_model", "flank_loads", "compliance", "sector_model"]


@dataclass
class RimSolve:
    """One mesh of a toothed section, assembled, constrained and factorised."""

    h_mm: float
    mesh: object              # skfem MeshTri1 (P1 geometry; P2 element)
    basis: object             # scalar P2 CellBasis
    T: sp.csr_matrix          # u = T u~ (bore dofs turned to (r, theta))
    free: np.ndarray          # free dofs of u~
    solve: object             # rhs (free) -> u~ (free)
    thickness_mm: float
    lame: Lame
    centre_angle_rad: float   # tooth 0's centre
    teeth: int
    internal: bool
    timings_s: dict


def _outline(spec, n_flank: int) -> np.ndarray:
    from strainwave.geometry.involute import tooth_polyline_mm
    return tooth_polyline_mm(spec, n_flank=n_flank, n_arc=4)


def _circle(r: float, h: float, a0: float = 0.0, a1: float = 2 * math.pi) -> np.ndarray:
    n = max(8, int(math.ceil(abs(a1 - a0) * r / h)))
    a = np.linspace(a0, a1, n, endpoint=abs(a1 - a0) < 2 * math.pi - 1e-9)
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def gmsh_triangles(loops: list[np.ndarray], size_fn, bare: np.ndarray | None = None,
              what: str = "gmsh (tooth-mesh rim)") -> tuple[np.ndarray, np.ndarray]:
    """P1 triangles of the region inside loops[0] and outside the others (gmsh, geo kernel: fast for the
    thousands of segments of a 200-tooth outline), in a guarded child. ``bare``: a mask over loops[0]'s points;
    a segment between two masked points keeps no interior node (a contact zone's own spacing)."""
    from strainwave.fea.session import mesh_in_child

    def build(model):
        import gmsh
        curves, first = [], []
        for loop in loops:
            pts = [model.geo.addPoint(float(x), float(y), 0.0) for x, y in loop]
            lines = [model.geo.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
            first = first or lines
            curves.append(model.geo.addCurveLoop(lines))
        model.geo.addPlaneSurface(curves)
        model.geo.synchronize()
        n = len(first)
        for i in range(n) if bare is not None else ():
            if bare[i] and bare[(i + 1) % n]:
                model.mesh.setTransfiniteCurve(first[i], 2)
        for key in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature"):
            gmsh.option.setNumber(key, 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        model.mesh.setSizeCallback(lambda dim, tag, x, y, z, lc: size_fn(x, y))
        model.mesh.generate(2)
        tags, xyz, _ = model.mesh.getNodes()
        _, _, conn = model.mesh.getElements(2)
        idx = np.full(int(tags.max()) + 1, -1)
        idx[tags.astype(int)] = np.arange(tags.size)
        return xyz.reshape(-1, 3)[:, :2].T.copy(), idx[np.asarray(conn[0], int).reshape(-1, 3)].T.copy()

    return mesh_in_child(build, what=what)


def _factorise(K: sp.spmatrix, T: sp.csr_matrix, fixed: np.ndarray):
    from scipy.sparse.linalg import splu
    Kt = (T.T @ K @ T).tocsr()
    free = np.setdiff1d(np.arange(Kt.shape[0]), fixed)
    # symmetric 2D: minimum degree on A^T + A keeps the factor near nested dissection's
    lu = splu(Kt[free][:, free].tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
              options={"SymmetricMode": True})
    return free, lu.solve


def _rotation(points: np.ndarray, nodes: np.ndarray, n_dofs: int) -> sp.csr_matrix:
    """u = T u~: at ``nodes`` u~ = (u_r, u_theta); elsewhere the identity."""
    ang = np.arctan2(points[1, nodes], points[0, nodes])
    c, s = np.cos(ang), np.sin(ang)
    T = sp.identity(n_dofs, format="lil")
    for k, i in enumerate(nodes):
        T[2 * i, 2 * i], T[2 * i, 2 * i + 1] = c[k], -s[k]
        T[2 * i + 1, 2 * i], T[2 * i + 1, 2 * i + 1] = s[k], c[k]
    return T.tocsr()


def _assemble(p, t, lame: Lame, thickness_mm: float):
    from skfem import ElementTriP2, MeshTri
    mesh = MeshTri(p, t)
    basis = scalar_basis(mesh, ElementTriP2(), intorder=4)
    return mesh, basis, elasticity_stiffness(basis, lame, thickness_mm=thickness_mm)


def _bore_bed(mesh, basis, r_bore_mm: float, k_N_per_mm3: float):
    """Stiffness of a radial Winkler bed (modulus per unit bore area) under the bore, per unit thickness."""
    from skfem import BilinearForm, ElementVector, FacetBasis
    from skfem.helpers import dot
    bf = mesh.boundary_facets()
    r_mid = np.hypot(*mesh.p[:, mesh.facets[:, bf]].mean(axis=1))
    fb = FacetBasis(mesh, ElementVector(basis.elem), facets=bf[r_mid < r_bore_mm + 1e-3], intorder=4)

    @BilinearForm
    def bed(u, v, w):
        # radial, not the chord's normal: a chord's normal would also hold the bore's tangential slip
        e = w.x / np.sqrt(w.x[0] ** 2 + w.x[1] ** 2)
        return k_N_per_mm3 * dot(u, e) * dot(v, e)
    return bed.assemble(fb)


def rim_model(spec, r_bore_mm: float, h_mm: float, lame: Lame, thickness_mm: float,
              bed_N_per_mm2: float | None = None) -> RimSolve:
    """The flexspline's whole toothed rim on a rigid WG (radially held bore), factorised. ``bed_N_per_mm2``: the
    bore on a radial Winkler bed instead (N/mm per mm of bore, over the whole thickness: the WG bearing's balls)."""
    t0 = time.perf_counter()
    outer = _outline(spec, n_flank=max(6, int(math.ceil(2.5 * spec.module_mm / h_mm))))
    bore = _circle(r_bore_mm, h_mm)
    p, t = gmsh_triangles([outer, bore], lambda x, y: h_mm)
    t1 = time.perf_counter()
    mesh, basis, K = _assemble(p, t, lame, thickness_mm)
    locs = basis.doflocs
    on_bore = np.flatnonzero(np.hypot(*locs) < r_bore_mm + 1e-6 * r_bore_mm)
    T = _rotation(locs, on_bore, K.shape[0])
    pin = on_bore[np.argmin(np.abs(np.arctan2(locs[1, on_bore], locs[0, on_bore]) - math.pi / 2))]
    fixed = np.concatenate([2 * on_bore, [2 * pin + 1]])
    if bed_N_per_mm2 is not None:
        # the bed holds the bore radially (and the rim's translation); only the rigid rotation is pinned
        K = K + _bore_bed(mesh, basis, r_bore_mm, bed_N_per_mm2 / thickness_mm) * thickness_mm
        fixed = np.array([2 * pin + 1])
    t2 = time.perf_counter()
    free, solve = _factorise(K, T, fixed)
    t3 = time.perf_counter()
    return RimSolve(h_mm, mesh, basis, T, free, solve, thickness_mm, lame, 0.0, spec.teeth, False,
                    {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2})


def root_slot(outline: np.ndarray, spec, depth_mm: float, width_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """``outline`` with a radial slot (width ``width_mm``, depth ``depth_mm``) cut into the root circle where tooth 0's
    +theta flank meets it (its tension side under a +theta-flank load), and the slot's tip point."""
    from strainwave.geometry.involute import half_angle_rad
    r_f = spec.root_radius_mm
    ang = np.arctan2(outline[:, 1], outline[:, 0])
    r = np.hypot(outline[:, 0], outline[:, 1])
    corner = float(half_angle_rad(spec, r_f)) + 0.5 * width_mm / r_f + 0.05 * spec.module_mm / r_f
    on_root = np.abs(r - r_f) < 1e-6 * r_f
    after = np.flatnonzero(on_root & (ang > corner) & (ang < math.pi / spec.teeth + corner))
    k = int(after[np.argmin(ang[after])])            # the slot is cut before this root point
    s = -1.0 if spec.internal else 1.0               # into the body: inward for external teeth
    tip_r = r_f - s * depth_mm
    half = 0.5 * width_mm / r_f
    cut = np.array([[r_f * math.cos(corner - half), r_f * math.sin(corner - half)],
                    [tip_r * math.cos(corner - half), tip_r * math.sin(corner - half)],
                    [tip_r * math.cos(corner + half), tip_r * math.sin(corner + half)],
                    [r_f * math.cos(corner + half), r_f * math.sin(corner + half)]])
    return np.vstack([outline[:k], cut, outline[k:]]), np.array([tip_r * math.cos(corner), tip_r * math.sin(corner)])


def sector_model(spec, r_held_mm: float, teeth_each_side: int, h_mm: float, lame: Lame,
                 thickness_mm: float, crack: tuple[float, float] | None = None) -> RimSolve:
    """A sector of teeth (tooth 0 on +x and ``teeth_each_side`` either side) on a body held at ``r_held_mm``
    (outside the root for internal teeth: the CS housing; inside it for external: a solid gear body); the mesh
    coarsens away from the teeth."""
    t0 = time.perf_counter()
    pitch = 2 * math.pi / spec.teeth
    a0, a1 = -(teeth_each_side + 0.5) * pitch, (teeth_each_side + 0.5) * pitch
    teeth = _outline(spec, n_flank=max(6, int(math.ceil(2.5 * spec.module_mm / h_mm))))
    ang = np.arctan2(teeth[:, 1], teeth[:, 0])
    keep = (ang > a0) & (ang < a1)
    inner = teeth[keep][np.argsort(ang[keep])]
    tip = None
    if crack is not None:                            # (depth, slot width): a root crack at tooth 0
        inner, tip = root_slot(inner, spec, *crack)
    r_root = spec.root_radius_mm
    start = np.array([[r_root * math.cos(a0), r_root * math.sin(a0)]])
    end = np.array([[r_root * math.cos(a1), r_root * math.sin(a1)]])
    held_arc = _circle(r_held_mm, 4 * h_mm, a1, a0)
    loop = np.vstack([start, inner, end, held_arc])
    grow = lambda x, y: h_mm + 0.5 * abs(math.hypot(x, y) - r_root)  # noqa: E731
    if tip is not None:                              # resolve the slot: h/8 at its tip (one ratio for all three meshes)
        near = lambda x, y: min(h_mm / 8 + 0.5 * math.hypot(x - tip[0], y - tip[1]), h_mm)  # noqa: E731
        p, t = gmsh_triangles([loop], lambda x, y: min(grow(x, y), 8 * h_mm, near(x, y)))
    else:
        p, t = gmsh_triangles([loop], lambda x, y: min(grow(x, y), 8 * h_mm))
    t1 = time.perf_counter()
    mesh, basis, K = _assemble(p, t, lame, thickness_mm)
    r = np.hypot(*basis.doflocs)
    held = np.flatnonzero(r > r_held_mm * (1 - 1e-6) if spec.internal else r < r_held_mm * (1 + 1e-6))
    T = sp.identity(K.shape[0], format="csr")
    t2 = time.perf_counter()
    free, solve = _factorise(K, T, np.concatenate([2 * held, 2 * held + 1]))
    t3 = time.perf_counter()
    return RimSolve(h_mm, mesh, basis, T, free, solve, thickness_mm, lame, 0.0, spec.teeth, bool(spec.internal),
                    {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2})


def _boundary_facet_teeth(model: RimSolve) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The boundary facets, their mid radii, the tooth each faces and its angle off that tooth's centre line."""
    mesh = model.mesh
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    pitch = 2 * math.pi / model.teeth
    rel = np.angle(np.exp(1j * (np.arctan2(mid[1], mid[0]) - model.centre_angle_rad)))
    nearest = np.round(rel / pitch)
    return bf, np.hypot(*mid), nearest.astype(int) % model.teeth, rel - nearest * pitch


def flank_loads(model: RimSolve, teeth: np.ndarray, radius_mm: np.ndarray, band_mm: float,
                side: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit flank loads (columns, in u~ dofs) pressing on flank ``side`` (+1: the tooth's +theta flank) of each
    tooth at its contact radius, and each load's moment about the axis (N mm per N).

    The rim's loads are balanced in moment by a uniform tangential shear on the bore."""
    from skfem import FacetBasis, ElementVector, LinearForm
    bf, r_mid, which, off = _boundary_facet_teeth(model)
    cols, moments = [], []
    ndof = model.T.shape[0]
    for j, rc in zip(teeth, radius_mm):
        sel = bf[(which == j % model.teeth) & (np.sign(off) == side) & (np.abs(r_mid - rc) < band_mm + 0.5 * model.h_mm)]
        if sel.size == 0:
            raise ValueError(f"tooth {j}: no flank facet near r = {rc:.4g} mm")
        fb = FacetBasis(model.mesh, ElementVector(model.basis.elem), facets=sel, intorder=6)

        @LinearForm
        def press(v, w):
            r = np.sqrt(w.x[0] ** 2 + w.x[1] ** 2)
            p = np.maximum(0.0, 1.0 - ((r - rc) / band_mm) ** 2)
            return -p * (w.n[0] * v[0] + w.n[1] * v[1])    # pressure: into the tooth

        f = press.assemble(fb) * model.thickness_mm
        fx, fy = f[0::2], f[1::2]
        x, y = model.basis.doflocs
        force = math.hypot(fx.sum(), fy.sum())
        f = f / force                                      # unit resultant
        moments.append(float((x * f[1::2] - y * f[0::2]).sum()))
        cols.append(f)
    F = np.column_stack(cols) if cols else np.zeros((ndof, 0))
    return model.T.T @ F, np.asarray(moments)


def bore_shear(model: RimSolve, r_bore_mm: float) -> np.ndarray:
    """u~ load vector of a uniform tangential shear on the bore with unit moment (N mm)."""
    from skfem import FacetBasis, ElementVector, LinearForm
    mesh = model.mesh
    bf = mesh.boundary_facets()
    r_mid = np.hypot(*mesh.p[:, mesh.facets[:, bf]].mean(axis=1))
    fb = FacetBasis(mesh, ElementVector(model.basis.elem), facets=bf[r_mid < r_bore_mm + 0.01], intorder=4)

    @LinearForm
    def shear(v, w):
        r = np.sqrt(w.x[0] ** 2 + w.x[1] ** 2)
        return (-w.x[1] * v[0] + w.x[0] * v[1]) / r

    f = shear.assemble(fb) * model.thickness_mm
    x, y = model.basis.doflocs
    f = f / float((x * f[1::2] - y * f[0::2]).sum())
    return model.T.T @ f


def displacements(model: RimSolve, F: np.ndarray) -> np.ndarray:
    """u~ (full) for each column of F (u~ loads)."""
    U = np.zeros_like(F)
    U[model.free] = model.solve(F[model.free])
    return U


def compliance(model: RimSolve, F: np.ndarray) -> np.ndarray:
    """C = F^T K^-1 F (mm/N), symmetrised."""
    C = F.T @ displacements(model, F)
    return 0.5 * (C + C.T)


def _flank_facets(model: RimSolve, side: int, root_mm: float):
    """The boundary facets on flank ``side`` of every tooth (above/below the root circle) and their tooth."""
    bf, r_mid, which, off = _boundary_facet_teeth(model)
    on_tooth = (r_mid < root_mm - 1e-3) if model.internal else (r_mid > root_mm + 1e-3)
    keep = on_tooth & (np.sign(off) == side)
    return bf[keep], which[keep]


def _flank_quadrature(model: RimSolve, side: int, root_mm: float, offsets: np.ndarray):
    """(basis, points x, outward normals n, dx, radius r, slot, want) on flank ``side`` of teeth ``offsets``: the
    quadrature every band reading integrates over (slot: each facet's index in ``want``)."""
    from skfem import ElementVector, FacetBasis
    facets, tooth = _flank_facets(model, side, root_mm)
    want = np.asarray(offsets) % model.teeth
    pick = np.isin(tooth, want)
    facets, tooth = facets[pick], tooth[pick]
    fb = FacetBasis(model.mesh, ElementVector(model.basis.elem), facets=facets, intorder=6)
    x = fb.global_coordinates().value
    slot = np.searchsorted(want, tooth) if np.all(np.diff(want) > 0) else np.array([list(want).index(t) for t in tooth])
    return fb, x, fb.normals.value, fb.dx * model.thickness_mm, np.hypot(x[0], x[1]), slot, want


def influence(model: RimSolve, root_mm: float, radii_mm: np.ndarray, band_mm: float, side: int,
              offsets: np.ndarray, r_bore_mm: float | None) -> np.ndarray:
    """c[d, a, b] (mm/N): flank displacement (along the flank normal, into tooth ``offsets[d]``, at radius
    ``radii_mm[b]``) per unit flank load on tooth 0 at ``radii_mm[a]``. With ``r_bore_mm`` (the rim) each load
    is balanced by the bore's uniform shear and the displacement is relative to the bore's mean rotation (the
    rotation's work on a self-equilibrated pair of loads); the teeth are all alike, so tooth j on tooth k is
    c[k - j] (the mesh is not periodic: the difference is a discretisation error the GCI sees)."""
    F, M = flank_loads(model, np.zeros(radii_mm.size, int), radii_mm, band_mm, side)
    shear = None
    if r_bore_mm is not None:
        shear = bore_shear(model, r_bore_mm)
        F = F - shear[:, None] * M[None, :]
    U = displacements(model, F)
    Uc = model.T @ U
    fb, x, n, dx, r, slot, want = _flank_quadrature(model, side, root_mm, offsets)
    out = np.zeros((want.size, radii_mm.size, radii_mm.size))
    normal_u = [-(fb.interpolate(Uc[:, a]).value * n).sum(0) for a in range(radii_mm.size)]   # (nf, nq) each
    for b, rb in enumerate(radii_mm):
        p = np.maximum(0.0, 1.0 - ((r - rb) / band_mm) ** 2) * dx            # (nf, nq)
        fx = np.bincount(slot, (-n[0] * p).sum(1), want.size)
        fy = np.bincount(slot, (-n[1] * p).sum(1), want.size)
        mom = np.bincount(slot, ((x[0] * -n[1] - x[1] * -n[0]) * p).sum(1), want.size)
        norm = np.hypot(fx, fy)
        for a in range(radii_mm.size):
            disp = np.bincount(slot, (normal_u[a] * p).sum(1), want.size)
            rot = 0.0 if shear is None else float(shear @ U[:, a])
            out[:, a, b] = (disp - mom * rot) / norm
    return out


def turned(model: RimSolve, F: np.ndarray) -> np.ndarray:
    """Pressure bands F (u~ columns) as tangential tractions along t = rot90(n), n the flank's outward normal (the
    minus resultant of F), each with a unit resultant along t (fea/mesh_friction.turned_bands)."""
    from strainwave.fea.mesh_friction import turned_bands
    full = model.T @ F          # T is a rotation at each bore node, else the identity: u~ loads -> full
    res = np.stack([full[0::2].sum(0), full[1::2].sum(0)], axis=1)
    n = -res / np.hypot(res[:, 0], res[:, 1])[:, None]
    return model.T.T @ turned_bands(full, np.column_stack([-n[:, 1], n[:, 0]]))


def load_moments(model: RimSolve, F: np.ndarray) -> np.ndarray:
    """Each load column's moment about the axis (N mm per N)."""
    x, y = model.basis.doflocs
    full = model.T @ F
    return (x[:, None] * full[1::2] - y[:, None] * full[0::2]).sum(0)


def _read_blocks(model: RimSolve, Uc: np.ndarray, rot: np.ndarray, root_mm: float, radii_mm: np.ndarray,
                 band_mm: float, side: int, offsets: np.ndarray) -> np.ndarray:
    """c[x, y, d, a, b]: the band reading of kind y (0: normal into the tooth, 1: along t = rot90(n)) on flank
    ``side`` of tooth ``offsets[d]`` at radius b, per unit load column x * na + a of ``Uc`` (full dofs)."""
    na = radii_mm.size
    fb, x, n, dx, r, slot, want = _flank_quadrature(model, side, root_mm, offsets)
    dirs = (-n, np.stack([-n[1], n[0]]))
    u = [fb.interpolate(Uc[:, c]).value for c in range(Uc.shape[1])]          # (2, nf, nq) each
    out = np.zeros((2, 2, want.size, na, na))
    for b, rb in enumerate(radii_mm):
        p = np.maximum(0.0, 1.0 - ((r - rb) / band_mm) ** 2) * dx
        for y, e in enumerate(dirs):
            fx, fy = (np.bincount(slot, (e[i] * p).sum(1), want.size) for i in (0, 1))
            mom = np.bincount(slot, ((x[0] * e[1] - x[1] * e[0]) * p).sum(1), want.size)
            norm = np.hypot(fx, fy)
            for c, uc in enumerate(u):
                disp = np.bincount(slot, ((uc * e).sum(0) * p).sum(1), want.size)
                out[c // na, y, :, c % na, b] = (disp - mom * rot[c]) / norm
    return out


def influence_blocks(model: RimSolve, root_mm: float, radii_mm: np.ndarray, band_mm: float, side: int,
                     read_sides: tuple, offsets: np.ndarray, r_bore_mm: float | None) -> dict:
    """{read side: c[x, y, d, a, b]} (mm/N): tooth 0's flank ``side`` loaded at radius a by a unit band of kind x
    (0: the pressure band, ``influence``'s load; 1: the same band turned to the flank's tangent t = rot90(n)), read
    on flank ``read side`` of tooth ``offsets[d]`` at radius b as kind y. As ``influence`` (whose numbers are
    c[0, 0] on the loaded side): each load balanced by the bore's shear, readings relative to the bore's rotation;
    tooth j on tooth k is c[..., k - j, ...] by the teeth's translation symmetry (decision 073-slipstudy48)."""
    F, M = flank_loads(model, np.zeros(radii_mm.size, int), radii_mm, band_mm, side)
    G = turned(model, F)
    L = np.hstack([F, G])
    rot = np.zeros(L.shape[1])
    if r_bore_mm is not None:
        shear = bore_shear(model, r_bore_mm)
        L = L - shear[:, None] * np.concatenate([M, load_moments(model, G)])[None, :]
    U = displacements(model, L)
    if r_bore_mm is not None:
        rot = shear @ U
    Uc = model.T @ U
    return {s: _read_blocks(model, Uc, rot, root_mm, radii_mm, band_mm, s, offsets) for s in read_sides}
