"""One plane-stress solve of a ring cross-section (seed 003, Fig. 3): force-controlled or EWG-controlled.

The whole ring is meshed (the toothed ring is doubly symmetric only when Z_R is a multiple of 4), with
nodes forced onto A, B (+/-x) and D (+y) of the outer circle and onto the ends of the two contact arcs,
so the arcs carry exactly their pressure and the three rigid-body constraints sit on the symmetry axes:
u_y(A) = u_y(B) = 0 and u_x(D) = 0 hold in the exact symmetric solution, so they carry no reaction, and
C (-y) is left free for the symmetry check delta_C = delta_D.
"""
from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass

import numpy as np

from strainwave.fea.assembly import Lame, elasticity_stiffness, facet_vector_basis, scalar_basis
from strainwave.fea.mesh_data import MeshData, SkfemMesh, to_skfem
from strainwave.fea.meshing import Refine, mesh_section
from strainwave.fea.ring_loads import ArcLoad
from strainwave.fea.ring_sections import (MidLayer, Probes, boundary_stress_MPa, fibre_points, hoop, hoop_at,
                                         mid_layer_points, peak_near, signed_principal)
from strainwave.fea.session import mesh_in_child
from strainwave.fea.solver import SolverInfo
from strainwave.fea.surface import SurfaceQuadrature


@dataclass(frozen=True)
class RingGeometry:
    """Radii of the rim (root circle to outer circle), the mid-layer radius and the width B."""

    r_root_mm: float          # inner fibre of the rim: root circle of the internal teeth (or the bore)
    r_outer_mm: float
    r_m_mm: float             # seed 003, eq 1
    width_mm: float

    @property
    def thickness_mm(self) -> float:
        return self.r_outer_mm - self.r_root_mm


@dataclass(frozen=True)
class PlaneSolution:
    """What one 2D solve yields, in the units of its load (force case: per ``force_N``)."""

    h_mm: float
    force_N: float            # applied (force case) or reaction (EWG case) on one arc, along y
    mid: MidLayer
    sigma_B: tuple[float, float]    # (outer, inner) hoop stress at section B
    sigma_D: tuple[float, float]
    root_B_MPa: float         # signed peak principal stress on the inner boundary within a pitch of B
    root_D_MPa: float
    outer_B_MPa: float        # peak outer-fibre hoop stress within a pitch of B (the rim's nominal stress)
    outer_D_MPa: float
    mesh: MeshData
    timings_s: dict
    solver: dict
    fields: tuple = ()        # (sk, u, lame) for VTU output


@contextlib.contextmanager
def _tri_edges_are_facets():
    """fea/mesh_data.to_skfem reads ``MeshTri1.edges``, which scikit-fem only defines in 3D; in 2D the
    edges are the facets. Reported to the FEA core; this shim is scoped to the conversion call."""
    import skfem
    saved = skfem.MeshTri1.__dict__.get("edges")
    skfem.MeshTri1.edges = property(lambda self: self.facets)
    try:
        yield
    finally:
        if saved is None:
            del skfem.MeshTri1.edges
        else:
            skfem.MeshTri1.edges = saved


def _facet_bases(sk: SkfemMesh, facets: np.ndarray) -> list:
    """Facet bases covering ``facets``, split in halves where scikit-fem's inverse mapping fails.

    On some toothed meshes (Z_R = 80 and 100, measured) the Newton inversion of the curved P2 mapping at the
    facet quadrature points stops short of its 1e-12 tolerance when all boundary facets are inverted as one
    batch, although every facet inverts alone; halving the batch finds the same points."""
    try:
        return [facet_vector_basis(sk.mesh, sk.element, facets, intorder=4)]
    except Exception as exc:   # scikit-fem raises a bare Exception for a Newton failure
        if "Newton" not in str(exc):
            raise
        if facets.size <= 1:    # one badly curved coarse element: damped Newton without the [0, 1] clip
            from skfem import ElementVector, FacetBasis
            return [FacetBasis(sk.mesh, ElementVector(sk.element), facets=facets, intorder=4,
                               mapping=_damped_mapping(sk.mesh))]
        half = facets.size // 2
        return _facet_bases(sk, facets[:half]) + _facet_bases(sk, facets[half:])


def _damped_mapping(mesh):
    """The mesh's isoparametric mapping with an inverse that takes half Newton steps (up to 400) from the
    element centroid; the facet points it inverts lie on the element's own edge, so no clipping is needed."""
    from skfem.mapping import MappingIsoparametric

    class _Damped(MappingIsoparametric):
        def invF(self, x, tind=None, newton_max_iters=400, newton_tol=1e-12):
            X = np.zeros(x.shape) + 1.0 / 3.0
            for _ in range(newton_max_iters):
                dX = np.einsum("ijkl,jkl->ikl", self.invDF(X, tind), x - self.F(X, tind))
                X = X + 0.5 * dX
                if (np.linalg.norm(dX, 1, (0, 2)) < newton_tol).all():
                    return X
            raise Exception(f"Newton iteration didn't converge up to TOL={newton_tol} (damped)")

    return _Damped(mesh, mesh.elem(), mesh.bndelem)


def _boundary_stress(bases: list, u, lame: Lame) -> tuple[np.ndarray, np.ndarray]:
    parts = [boundary_stress_MPa(fb, u, lame) for fb in bases]
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts], axis=1)


def section_to_skfem(md: MeshData) -> SkfemMesh:
    try:
        return to_skfem(md)
    except np.exceptions.AxisError:
        with _tri_edges_are_facets():
            return to_skfem(md)


def mesh_ring_section(face, geo: RingGeometry, load: ArcLoad, *, size_mm: float, order: int) -> MeshData:
    """Mesh the section with the contact arcs resolved (8 elements per arc) and named."""
    r_o, th = geo.r_outer_mm, load.half_angle_rad
    ends = [(r_o * np.cos(c + s * th), r_o * np.sin(c + s * th)) for c in (0.5 * np.pi, -0.5 * np.pi) for s in (-1, 1)]
    arc_mm = 2.0 * th * r_o
    # the predicate sees points sampled along each curve (meshing._match): the contact arcs lie wholly
    # within |x| < arc length, on the outer side of the mid-layer
    contact = lambda pts: bool(np.all(np.abs(pts[:, 0]) < arc_mm) and np.all(np.abs(pts[:, 1]) > geo.r_m_mm))  # noqa: E731
    # A fixed load-zone size (arc/8): scaled with h, the toothed ring's root peaks oscillated (docs/decisions/011-ring-meshes.md)
    refine = Refine(size_mm=min(size_mm, arc_mm / 8), dist_min_mm=arc_mm, dist_max_mm=6 * geo.thickness_mm,
                    points_mm=((0.0, r_o, 0.0), (0.0, -r_o, 0.0)))
    return mesh_in_child(lambda model: mesh_section(
        model, face, size_mm=size_mm, order=order, named_edges={"contact": contact},
        named_points={"A": [(-r_o, 0.0)], "B": [(r_o, 0.0)], "D": [(0.0, r_o)], "C": [(0.0, -r_o)], "arc_ends": ends},
        refine=[refine]))


def solve_ring_section(face, geo: RingGeometry, load: ArcLoad, lame: Lame, *, size_mm: float, order: int,
                       ewg_w0_mm: float | None = None, pitch_rad: float | None = None,
                       keep_fields: bool = False) -> dict[str, PlaneSolution]:
    """Mesh and assemble once; solve the arc load ("force") and, if ``ewg_w0_mm`` is given, the EWG case
    ("ewg"): rigid flat contact strips pushed in radially by W0 (u_y = -W0 on the arc at D, +W0 at C),
    tangential motion free. Both come back with the same mesh."""
    t0 = time.perf_counter()
    md = mesh_ring_section(face, geo, load, size_mm=size_mm, order=order)
    t1 = time.perf_counter()
    sk = section_to_skfem(md)
    sb = scalar_basis(sk.mesh, sk.element, intorder=4)    # curved P2: order 4 integrates the mapping well
    K = elasticity_stiffness(sb, lame, thickness_mm=geo.width_mm)
    t2 = time.perf_counter()
    dof = lambda name, c: 2 * sk.node_to_dof[md.group_nodes(name)] + c     # noqa: E731
    base_fixed = np.concatenate([dof("A", 1), dof("B", 1), dof("D", 0)])
    arc = np.unique(sk.node_to_dof[md.group_nodes("contact")])
    arc_top, arc_bottom = arc[sb.doflocs[1, arc] > 0], arc[sb.doflocs[1, arc] < 0]
    # on the curved contact edges themselves (fea/surface.py, the one facet quadrature), degree 8 for the
    # square-root profile's ends
    f = geo.width_mm * SurfaceQuadrature.of(md, "contact", order=8).load_vector(
        lambda x: -load.pressure_MPa(x[0], x[1]) * x / np.hypot(x[0], x[1]), sk.node_to_dof, 2, 2 * sb.N)
    # each arc's y-resultant is F up to the quadrature of the square-root profile: make it exact
    top = sb.doflocs[1] > 0
    fy = f[1::2]
    fy[top] *= load.force_N / -fy[top].sum()
    fy[~top] *= load.force_N / fy[~top].sum()
    f[1::2] = fy
    # one factorisation serves both cases: the EWG strips hold the arcs' u_y, from the Schur complement on them
    arc_y = np.sort(np.concatenate([2 * arc_top + 1, 2 * arc_bottom + 1]))
    solutions, reaction_N = _solve_cases(K, f, base_fixed, arc_y, np.isin(arc_y, 2 * arc_top + 1), ewg_w0_mm)
    window = 0.5 * pitch_rad if pitch_rad else 0.5 * geo.thickness_mm / geo.r_root_mm
    t3 = time.perf_counter()
    read = _SectionReader.of(sk, sb, geo, window)
    out = {}
    for name, (rhs, u, info) in solutions.items():
        te = time.perf_counter()
        out[name] = read(u, lame, size_mm, reaction_N if name == "ewg" else load.force_N, md,
                         {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2},
                         info.to_dict(), keep_fields, te)
    return out


def _window_facets(mesh, facets: np.ndarray, window_rad: float) -> np.ndarray:
    """The ``facets`` that may hold a point within ``window_rad`` of B (0) or D (pi/2): a vertex within the window
    widened by the facet's own angular span (its curved points lie between its ends)."""
    ang = np.arctan2(mesh.p[1, mesh.facets[:, facets]], mesh.p[0, mesh.facets[:, facets]])      # (2, n)
    span = np.abs(np.angle(np.exp(1j * (ang[1] - ang[0]))))
    near = np.zeros(facets.size, bool)
    for centre in (0.0, 0.5 * np.pi):
        d = np.abs(np.angle(np.exp(1j * (ang - centre)))).min(axis=0)
        near |= d <= window_rad + 2.0 * span
    return facets[near]


@dataclass(frozen=True)
class _SectionReader:
    """What one mesh's solutions are read at, made once for all of them: the mid-layer points and the fibres of B
    and D (one probe basis), and the inner and outer boundary near B and D (facet bases over those facets only)."""

    sk: SkfemMesh
    probes: Probes
    inner: list
    outer: list
    window_rad: float

    @classmethod
    def of(cls, sk: SkfemMesh, sb, geo: RingGeometry, window_rad: float) -> "_SectionReader":
        points = np.hstack([mid_layer_points(geo.r_m_mm), fibre_points(0.0, geo.r_root_mm, geo.r_outer_mm),
                            fibre_points(0.5 * np.pi, geo.r_root_mm, geo.r_outer_mm)])
        # the inner boundary (bore or tooth flanks and roots) and the outer circle, told apart by radius
        radius = lambda x: np.hypot(x[0], x[1])                                  # noqa: E731
        inner = sk.mesh.facets_satisfying(lambda x: radius(x) < geo.r_m_mm, boundaries_only=True)
        outer = sk.mesh.facets_satisfying(lambda x: radius(x) > geo.r_m_mm, boundaries_only=True)
        return cls(sk, Probes.at(sb, points, vector=True), _facet_bases(sk, _window_facets(sk.mesh, inner, window_rad)),
                   _facet_bases(sk, _window_facets(sk.mesh, outer, window_rad)), window_rad)

    def __call__(self, u, lame: Lame, size_mm: float, force_N: float, md: MeshData, timings_s: dict, solver: dict,
                 keep_fields: bool, t0: float) -> PlaneSolution:
        w = self.window_rad
        sig_in, xyz = _boundary_stress(self.inner, u, lame)
        vals_in = signed_principal(sig_in)
        sig_out, xyz_out = _boundary_stress(self.outer, u, lame)
        hoop_out = hoop_at(sig_out, xyz_out)
        mid, fibres = self.probes.values(u)[:, :4], self.probes.stresses(u, lame)[4:]
        h_B, h_D = hoop(fibres[:2], 0.0), hoop(fibres[2:], 0.5 * np.pi)
        return PlaneSolution(
            h_mm=size_mm, force_N=force_N, mid=MidLayer(*mid.T),
            sigma_B=(float(h_B[0]), float(h_B[1])), sigma_D=(float(h_D[0]), float(h_D[1])),
            root_B_MPa=peak_near(vals_in, xyz, 0.0, w), root_D_MPa=peak_near(vals_in, xyz, 0.5 * np.pi, w),
            outer_B_MPa=peak_near(hoop_out, xyz_out, 0.0, w), outer_D_MPa=peak_near(hoop_out, xyz_out, 0.5 * np.pi, w),
            mesh=md, timings_s=dict(timings_s, extract=time.perf_counter() - t0), solver=solver,
            fields=(self.sk, u) if keep_fields else ())


def _solve_cases(K, f: np.ndarray, base: np.ndarray, arc_y: np.ndarray, top: np.ndarray,
                 w0_mm: float | None) -> tuple[dict, float | None]:
    """({case: (load vector, u, solver facts)}, the EWG top arc's reaction or None): the force case (``f``, ``base`` held) and, with ``w0_mm``, the EWG case
    (no load, the arcs' u_y ``arc_y`` also held: -W0 where ``top``, +W0 below), from one factorisation of K with ``base`` held and its Schur complement on ``arc_y``
    (``face_schur.FaceSystem``)."""
    from strainwave.fea.face_schur import FaceSystem

    t0 = time.perf_counter()
    system = FaceSystem.of(K, base, arc_y, "ring-compression")
    reaction_N = None
    try:
        free = system.free
        u = np.zeros(K.shape[0])
        u[free] = system.factor.solve(f[free])
        out = {"force": (f, u, _info(K, f, u, free, system.factor.method, t0))}
        if w0_mm is not None:
            t1 = time.perf_counter()
            zero, held = np.zeros_like(f), np.ones(arc_y.size, bool)
            u_ewg = system.held(zero, np.zeros(arc_y.size), held, np.where(top, -w0_mm, w0_mm))
            # the top strip's reaction as v.K u, v the field of the top strip moved by 1 (the bottom one held): the
            # solution's round-off cancels to first order, where the sum of K u over the strip amplifies it
            v = system.held(zero, np.zeros(arc_y.size), held, top.astype(float))
            keep = np.setdiff1d(free, arc_y, assume_unique=True)
            out["ewg"] = (zero, u_ewg, _info(K, zero, u_ewg, keep, system.factor.method, t1))
            reaction_N = -float(v @ (K @ u_ewg))
    finally:
        system.factor.close()
    return out, reaction_N


def _info(K, f: np.ndarray, u: np.ndarray, free: np.ndarray, method: str, t0: float) -> SolverInfo:
    """Solver facts of one case (``solver.solve_elasticity``'s): ||f - K u|| / ||f - K u_held|| over the equations of
    its unknowns ``free`` (u_held: u with the unknowns zeroed, the prescribed values kept)."""
    held = u.copy()
    held[free] = 0.0
    b = (f - K @ held)[free]
    r = b - (K @ (u - held))[free]
    return SolverInfo(method, int(free.size), 1, float(np.linalg.norm(r) / np.linalg.norm(b)), time.perf_counter() - t0)
