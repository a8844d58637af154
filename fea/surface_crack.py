"""Study ``cup-surface-crack``: the flexspline's tooth-root crack as a semi-elliptical surface crack, in a
local block of the band wall.

The crack is mm-sized in a cup of 160 mm, so the model is a block of the wall around one tooth root, in the
crack's frame: x along the crack's surface length, y through the wall (0 at the tooth root, the outer
fibre; t at the bore), z normal to the crack. The crack a x c is the quarter ellipse x^2/c^2 + y^2/a^2 <= 1
of the plane z = 0. Two symmetry planes keep a quarter of the block (0 <= x <= b, 0 <= z <= L): the crack
plane z = 0 (the crack's normal stress is symmetric about it) and x = 0. The crack is the seam's lower half:
on z = 0 the ligament is held (u_z = 0) and the crack face is free to lift off (u_z >= 0) and held where it
would pass through its mirror image: frictionless face contact by an active set on the face's normal
gap 2 u_z (a face point is shut where it would interpenetrate, released where its contact force pulls).

Loads, all inputs (fea/ holds no closed form): the stress normal to the crack face on the far face z = L,
sigma_n(y) = membrane + bending (1 - 2y/t) (the wave generator's hoop stress, rotated onto the crack's
plane) plus the torque's membrane per N*mm times the torque (analytic.surface_crack.tooth_root_loads says
how each maps). Supports: u_x = 0 on x = 0, u_z = 0 on the ligament, u_y = 0 at the ligament's corner
(x, y, z) = (0, t, 0) (the loads are self-equilibrated in y).

Quantity: the tangent torsional compliance of the crack at the state (wave generator + rated torque),
delta lambda_f = 4 (f1.u1 - f1.u1_0) s^2: f1 the far-face load of a unit normal stress, u1 its solution
with the converged contact set held, u1_0 the same with the whole face held (the uncracked block, same
mesh), 4 the two symmetry planes, s the torque's crack-face stress per N*mm. P2 tetrahedra graded to the
front (``refinement.CrackFrontGrading``; the checked depth over a wider zone, ``GRADING_CHECKED``) with
quarter-point mid-side nodes on the edges from it, three meshes, GCI of formal order 1 (a crack compliance).
At the checked depth also the closure ratio: -sigma_m/sigma_b at which a compressive outer-fibre bending shuts
the crack whole (``closure_ratio``, by bisection on the face contact).

Solution: one factorisation per mesh, of K with the face free, which also gives S, its Schur complement on the
face's normal dofs (``FaceSystem``); a contact set is then a dense solve of S's open block, and
f1.u1 - f1.u1_0 = r_O . S_OO^-1 r_O (r: f1 condensed on the face, O: the open dofs), without the difference of
two energies.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.errors import InputError
from strainwave.fea.face_schur import FaceSystem, open_compliance
from strainwave.fea.refinement import CRACK_FORMAL_ORDER, DEFAULT_RATIO, CrackFrontGrading, converged_quantity
from strainwave.fea.result import CrackRecord, Load, MeshQuality, StudyResult, Support
from strainwave.fea.study_facts import TORQUE_RATED, StudyFacts

__all__ = ["STUDY", "ASPECT", "DEPTHS_OVER_T", "SurfaceCrack", "Block", "block_for", "block_mesh", "solve_block",
           "converge_depth", "delta_name", "closure_name", "closure_ratio", "quarter_point", "GRADING_CHECKED", "sweep_depths_mm", "run", "FIELDS_STATES", "field_paths", "contact_state"]

STUDY = "cup-surface-crack"
# the crack's shape: a/c = 0.5, a fatigue crack's usual aspect at a notch root (its depth grows slower)
ASPECT = 0.5
# crack depths of the sweep over the wall t; --quick runs the middle one (the checked depth)
DEPTHS_OVER_T = (0.1, 0.2, 0.4)
MAX_ACTIVE_SET_ITERATIONS = 30
# front size a/12 on the finest mesh, graded to h over 2a + h/2 (docs/decisions/029-surface-crack-block.md)
GRADING = CrackFrontGrading(tip_over_a=1.0 / 12.0, floor_over_h=0.02, near_over_a=0.25, zone_over_a=2.0,
                            grow_over_h=0.5)
# the checked depth's grading: the same front, graded to h over 8a + h/2 (the crack's own near field resolved:
# GCI 10.5 -> 0.72 % default, 0.88 % second gear, with quarter-point nodes; decision 067-crack50b)
GRADING_CHECKED = dataclasses.replace(GRADING, zone_over_a=8.0)
# gmsh's 10-node tetrahedron: mid-side nodes 4..9 sit on these vertex pairs
TET10_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3))
# closure: the crack counts as shut when its tangent compliance is below this share of the open crack's (a held
# face keeps ~1e-10 of it: P2 vertices released by their consistent forces, docs/surface_crack.md)
SHUT_SHARE = 1e-6
CLOSURE_BRACKET = (0.0, 1.5)     # -sigma_m/sigma_b: shut at 0 (the face all in compression for a < t/2), open at 1.5
# the fields' stress read this fraction inside each element: a quarter-point element's map is singular at its front node
QUARTER_POINT_INSET = 1e-3
CLOSURE_STEPS = 12               # bisection: the bracket / 2^12 = 3.7e-4
# the fields drawn, at the checked depth: the crack wide open at the major axis and held shut at the minor axis
FIELDS_STATES = ("major", "minor")
HALF_WIDTH_OVER_C = 4.0     # block half-width b = max(4 c, t): f_w of Newman-Raju <= 1.0007 at a/t <= 0.8
LENGTH_OVER_T = 3.0         # far face at L = max(3 t, 4 c) from the crack plane (Saint-Venant decay ~ t)


@dataclass(frozen=True)
class Block:
    """The quarter block of one crack and the crack-face loads of the states it is solved in."""

    t_mm: float
    a_mm: float
    c_mm: float
    E_MPa: float
    nu: float
    per_torque_MPa_per_Nmm: float                # torque's membrane normal to the crack face, per N*mm
    states: tuple[tuple[str, float, float], ...]  # (name, membrane, outer-fibre bending) at WG + rated torque, MPa

    @property
    def half_width_mm(self) -> float:
        return max(HALF_WIDTH_OVER_C * self.c_mm, self.t_mm)

    @property
    def length_mm(self) -> float:
        return max(LENGTH_OVER_T * self.t_mm, 4.0 * self.c_mm)


def block_for(t_mm: float, a_mm: float, a_over_c: float, E_MPa: float, nu: float, per_torque_MPa_per_Nmm: float,
              states) -> Block:
    """The block of a crack of depth a and aspect a/c <= 1 (c along the surface)."""
    if not 0.0 < a_over_c <= 1.0:
        raise InputError("aspect a/c", a_over_c, "the FEA block takes 0 < a/c <= 1 (c along the surface)")
    if not 0.0 < a_mm <= 0.8 * t_mm:
        raise InputError("crack depth a_mm", a_mm, f"must lie in (0, 0.8 t] = (0, {0.8 * t_mm:g}] mm")
    return Block(t_mm, a_mm, a_mm / a_over_c, E_MPa, nu, per_torque_MPa_per_Nmm,
                 tuple((str(n), float(m), float(b)) for n, m, b in states))


def _front_points(s: Block, n: int = 24) -> tuple[tuple[float, float, float], ...]:
    phi = np.linspace(0.0, 0.5 * math.pi, n)
    return tuple((float(s.c_mm * math.cos(p)), float(s.a_mm * math.sin(p)), 0.0) for p in phi)


def _build(model, s: Block, h_mm: float, h_fine_mm: float, mirrored: bool, grading: CrackFrontGrading):
    from strainwave.fea.meshing import extract, generate
    occ = model.occ
    b, t, L = s.half_width_mm, s.t_mm, s.length_mm
    box = occ.addBox(0.0, 0.0, -L if mirrored else 0.0, b, t, 2.0 * L if mirrored else L)
    disk = occ.addDisk(0.0, 0.0, 0.0, s.c_mm, s.a_mm)
    rect = occ.addRectangle(0.0, 0.0, 0.0, b, t)
    quarter, _ = occ.intersect([(2, disk)], [(2, rect)])
    occ.fragment([(3, box)], quarter)
    occ.synchronize()
    tol = 1e-6 * L
    groups = {"crack": [], "ligament": [], "sym_x": [], "far": []}
    for _, tag in model.getEntities(2):
        x0, y0, z0, x1, y1, z1 = model.getBoundingBox(2, tag)
        if abs(z0) < tol and abs(z1) < tol:
            cx, cy, _ = occ.getCenterOfMass(2, tag)
            inside = (cx / s.c_mm) ** 2 + (cy / s.a_mm) ** 2 < 1.0
            groups["crack" if inside else "ligament"].append(tag)
        elif x1 < tol:
            groups["sym_x"].append(tag)
        elif z0 > L - tol or z1 < -L + tol:
            groups["far"].append(tag)
    refine = [grading.refine(_front_points(s), h_mm, h_fine_mm, s.a_mm)]
    generate(model, 3, 2, size_mm=h_mm, refine=refine)
    tags = {name: (2, v) for name, v in groups.items() if v}
    return extract(model, 3, 2, tags, h_mm)


def block_mesh(s: Block, h_mm: float, h_fine_mm: float, *, mirrored: bool = False, grading=None,
               quarter_points: bool = True):
    """MeshData of the quarter block (P2 tets), groups crack / ligament / sym_x / far, quarter-point nodes at the
    front. ``mirrored``: the half block -L <= z <= L with the crack as an internal surface (a seam for
    ``crack_seam.open_crack``), the same grading, mid-side nodes left mid-side: the cross-check of the
    symmetry-plane model."""
    from strainwave.fea.session import mesh_in_child
    md = mesh_in_child(lambda model: _build(model, s, h_mm, h_fine_mm, mirrored, grading or GRADING),
                       what=f"{STUDY} block")
    if mirrored or not quarter_points:
        return md
    return quarter_point(md, np.intersect1d(md.group_nodes("crack"), md.group_nodes("ligament")))


def quarter_point(md, front_nodes: np.ndarray):
    """``md`` with the mid-side node of every edge that has one vertex on the front moved to a quarter of the edge
    from it (Barsoum): the element's map then holds the front's sqrt(r) displacement along that edge."""
    nodes, cells = md.nodes_mm.copy(), md.cells
    on = np.zeros(nodes.shape[0], bool)
    on[np.intersect1d(front_nodes, cells[:, :4])] = True
    moved = np.zeros(nodes.shape[0], bool)
    for j, (i0, i1) in enumerate(TET10_EDGES):
        mid = cells[:, 4 + j]
        for a, b in ((cells[:, i0], cells[:, i1]), (cells[:, i1], cells[:, i0])):
            sel = on[a] & ~on[b] & ~moved[mid]
            nodes[mid[sel]] = 0.75 * md.nodes_mm[a[sel]] + 0.25 * md.nodes_mm[b[sel]]
            moved[mid[sel]] = True
    return dataclasses.replace(md, nodes_mm=nodes)


@dataclass(frozen=True)
class StateSolution:
    delta_flexibility: float    # rad/(N*mm)
    shut_fraction: float        # of the crack face's normal dofs held in contact
    active_set_iterations: int


@dataclass(frozen=True)
class BlockSolution:
    states: dict                # state name -> StateSolution
    dofs: int
    elements: int
    nodes: int
    quality: tuple[float, float]
    solve_s: float
    fields: dict = dataclasses.field(default_factory=dict)   # state -> (MeshData, skfem mesh, u) (``fields_of``)
    closure_ratio: float = math.nan   # -sigma_m/sigma_b at which the crack shuts whole (``closure_ratio``)


def _system(md, s: Block):
    """K, the far-face loads of a unit membrane and a unit outer-fibre bending stress, the held dofs and the
    crack face's normal dofs (off the front: the front's nodes are the ligament's)."""
    from strainwave.fea.assembly import Lame
    from strainwave.fea.mesh_data import group_dofs
    from strainwave.fea.static import assemble
    from strainwave.fea.surface import SurfaceQuadrature
    t = s.t_mm
    sk, K, f_membrane, _, _ = assemble(md, Lame.from_young(s.E_MPa, s.nu), study=STUDY,
                                       tractions={"far": lambda x: np.stack([0 * x[0], 0 * x[0], 1.0 + 0 * x[0]])})
    f_bending = SurfaceQuadrature.of(md, "far").load_vector(
        lambda x: np.stack([0 * x[0], 0 * x[0], 1.0 - 2.0 * x[1] / t]), sk.node_to_dof, 3, K.shape[0])
    lig, crack = group_dofs(sk, md, "ligament"), group_dofs(sk, md, "crack")
    face = np.setdiff1d(crack, lig)
    corner = int(np.argmin(np.linalg.norm(sk.doflocs.T - np.array([0.0, t, 0.0]), axis=1)))
    base = np.unique(np.concatenate([3 * lig + 2, 3 * group_dofs(sk, md, "sym_x"), [3 * corner + 1]]))
    return sk, K, f_membrane, f_bending, base, 3 * face + 2


def _solve(K, f, fixed, sk):
    from strainwave.fea.solver import solve_elasticity
    return solve_elasticity(K, f, fixed_dofs=fixed, fixed_values=0.0, coords=sk.doflocs, dim=3, study=STUDY,
                            method="direct")[0]


def contact_state(system: FaceSystem, f: np.ndarray, r: np.ndarray, start: np.ndarray,
                  u_free: np.ndarray | None = None) -> tuple[np.ndarray, int, np.ndarray]:
    """Active set of the crack face's normal dofs (True = shut) at load ``f`` (condensed on the face: ``r``),
    from ``start``, its iterations and the solution with it held: held where u_z < 0 would interpenetrate the
    mirror face, released where the holding force pulls (K u - f)_z < 0. Each iteration is S's alone (the
    face's u and the held points' forces are S's); the settled set is checked once on the full solution, whose
    round-off bands are the rule's. ``u_free``: the solution with the face free (the bands' first scale)."""
    active = np.asarray(start, bool).copy()
    tol_f = 1e-9 * float(np.abs(f).max())
    # round-off bands: a point at zero gap and zero force stays as it is (no flip-flop between sweeps)
    scale = float(np.abs(u_free if u_free is not None else system.held(f, r, active)).max())
    for it in range(1, MAX_ACTIVE_SET_ITERATIONS + 1):
        u_face, force = _face_state(system, r, active)
        new = _settled(active, u_face, force, 1e-9 * scale, tol_f)
        if np.array_equal(new, active):
            u = u_free if u_free is not None and not active.any() else system.held(f, r, active)
            scale = float(np.abs(u).max())
            new = _settled(active, u[system.face_z], (system.K @ u - f)[system.face_z], 1e-9 * scale, tol_f)
            if np.array_equal(new, active):
                return active, it, u
        active = new
    raise RuntimeError(f"{STUDY}: crack-face active set did not settle in {MAX_ACTIVE_SET_ITERATIONS} iterations")


def _face_state(system: FaceSystem, r: np.ndarray, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The face's normal displacement with ``active`` held and the holding force there (0 off it), from S."""
    from strainwave.fea.solver import tail_solve
    S = system.factor.S
    u_face = tail_solve(S, r, active)
    force = np.zeros(r.shape)
    force[active] = S[active] @ u_face - r[active]
    return u_face, force


def _settled(active, u_face, force, tol, tol_f) -> np.ndarray:
    """The next set: a held point stays while its force holds (>= -tol_f), an open one shuts below -tol."""
    return (active & (force >= -tol_f)) | (~active & (u_face < -tol))


def _state_contact(system: FaceSystem, loads, face_y: np.ndarray, t_mm: float, membrane: float, bending: float):
    """contact_state at (membrane, bending) on the far face, started from the face points the uncracked stress
    presses shut (fewer iterations than from none)."""
    f_m, f_b, r_m, r_b, u0 = loads
    start = membrane + bending * (1.0 - 2.0 * face_y / t_mm) < 0.0
    return contact_state(system, membrane * f_m + bending * f_b, membrane * r_m + bending * r_b, start,
                         u0 @ [membrane, bending])


def closure_ratio(system: FaceSystem, loads, face_y: np.ndarray, t_mm: float, open_c: float) -> float:
    """-sigma_m/sigma_b at which the crack shuts whole under a compressive outer-fibre bending (sigma_b = -1):
    bisection of CLOSURE_BRACKET until the tangent compliance falls below SHUT_SHARE of the open crack's
    (frictionless face contact decides; the midpoint of the last bracket, resolution CLOSURE_BRACKET / 2^steps)."""
    lo, hi = CLOSURE_BRACKET
    r_m = loads[2]
    for _ in range(CLOSURE_STEPS):
        mid = 0.5 * (lo + hi)
        active = _state_contact(system, loads, face_y, t_mm, mid, -1.0)[0]
        shut = open_compliance(system.factor.S, r_m, active) < SHUT_SHARE * open_c
        lo, hi = (mid, hi) if shut else (lo, mid)
    return 0.5 * (lo + hi)


def solve_block(s: Block, h_mm: float, h_fine_mm: float, fields_of: tuple[str, ...] = (), *, grading=None,
                closure: bool = False, quarter_points: bool = True) -> BlockSolution:
    """One mesh: per state the contact set at (wave generator + rated torque), then the tangent compliance
    under the torque's unit membrane with that set held, minus the whole face held (uncracked). ``fields_of``:
    the states whose mesh and displacement are kept for their fields; ``closure``: also the closure ratio;
    ``quarter_points``: False keeps every mid-side node mid-side (the seam cross-check's elements)."""
    t0 = time.perf_counter()
    md = block_mesh(s, h_mm, h_fine_mm, grading=grading, quarter_points=quarter_points)
    sk, K, f_m, f_b, base, face_z = _system(md, s)
    system = FaceSystem.of(K, base, face_z, STUDY)
    try:
        u0 = system.free_solution(np.stack([f_m, f_b], axis=1))
        r_m, r_b = system.condensed(u0).T
        loads, face_y = (f_m, f_b, r_m, r_b, u0), sk.doflocs[1, face_z // 3]
        none = np.zeros(r_m.shape, bool)
        open_c = open_compliance(system.factor.S, r_m, none)
        by_active: dict[bytes, float] = {np.packbits(none).tobytes(): open_c}
        out, fields = {}, {}
        for name, membrane, bending in s.states:
            active, iterations, u = _state_contact(system, loads, face_y, s.t_mm, membrane, bending)
            if name in fields_of:
                fields[name] = (md, sk, u)
            key = np.packbits(active).tobytes()
            if key not in by_active:      # the open crack's compliance does not depend on the state's magnitudes
                by_active[key] = open_compliance(system.factor.S, r_m, active)
            delta = 4.0 * by_active[key] * s.per_torque_MPa_per_Nmm ** 2
            out[name] = StateSolution(delta, float(active.mean()) if active.size else 0.0, iterations)
        rho = closure_ratio(system, loads, face_y, s.t_mm, open_c) if closure else math.nan
    finally:
        system.factor.close()
    q = md.quality
    return BlockSolution(out, K.shape[0], q.elements, q.nodes, (q.min_quality, q.mean_quality),
                         time.perf_counter() - t0, fields, rho)


def default_size_mm(params, quick: bool) -> float:
    """Finest global size t/4, --quick too (it runs one depth on the full run's meshes, so it reaches the
    full run's verdicts)."""
    return params.flexspline_cup.wall_thickness_mm / 4.0


def sweep_depths_mm(params, quick: bool) -> tuple[float, ...]:
    """The crack depths (DEPTHS_OVER_T of the wall, 3 significant digits); --quick: a = 0.2 t."""
    t = params.flexspline_cup.wall_thickness_mm
    return tuple(float(f"{f * t:.3g}") for f in ((DEPTHS_OVER_T[1],) if quick else DEPTHS_OVER_T))


class SurfaceCrack(StudyFacts):
    """The surface crack's facts (its solve is ``run``, not the skeleton: it sweeps its own crack depths)."""

    study = STUDY
    # the deepest crack's block (the estimate's volume) at the default h = t/4: 17,884 tets vs 655 cells (27.3)
    elements_per_cell = 27.3
    # full, --quick: validate's schedule (decision 049); decision 067's checked depth (37.6k tets on its finest mesh):
    # --quick 24.2 CPU s at load 14 (was 5.4 s), full ~ the former 15 s + that difference
    cpu_s_per_element = (1.9e-3, 1.35e-3)
    default_size_mm = staticmethod(default_size_mm)
    rated_load = TORQUE_RATED      # solved at the rated T on top of the wave generator (not linear in T: contact)
    title = "flexspline tooth-root surface crack"
    report_component = "cup"
    stress_field_suffix = "_major"          # the crack wide open: the state whose stress is drawn
    crack_opening_states = FIELDS_STATES
    image_marks = (("sym_x", "ligament"), "far", "sigma_n")
    image_view_from = (1.0, -1.0, -0.8)      # below the crack plane, outside the tooth root: the crack's mouth in view
    outside_design = ("a block of the band wall cut around the crack, loaded by the tooth root's far-field stress: "
                      "its peak is the crack front's, not the cup's; the crack is judged by its compliance checks")
    element_text = ("P{order} tetrahedra graded to the crack front, quarter block of the band wall; the crack face "
                    "in frictionless contact with its mirror (symmetry plane)")

    @classmethod
    def deepest_crack_mm(cls, params) -> float:
        return max(sweep_depths_mm(params, False))

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        """The deepest crack's quarter block, capped by the cup's wall."""
        t = params.flexspline_cup.wall_thickness_mm
        b = block_for(t, cls.deepest_crack_mm(params), ASPECT, 1.0, 0.3, 0.0, ())
        return b.t_mm * b.half_width_mm * b.length_mm, t


def delta_name(state: str, depth_mm: float) -> str:
    return f"delta_flexibility_{state}_a{depth_mm:g}_rad_per_Nmm"


def closure_name(depth_mm: float) -> str:
    return f"closure_ratio_a{depth_mm:g}"


def converge_depth(s: Block, h_fine_mm: float, progress=lambda m: None, fields_of: tuple[str, ...] = (), *,
                   checked: bool = False):
    """({quantity name: Quantity with GCI}, the three solutions, finest first) of one crack depth, every state on
    the same three meshes h, h r, h r^2; ``fields_of``: the finest keeps these states' fields. ``checked``: the
    checked depth, graded by GRADING_CHECKED and with its closure ratio."""
    sizes = [h_fine_mm * DEFAULT_RATIO ** k for k in range(3)]
    grading = GRADING_CHECKED if checked else GRADING
    runs = []
    for k in (2, 1, 0):
        progress(f"{STUDY}: a = {s.a_mm:g} mm, refinement {3 - k}/3 (h = {sizes[k]:.3g} mm)")
        runs.append(solve_block(s, sizes[k], h_fine_mm, fields_of if k == 0 else (), grading=grading, closure=checked))
    runs = runs[::-1]
    q = {}
    for name, _, _ in s.states:
        qn = delta_name(name, s.a_mm)
        q[qn] = converged_quantity(qn, "rad/(N*mm)", sizes, [r.states[name].delta_flexibility for r in runs],
                                   order=CRACK_FORMAL_ORDER)
    if checked:
        # the shut/open decision is the crack's contact: formal order 1 as its compliance (Fs 3 unless confirmed)
        qn = closure_name(s.a_mm)
        q[qn] = converged_quantity(qn, "1", sizes, [r.closure_ratio for r in runs], order=CRACK_FORMAL_ORDER)
    return q, runs


def run(params, *, per_torque_MPa_per_Nmm: float, states, mesh_size_mm=None, order=2, crack_depth_mm=None,
        vtu=None, progress=lambda m: None, quick=False, aspect: float | None = None) -> StudyResult:
    """Every crack depth of the sweep (``sweep_depths_mm``) in every state, each on three meshes.
    ``crack_depth_mm`` must be None: the study sweeps its own depths."""
    if order != 2:
        raise InputError("--order", order, f"study {STUDY} is P2 only")
    if crack_depth_mm is not None:
        raise InputError("--crack-depth-mm", crack_depth_mm, f"study {STUDY} sweeps its own crack depths; leave it out")
    t, m = params.flexspline_cup.wall_thickness_mm, params.material
    h = mesh_size_mm or default_size_mm(params, quick)
    ratio = ASPECT if aspect is None else aspect
    q, facts, t0, finest, fields = {}, {}, time.perf_counter(), None, ()
    for depth in sweep_depths_mm(params, quick):
        block = block_for(t, depth, ratio, m.youngs_modulus_MPa, m.poisson_ratio, per_torque_MPa_per_Nmm, states)
        drawn = vtu is not None and depth == sweep_depths_mm(params, True)[0]     # the checked depth
        checked = depth == sweep_depths_mm(params, True)[0]
        qd, runs = converge_depth(block, h, progress, FIELDS_STATES if drawn else (), checked=checked)
        q |= qd
        fields = _write_fields(vtu, block, runs[0], m) if drawn else fields
        finest = runs[0] if finest is None or runs[0].dofs > finest.dofs else finest
        facts[f"{depth:g}"] = {"depth_mm": depth, "half_length_mm": block.c_mm, "half_width_mm": block.half_width_mm,
                               "length_mm": block.length_mm, "dofs": [r.dofs for r in runs],
                               "grading": dataclasses.asdict(GRADING_CHECKED if checked else GRADING),
                               "solve_s": [r.solve_s for r in runs],
                               "shut_fraction": {n: r.shut_fraction for n, r in runs[0].states.items()},
                               "active_set_iterations": {n: r.active_set_iterations for n, r in runs[0].states.items()}}
    mesh = MeshQuality(finest.elements, finest.nodes, finest.dofs, 2, *finest.quality)
    meta = {"model": "quarter block of the band wall in the crack's frame, P2 tetrahedra graded to the front "
                     "(quarter-point mid-side nodes on the edges from it), "
                     "crack face in frictionless contact with its mirror (symmetry plane z = 0)",
            "aspect_a_over_c": ratio, "wall_mm": t, "states": [list(s) for s in states],
            "per_torque_MPa_per_Nmm": per_torque_MPa_per_Nmm, "cracks": facts}
    load = Load("output torque T at the tooth root's crack face", params.gear.rated_output_torque_Nmm, "N*mm", ("far",),
                f"crack-face normal stress {per_torque_MPa_per_Nmm:.4g} MPa per N*mm (membrane), on top of the wave "
                "generator's membrane + bending at each state's angle", (("aspect_a_over_c", ratio),))
    supports = (Support(("sym_x", "ligament"), "symmetry: u_x = 0 on x = 0, u_z = 0 on the ligament of the crack "
                        "plane, the crack face u_z >= 0 (contact); u_y = 0 at the ligament's bore corner"),)
    return StudyResult(STUDY, q, mesh, load, supports,
                       CrackRecord(sweep_depths_mm(params, True)[0], f"semi-elliptical surface crack, a/c = {ratio:g}, "
                                   "crack face in frictionless contact; the checked depth (its fields), every depth "
                                   "of the sweep in meta.cracks (each on three meshes)"),
                       {"cracks": time.perf_counter() - t0}, fields, {}, meta, (mesh,) * 3)


def field_paths(vtu) -> dict[str, Path]:
    """{state: <stem>_<state>.vtu} next to ``vtu``, one per drawn state (FIELDS_STATES)."""
    v = Path(vtu)
    return {state: v.with_name(f"{v.stem}_{state}.vtu") for state in FIELDS_STATES}


def _write_fields(vtu, block: Block, finest: BlockSolution, material) -> tuple:
    """The finest mesh's fields of each drawn state (wave generator + rated torque): <stem>_<state>.vtu."""
    from strainwave.fea.assembly import Lame
    from strainwave.fea.fields import field_info, write_solid_fields
    written = []
    for state, path in field_paths(vtu).items():
        md, sk, u = finest.fields[state]
        _, membrane, bending = next(st for st in block.states if st[0] == state)
        load = (f"{state} state, wave generator + rated torque: crack-face normal stress {membrane:.4g} MPa membrane "
                f"+ {bending:.4g} MPa outer-fibre bending on the far face (quarter block, a = {block.a_mm:g} mm)")
        info = field_info(STUDY, load, material)
        written.append(write_solid_fields(path, md, sk, u, Lame.from_young(block.E_MPa, block.nu), info,
                                          inset=QUARTER_POINT_INSET))
    return tuple(written)
