"""Study `bearing-ring` (seed 000): radial compliance of the wave-generator bearing inner ring, with and
without the semi-elliptical surface crack at the ball contact.

Load: the radial force F_r, an input (the registry computes seed 000's F_r = 1.15 k_r T / d1 in
``analytic/study_loads.py``; fea/ holds no closed form), as a Hertzian pressure
p = p0 sqrt(1 - (s/b')^2 - (z'/a')^2), p0 = 3 F_r/(2 pi a' b'), on the race around the contact centre (+x);
a' along the ring axis (across the race), b' along the circumference (rolling direction). The resultant is
made exactly F_r.
Support: the whole bore fixed. The inner ring sits on the wave generator's cam, which is far stiffer
than the ring locally and carries it all round; a bonded bore is that rigid-cam limit (it also removes
every rigid-body mode without a point constraint that would add its own compliance).
Compliance: the work-conjugate displacement of the load, C = f.u / F_r^2 (what the crack-compliance
integral of seed 000 is conjugate to). Crack effect: C(cracked) - C(uncracked) on ONE mesh per refinement:
the ring is meshed with the crack as an embedded zero-width surface (geometry's CrackModel.SEAM) and the
surface opened (fea.crack_seam.open_crack). One factorisation of the opened mesh, with its Schur complement on
the crack pairs' openings (fea.face_schur.SeamSystem), gives both: every pair tied is the seam closed (the
uncracked ring), the pairs in frictionless contact the cracked one, and the difference is the Schur complement's
open block's own term, so the far-field discretization error cancels in it.
With a cache folder (validate's full plan: several depths per gear) the uncracked ring is solved once per
refinement and kept there, and each depth solves only a patch of its seam mesh around the crack, its cut held at
the uncracked ring's field (fea.bearing_patch): the same Schur complement term, on a fraction of the dofs.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Mapping

import numpy as np

from strainwave.errors import StageError
from strainwave.fea import fused_sweeps
from strainwave.fea.assembly import Lame, elasticity_stiffness, scalar_basis
from strainwave.fea.crack_contact import crack_pairs
from strainwave.fea.crack_seam import open_crack_for, seam_crack
from strainwave.fea.fields import field_info, write_solid_fields
from strainwave.fea.mesh_data import group_dofs, to_skfem
from strainwave.fea.mesh_isolated import mesh_part_isolated
from strainwave.fea.meshing import MeshingFailed, Refine
from strainwave.fea.refinement import CRACK_FORMAL_ORDER, DEFAULT_RATIO, refinement_sizes
from strainwave.fea.result import CrackRecord, Load, StudyResult, Support
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, StudyVariant, check_variant, run_variant
from strainwave.fea.solver import solve_elasticity
from strainwave.fea.surface import SurfaceQuadrature

STUDY = "bearing-ring"
PART = "wg-bearing-ring"
# Iterative solve (p-multigrid / AMG-CG, fea/solver.py): 3D P2 fill-in makes a sparse direct solve lose
# early; the crossover is measured by benchmarks/bench_fea.py --compare, not asserted here.
SOLVER = "amg"


def hertz_pressure(force_N: float, semi_axes_mm: tuple[float, float], centre_mm, race_radius_mm: float):
    """Callable x (3, ...) -> pressure (MPa); a' along z, b' along the arc s = R (psi - psi_c)."""
    a_ax, b_circ = semi_axes_mm
    p0 = 3.0 * force_N / (2.0 * np.pi * a_ax * b_circ)
    psi_c = np.arctan2(centre_mm[1], centre_mm[0])

    def p(x):
        s = race_radius_mm * np.angle(np.exp(1j * (np.arctan2(x[1], x[0]) - psi_c)))
        rho2 = (s / b_circ) ** 2 + ((x[2] - centre_mm[2]) / a_ax) ** 2
        return p0 * np.sqrt(np.clip(1.0 - rho2, 0.0, None))
    return p


def contact_centre_mm(part, contact_name: str) -> np.ndarray:
    """Centre of the contact on the race: the named patch's centre projected radially onto the race
    (its centre of mass lies inside the curved surface), or +x at mid-width when only ``race`` is named."""
    bb = part.solid.bounding_box()
    r_out = float(bb.max.X)
    if contact_name == "contact":
        c = np.asarray(part.named_faces["contact"][0].center_mm, float)
        psi = np.arctan2(c[1], c[0])
        return np.array([r_out * np.cos(psi), r_out * np.sin(psi), c[2]])
    return np.array([r_out, 0.0, 0.5 * (bb.min.Z + bb.max.Z)])


def ring_refine(part, params, *, size_mm, refine_points, local_mm, contact_mm=None) -> list[Refine]:
    """Size fields: the contact ellipse (``contact_mm``, default min(size, b'/3)) and the crack front."""
    a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
    centre = contact_centre_mm(part, "contact" if "contact" in part.named_faces else "race")
    c_mm = min(size_mm, contact_mm if contact_mm else b_circ / 3)
    refine = [Refine(size_mm=c_mm, dist_min_mm=max(a_ax, b_circ), dist_max_mm=3 * max(a_ax, b_circ),
                     points_mm=(tuple(centre),))]
    if refine_points:
        refine.append(Refine(size_mm=local_mm, dist_min_mm=2 * local_mm, dist_max_mm=max(a_ax, b_circ),
                             points_mm=tuple(refine_points)))
    return refine


def loaded_ring(md, part, params, lame, *, force_N) -> tuple:
    """(skfem mesh, scalar basis, K, f, fixed dofs) of ``md``: the Hertzian patch (resultant F_r) and the bore
    fixed."""
    sk = to_skfem(md)
    sb = scalar_basis(sk.mesh, sk.element)
    K = elasticity_stiffness(sb, lame)
    f, _ = race_load(md, sk, part, params, force_N=force_N)
    fixed = (3 * group_dofs(sk, md, "bore")[:, None] + np.arange(3)).ravel()
    return sk, sb, K, f, fixed


def race_load(md, sk, part, params, *, force_N, scale=None) -> tuple[np.ndarray, float]:
    """(f, scale): the Hertzian pressure on ``md``'s contact facets, times ``scale``; None: the scale that makes
    its resultant F_r exactly (the quadrature of the sqrt profile's edge), which a patch takes from its ring."""
    a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
    contact_name = "contact" if "contact" in part.named_faces else "race"
    centre = contact_centre_mm(part, contact_name)
    race_nodes = group_dofs(sk, md, contact_name)
    r_race = float(np.median(np.hypot(*sk.doflocs[:2, race_nodes])))
    p = hertz_pressure(force_N, (a_ax, b_circ), centre, r_race)
    # integrated on the facet triangles (FacetBasis's inverse mapping fails on curved sliver tets), degree 6
    # for the sqrt profile's edge
    f = SurfaceQuadrature.of(md, contact_name, order=6).load_vector(
        lambda x: -p(x) * np.stack([x[0], x[1], 0 * x[2]]) / np.hypot(x[0], x[1]), sk.node_to_dof, 3,
        3 * sk.doflocs.shape[1])
    if scale is None:
        psi = np.arctan2(centre[1], centre[0])
        scale = force_N / -(f[0::3].sum() * np.cos(psi) + f[1::3].sum() * np.sin(psi))
    return f * scale, float(scale)


def compliance_on_mesh(md, part, params, lame, *, force_N, method=SOLVER, keep_field=False) -> tuple:
    """Load (Hertzian patch, resultant F_r), fix the bore, solve once on ``md``:
    (compliance, solver info dict, field or ())."""
    if method != "direct" and md.order == 2 and 3 * md.nodes_mm.shape[0] >= fused_sweeps.MIN_DOFS:
        fused_sweeps.warm_up()        # numba loads beside the assembly (fused_sweeps.warm_up)
    sk, sb, K, f, fixed = loaded_ring(md, part, params, lame, force_N=force_N)
    u, info = solve_elasticity(K, f, fixed_dofs=fixed, coords=sb.doflocs, dim=3, study=STUDY, method=method,
                               p2_element_dofs=sb.element_dofs if md.order == 2 else None)
    return float(f @ u) / force_N ** 2, info.to_dict(), ((md, sk, u) if keep_field else ())


def crack_compliances_on_mesh(md, opened, part, params, lame, *, force_N, keep_field=False) -> tuple:
    """The seam mesh ``md`` uncracked and cracked from one factorisation of the opened mesh (``opened``) with
    its Schur complement on the crack pairs' openings (``face_schur.SeamSystem``): every pair tied is ``md``
    (the same nodes joined), the pairs in frictionless contact (``crack_contact``'s active set) the crack.
    (uncracked, cracked, delta compliance, solver info dict, uncracked field or (), cracked field or ())."""
    from strainwave.fea.face_schur import SeamSystem, open_compliance
    sk, sb, K, f, fixed = loaded_ring(opened, part, params, lame, force_N=force_N)
    t0 = time.perf_counter()
    seam = SeamSystem.of(K, fixed, crack_pairs(opened).in_dofs(sk.node_to_dof), STUDY)
    try:
        ft, r = seam.loads(f)
        tied = seam.solution(ft, r, np.ones(r.size, bool))
        res = seam.contact(ft, r)
        # the crack's compliance from S's open block, not the difference of two energies
        delta = open_compliance(seam.faces.factor.S, r, seam.held(res.active)) / force_N ** 2
    finally:
        seam.close()
    c0 = float(f @ tied) / force_N ** 2
    inner = np.setdiff1d(seam.faces.free, seam.faces.face_z)
    residual = float(np.linalg.norm((seam.T.T @ (K @ tied) - ft)[inner]) / np.linalg.norm(ft[inner]))
    info = dict(method=f"{seam.faces.factor.method}-schur", dofs=int(seam.faces.free.size), iterations=1,
                residual=residual, time_s=time.perf_counter() - t0, schur_dofs=int(r.size),
                contact_iterations=res.iterations, contact_pairs=int(res.active.size),
                contact_closed_pairs=int(res.active.sum()), contact_min_opening_mm=float(res.opening_mm.min()),
                contact_max_opening_mm=float(res.opening_mm.max()),
                compliance_without_contact_mm_per_N=float(f @ res.u_unconstrained) / force_N ** 2)
    if not keep_field:
        return c0, c0 + delta, delta, info, (), ()
    # the tied solution on md's own dofs: md's nodes are the opened mesh's first ones
    sk0 = to_skfem(md)
    u0 = np.zeros(3 * sk0.node_to_dof.size)
    u0.reshape(-1, 3)[sk0.node_to_dof] = tied.reshape(-1, 3)[sk.node_to_dof[:sk0.node_to_dof.size]]
    return c0, c0 + delta, delta, info, (md, sk0, u0), (opened, sk, res.u)


# Patch radius over the crack's larger half-size max(a, c): its cut held rigid costs O((size / radius)^2)
# (docs/decisions/050-bearing-crack-patch.md)
PATCH_OVER_CRACK = 4.0


def crack_centre_mm(part) -> np.ndarray:
    """The crack's mouth centre: its front's points at the race (the seam's plane point at the surface)."""
    front = np.asarray(part.crack_front_mm, float)
    r = np.hypot(front[:, 0], front[:, 1])
    mouth = front[r >= r.max() - 1e-9 * r.max()]
    return mouth.mean(axis=0)


def crack_half_size_mm(part) -> float:
    """max(a, c): the front's farthest point from the mouth centre."""
    return float(np.linalg.norm(np.asarray(part.crack_front_mm, float) - crack_centre_mm(part), axis=1).max())


def global_ring(params, lame, *, force_N, h_mm, contact_mm, order, cache_dir=None, progress=lambda m: None):
    """The uncracked ring (``bearing_patch.GlobalRing``) meshed at global size ``h_mm`` and contact size
    ``contact_mm``; ``cache_dir``: kept there and read back by every later call with the same parameters but
    the crack's depth (the ring carries no crack), sizes and order."""
    from strainwave.cache import shared_entry
    from strainwave.fea.bearing_patch import read_global, write_global
    path = None if cache_dir is None else _global_file(params, force_N, h_mm, contact_mm, order, cache_dir)
    return shared_entry(path, read_global, lambda: _solve_global_ring(params, lame, force_N=force_N, h_mm=h_mm,
                                                                      contact_mm=contact_mm, order=order,
                                                                      progress=progress), write_global)


def _solve_global_ring(params, lame, *, force_N, h_mm, contact_mm, order, progress):
    """The uncracked ring meshed and solved (``global_ring`` without its cache)."""
    from strainwave.fea.bearing_patch import GlobalRing
    progress(f"{STUDY}: the uncracked ring, h = {h_mm:.3g} mm")
    part = build_plain_part(params)
    t0 = time.perf_counter()
    md, size_factor = mesh_ring(part, params, size_mm=h_mm, order=order, refine_points=(), local_mm=h_mm,
                                contact_mm=contact_mm)
    t1 = time.perf_counter()
    c0, info, (md, sk, u) = compliance_on_mesh(md, part, params, lame, force_N=force_N, keep_field=True)
    _, scale = race_load(md, sk, part, params, force_N=force_N)
    return GlobalRing(md, u, c0, dict(info, load_scale=scale, size_factor=size_factor), t1 - t0,
                      time.perf_counter() - t1)


def _global_file(params, force_N, h_mm, contact_mm, order, cache_dir) -> Path:
    from strainwave.cache import case_key
    data = params.to_dict()
    data["wave_generator"].pop("bearing_crack_depth_mm", None)     # the uncracked ring carries no crack
    key = case_key("bearing-ring-uncracked", {"params": data, "force_N": force_N, "h_mm": h_mm,
                                              "contact_mm": contact_mm, "order": order})
    return Path(cache_dir) / f"bearing-ring-uncracked-{key}.npz"


def mesh_ring(part, params, *, size_mm, order, refine_points, local_mm, contact_mm=None) -> tuple:
    """(mesh, size factor of the successful gmsh attempt)."""
    refine = ring_refine(part, params, size_mm=size_mm, refine_points=refine_points, local_mm=local_mm,
                         contact_mm=contact_mm)
    try:   # in a forked child: gmsh's high-order optimiser can abort natively (seen on the old slot)
        return mesh_part_isolated(part, size_mm=size_mm, order=order, refine=refine)
    except MeshingFailed as exc:
        raise StageError("mesh", STUDY, f"h = {size_mm:g} mm: {exc}") from exc


# No floor: the short semi-elliptical front affords a/3 at any depth (docs/decisions/009-bearing-crack-front-grading.md).
FRONT_FLOOR_OVER_H = 0.0


def crack_front_size_mm(a_mm: float, fine_mm: float, floor_over_h: float = FRONT_FLOOR_OVER_H) -> float:
    """Element size at the crack front on the finest mesh: a/3, not below ``floor_over_h`` h."""
    return max(a_mm / 3.0, floor_over_h * fine_mm)


def build_seam_part(params, crack_depth_mm: float):
    """The wave-generator bearing inner ring with its crack as an embedded seam (tests substitute a stand-in)."""
    from strainwave.geometry.part import CrackModel
    from strainwave.geometry.parts import build_part
    return build_part(PART, params, crack_depth_mm=crack_depth_mm, crack_model=CrackModel.SEAM)


def build_plain_part(params):
    """The uncracked wave-generator bearing inner ring (tests substitute a stand-in)."""
    from strainwave.geometry.parts import build_part
    return build_part(PART, params)


def vtu_paths(vtu) -> tuple[Path, Path]:
    """(cracked, uncracked) field files next to ``vtu``: <stem>_cracked.vtu first (the report's close-up)."""
    v = Path(vtu)
    return v.with_name(f"{v.stem}_cracked.vtu"), v.with_name(f"{v.stem}_uncracked.vtu")


COMPLIANCE = "radial_compliance_mm_per_N"
CRACKED = "cracked_radial_compliance_mm_per_N"
DELTA = "delta_radial_compliance_mm_per_N"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: t_i / 3 (t_i / 2 with --quick)."""
    return params.wave_generator.bearing_inner_ring_thickness_mm / (2.0 if quick else 3.0)


def race_section_mm2(params) -> tuple[float, float]:
    """The inner ring's cross-section area in the plane (the element estimate's volume per mm of width) and
    its thickness t_i: geometry/bearing_ring.py's race radius d1/2 - delta - t_o - D_w, bore t_i inside."""
    from strainwave.geometry.bearing_ring import race_radius_mm

    t = params.wave_generator.bearing_inner_ring_thickness_mm
    r_race = max(race_radius_mm(params), t)
    return math.pi * (r_race ** 2 - max(r_race - t, 0.0) ** 2), t


def patch_depth_limit_mm(params) -> float:
    """Deepest crack whose surface half-length c still fits the contact patch: geometry/bearing_ring.py refuses
    c >= 0.5 sqrt(pi) a' (the patch half-length across the race), with c from Q = 1 + 1.464 (a/c)^1.65
    (seed 000); c/a is fixed by Q, so the depth is bounded."""
    from strainwave.geometry.cracks import half_length_from_q

    patch_half_mm = 0.5 * math.sqrt(math.pi) * params.wave_generator.contact_semi_axes_mm[0]
    return patch_half_mm / half_length_from_q(1.0, params.cracks.surface_crack_shape_factor)


@dataclass(frozen=True)
class BearingRing(StudyVariant):
    """The skeleton's hooks for the bearing ring: one 3D series. Every length of the size field scales with
    the refinement: global size h, contact size min(h, b'/3) r^k and crack-front size a/3 r^k, so the GCI
    covers the contact zone and the crack front too. With a crack each mesh carries the seam and is solved
    tied and opened (faces in frictionless contact) from one factorisation: of the whole ring, or, when the
    uncracked ring is shared (``shares_uncracked``), of a patch around the crack."""

    study: ClassVar[str] = STUDY
    elements_per_cell: ClassVar[float] = 10.2
    # full, --quick: validate's schedule (decisions 049, 050)
    cpu_s_per_element: ClassVar[tuple[float, float]] = (1.1e-4, 2.2e-4)
    default_size_mm = staticmethod(default_size_mm)
    rated_load: ClassVar[str] = "strainwave.analytic.rated_load:rated_radial_force"
    stress_field_suffix: ClassVar[str] = "_uncracked"   # a crack tip's peak is singular
    report_component: ClassVar[str] = "bearing"
    title: ClassVar[str] = "bearing inner ring"
    element_text: ClassVar[str] = ("P{order} tetrahedra (curved, isoparametric); crack as a seam with frictionless "
                                   "crack-face contact")
    image_marks: ClassVar[tuple] = (("bore",), "contact", "F_r")
    shares_cache: ClassVar[bool] = True     # the uncracked ring, the same in every crack case of a gear
    params: object
    order: int
    h_fine_mm: float
    force_N: float
    crack_depth_mm: float | None
    cache_dir: Path | None = None
    quick: bool = False

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        area, t = race_section_mm2(params)     # width 4 a' (geometry/bearing_ring.py)
        return area * 4 * params.wave_generator.contact_semi_axes_mm[0], t

    @classmethod
    def feature_cells(cls, params, h_mm: float, wall_mm: float) -> float:
        """The contact patch (``ring_refine``: size min(h, b'/3) within max(a', b') of the patch centre)."""
        a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
        c = min(h_mm, b_circ / 3)
        reach = max(a_ax, b_circ)
        zone_mm3 = min(cls.volume_and_wall(params)[0], (2 * reach) ** 2 * wall_mm)
        cell = min(c, wall_mm) * c * c
        return zone_mm3 / cell if cell > 0 else math.inf

    @classmethod
    def deepest_crack_mm(cls, params) -> float:
        """Half the ring, and 90 % of the contact-patch limit."""
        return min(0.5 * params.wave_generator.bearing_inner_ring_thickness_mm, 0.9 * patch_depth_limit_mm(params))

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        w = params.wave_generator
        a, b = w.contact_semi_axes_mm
        return (("inner ring thickness t_i", f"{w.bearing_inner_ring_thickness_mm:g} mm"),
                ("contact ellipse a' x b'", f"{a:g} x {b:g} mm"), ("wave generator", w.kind.value),
                ("flexspline pitch diameter d1", f"{params.flexspline_cup.pitch_diameter_mm:g} mm"))

    def __post_init__(self):
        check_variant(STUDY, order=self.order, sizes_mm=(self.h_fine_mm,), crack_depth_mm=self.crack_depth_mm,
                      force_N=self.force_N)

    @property
    def lame(self) -> Lame:
        mat = self.params.material
        return Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)

    def build(self):
        if self.crack_depth_mm is None:
            return build_plain_part(self.params)
        return build_seam_part(self.params, self.crack_depth_mm)

    def series(self) -> tuple[SeriesPlan, ...]:
        return (SeriesPlan("solid", refinement_sizes(self.h_fine_mm, DEFAULT_RATIO)),)

    def _local_sizes_mm(self, k: int) -> tuple[float, float]:
        """(contact size, crack-front size) on refinement k: both refine with the global size."""
        scale = DEFAULT_RATIO ** k
        b_circ = self.params.wave_generator.contact_semi_axes_mm[1]
        front = crack_front_size_mm(self.crack_depth_mm, self.h_fine_mm) if self.crack_depth_mm else self.h_fine_mm
        return min(self.h_fine_mm, b_circ / 3.0) * scale, front * scale

    def solve(self, part, series, h_mm, k, keep_fields, progress) -> MeshSolve:
        contact_mm, local_mm = self._local_sizes_mm(k)
        cracked = self.crack_depth_mm is not None
        what = "uncracked" if not cracked else f"a = {self.crack_depth_mm:g} mm: " + (
            "the crack's patch on the uncracked ring" if self.shares_uncracked else
            "one mesh, solved uncracked and with the crack opened")
        progress(f"{STUDY}: {what}, h = {h_mm:.3g} mm")
        t0 = time.perf_counter()
        md, size_factor = mesh_ring(part, self.params, size_mm=h_mm, order=self.order,
                                    refine_points=list(part.crack_front_mm) if cracked else (),
                                    local_mm=local_mm if cracked else h_mm, contact_mm=contact_mm)
        timings = {"mesh": time.perf_counter() - t0}
        t1 = time.perf_counter()
        if cracked and self.shares_uncracked:
            values, fields, solver = self._cracked(part, md, h_mm, contact_mm, keep_fields, progress)
            timings.update(solver.pop("timings"))
        elif cracked:
            # the opened crack's faces may separate but not interpenetrate (crack_contact)
            opened = open_crack_for(md, STUDY)
            c0, c1, delta, info, field0, field1 = crack_compliances_on_mesh(
                md, opened, part, self.params, self.lame, force_N=self.force_N, keep_field=keep_fields)
            timings["assemble+solve_uncracked+cracked"] = time.perf_counter() - t1
            values, fields = {COMPLIANCE: c0, CRACKED: c1, DELTA: delta}, {"uncracked": field0, "cracked": field1}
            # the uncracked mesh's facts; the opened one adds the duplicated crack nodes
            solver = dict(info, dofs_total=md.quality.dofs, dofs_cracked=opened.quality.dofs)
        else:
            c0, solver, field0 = compliance_on_mesh(md, part, self.params, self.lame, force_N=self.force_N,
                                                    keep_field=keep_fields)
            timings["assemble+solve_uncracked"] = time.perf_counter() - t1
            values, fields = {COMPLIANCE: c0}, {"uncracked": field0}
        solver = dict(solver, size_factor=size_factor)
        return MeshSolve(h_mm * size_factor, values, md.quality, timings, solver,
                         fields if keep_fields else {})

    @property
    def shares_uncracked(self) -> bool:
        """The crack by the patch on the uncracked ring kept in the cache folder, which several depths share
        (validate's full plan); without a folder (one solve) or with --quick (one depth) nothing is shared and
        the whole ring's seam, one factorisation per mesh, costs less."""
        return self.cache_dir is not None and not self.quick

    def _cracked(self, part, md, h_mm, contact_mm, keep_fields, progress) -> tuple[dict, dict, dict]:
        """(values, fields, solver facts with their "timings"): the uncracked ring on this refinement (solved
        once per run: ``global_ring``), the crack from the patch of ``md`` around it (``bearing_patch``)."""
        from strainwave.fea.bearing_patch import patch_release
        ring = global_ring(self.params, self.lame, force_N=self.force_N, h_mm=h_mm, contact_mm=contact_mm,
                           order=self.order, cache_dir=self.cache_dir, progress=progress)
        t0 = time.perf_counter()
        scale = ring.solver["load_scale"]

        def load(opened):
            return race_load(opened, to_skfem(opened), part, self.params, force_N=self.force_N, scale=scale)[0]
        # the opened crack's faces may separate but not interpenetrate (crack_contact)
        rel = patch_release(md, crack_centre_mm(part), PATCH_OVER_CRACK * crack_half_size_mm(part), self.lame,
                            ring.displacement(), force_N=self.force_N, study=STUDY, load=load, keep_field=keep_fields)
        c0 = ring.compliance_mm_per_N
        values = {COMPLIANCE: c0, CRACKED: c0 + rel.delta_mm_per_N, DELTA: rel.delta_mm_per_N}
        fields = {"uncracked": ring.field(), "cracked": rel.field} if keep_fields else {}
        timings = {"uncracked_ring": ring.mesh_s + ring.solve_s, "patch": time.perf_counter() - t0}
        # the cracked mesh's facts; the uncracked ring's beside them
        solver = dict(rel.info, dofs_total=md.quality.dofs, uncracked_dofs=ring.solver["dofs"],
                      uncracked_nodes=int(ring.md.nodes_mm.shape[0]),
                      compliance_without_contact_mm_per_N=c0 + rel.info["delta_without_contact_mm_per_N"],
                      uncracked_method=ring.solver["method"], timings=timings)
        return values, fields, solver

    def quantities(self, series: Mapping[str, Series]) -> dict:
        s = series["solid"]
        q = {COMPLIANCE: s.converged(COMPLIANCE, "mm/N")}
        if self.crack_depth_mm is not None:
            q[CRACKED] = s.converged(CRACKED, "mm/N")
            q[DELTA] = s.converged(DELTA, "mm/N", order=CRACK_FORMAL_ORDER)
        return q

    def load(self, part) -> Load:
        a_ax, b_circ = self.params.wave_generator.contact_semi_axes_mm
        on = "contact" if "contact" in part.named_faces else "race"      # the patch compliance_on_mesh loads
        return Load("wave generator radial force F_r", self.force_N, "N", (on,),
                    "Hertzian ellipsoidal pressure p0 sqrt(1 - (s/b')^2 - (z'/a')^2), p0 = 3 F_r/(2 pi a' b'), "
                    "a' axial x b' circumferential",
                    (("semi_axis_axial_mm", float(a_ax)), ("semi_axis_circumferential_mm", float(b_circ))))

    def supports(self) -> tuple[Support, ...]:
        return (Support(("bore",), "fixed (the wave generator's cam: rigid and bonded)"),)

    def crack(self, part) -> CrackRecord | None:
        if self.crack_depth_mm is None:
            return None
        return seam_crack(self.crack_depth_mm, part, "at the Hertz centre, frictionless crack-face contact")

    def write_fields(self, series: Mapping[str, Series], vtu: Path, load: Load) -> tuple[Path, ...]:
        fields = series["solid"].finest.fields
        info = field_info(STUDY, load.describe(), self.params.material)
        if self.crack_depth_mm is None:
            return (write_solid_fields(vtu, *fields["uncracked"], self.lame, info=info),)
        return tuple(write_solid_fields(path, *fields[label], self.lame, info=info)
                     for path, label in zip(vtu_paths(vtu), ("cracked", "uncracked")))

    def meta(self, part, series: Mapping[str, Series]) -> dict:
        s = series["solid"]
        mat = self.params.material
        out = {"compliance": "work-conjugate f.u/F^2",
               "seed_uncracked_stiffness_N_per_mm": self.params.wave_generator.uncracked_radial_stiffness_N_per_mm,
               "fea_uncracked_stiffness_N_per_mm": 1.0 / s.finest.values[COMPLIANCE],
               "mesh_sizes_mm": list(s.h_mm), "contact_sizes_mm": [self._local_sizes_mm(k)[0] for k in range(3)],
               "mesh_size_factors": {f"h{k}": m.solver["size_factor"] for k, m in enumerate(s.solves)},
               "E_MPa": mat.youngs_modulus_MPa, "nu": mat.poisson_ratio, "G_implied_MPa": mat.implied_shear_modulus_MPa}
        if self.crack_depth_mm is not None:
            out["crack_front_sizes_mm"] = [self._local_sizes_mm(k)[1] for k in range(3)]
            out["part"] = {k: v for k, v in (part.meta or {}).items() if isinstance(v, (int, float, str))}
        return out


def run(params, *, force_N: float, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None,
        progress=lambda m: None, quick=False, cache_dir: Path | None = None) -> StudyResult:
    """Radial compliance at the radial force ``force_N`` on three meshes (GCI); with a crack also the
    cracked compliance and their difference on each mesh. None means uncracked, as in every study.
    ``cache_dir``: the uncracked ring's solutions are kept there and read back (``global_ring``), each crack
    solved on a patch around it (``BearingRing.shares_uncracked``)."""
    h = mesh_size_mm or default_size_mm(params, quick)
    return run_variant(BearingRing(params, order, h, float(force_N), crack_depth_mm, cache_dir, quick), vtu=vtu,
                       progress=progress)
