"""Checks ``mesh.flank_hertz`` (peak pressure p0) and ``mesh.flank_hertz_width`` (half-width b): Hertz line contact
at the flank (issue 48, item 3), like against like, where Hertz's assumptions hold.

FE (fea/flank_hertz.py): the design's cup tooth and circular-spline tooth, two plane-strain elastic bodies, pressed
together at the tooth-mesh study's major-axis contact point (the middle of the radial overlap) by a frictionless
contact solve (hat pressures, P2 flexibilities, active set). Three meshes: the contact zone's node spacing b/8.5,
b/12 and b/17 (ratio sqrt 2), the rest graded (0.5 per mm) out to m/4.
Closed form (analytic/hertz_line.py, Johnson sec. 4.2): the two involutes' radii of curvature at the contact,
rho = sqrt(r^2 - r_b^2) = r_b tan(alpha_r) (the spline's concave: R* = 1/(1/rho_f - 1/rho_c)), E* of the pair.

The load, fixed before any result: the line load whose Hertz half-width is 5 % of the smaller of the working flank
(the cup flank inside the spline's tip circle at the major axis, along the involute) and the cup tooth's thickness
at the contact, so the criterion b <= 0.1 x each holds by construction with a factor 2 to spare.

Tolerance = the GCI of the FE reading + three allowances, each computed from the geometry before the comparison:
- the relative curvature's change across the contact (Hertz takes it constant): the exact gap of the two
  involutes fitted by c2 x^2 + c3 x^3 over |x| <= b, 3 |c3| b / c2 (its first-order effect on p0 and b cancels by
  symmetry: taken whole, conservative);
- the finite body: the free tip corners and the held faces at distance d perturb the surface with a field smooth on
  the scale d, a curvature ~ P / (E* d^2) against Hertz's 1/R* = pi E* b^2 / (4 P R*): (b/d)^2;
- the normal's turn across the contact, not followed by the FE's loads (all along the common normal): b / rho_f.

At the rated peak flank load (the tooth-mesh study's) the same FE and Hertz are recorded beside the checks, not
asserted: there Hertz's half-width is about the working flank, outside the theory (records[mesh.flank_hertz]).
"""
from __future__ import annotations

import dataclasses
import functools

import numpy as np

from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, not_evaluated
from strainwave.errors import StageError

__all__ = ["CHECK_P0", "CHECK_B", "TOLERANCE", "reference", "rated_peak_line_load", "B_OVER_FLANK", "CRITERION",
           "MESHES", "closed_form", "allowances",
           "fe_quantities", "hertz_checks", "rated_record"]

CHECK_P0, CHECK_B = "mesh.flank_hertz", "mesh.flank_hertz_width"
B_OVER_FLANK = 0.05            # the validated load: Hertz's half-width over the working flank (and tooth thickness)
CRITERION = 0.1                # Hertz's assumption taken to hold up to this b / flank and b / tooth thickness
MESHES = (17.0, 12.0, 8.5)     # zone nodes per Hertz half-width, finest first (ratio sqrt 2)
GRADE = 0.5                    # the mesh size's growth per mm away from the zone
ZONE_OVER_B = 1.6              # the candidate zone's half-length over b
FAR_OVER_M = 0.25              # the mesh size away from the contact, over the module
RATED_MESHES = (40, 28)        # zone spacings over the working flank at the rated load (a record, two meshes)
STUDY = "tooth-mesh"
TOLERANCE = ("GCI (Roache Fs 1.25 / 3 inside, added once) + the relative curvature's change across the contact + "
             "the finite body (b/d)^2 + the normal's turn b/rho")


def _lame(params):
    from strainwave.fea.assembly import Lame
    m = params.material
    return Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)


def tooth_thickness_mm(pair) -> float:
    from strainwave.geometry.involute import half_angle_rad
    return 2.0 * pair.r_fs_mm * float(half_angle_rad(pair.fs, pair.r_fs_mm))


def closed_form(params, load_N_per_mm: float | None = None):
    """(the flank pair, Hertz at ``load_N_per_mm`` (default: the validated load), the working flank and the
    distance to its nearer end, mm)."""
    from strainwave.analytic.hertz_line import contact_modulus_MPa, line_contact, load_for_half_width
    from strainwave.fea.flank_hertz import flank_pair, working_flank_mm
    pair = flank_pair(params)
    m = params.material
    e_star = contact_modulus_MPa(m.youngs_modulus_MPa, m.poisson_ratio)
    flank, end = working_flank_mm(pair)
    if load_N_per_mm is None:
        b = B_OVER_FLANK * min(flank, tooth_thickness_mm(pair))
        load_N_per_mm = load_for_half_width(b, pair.relative_radius_mm, e_star)
    return pair, line_contact(load_N_per_mm, pair.relative_radius_mm, e_star), flank, end


def reference(params, which: str):
    """The closed form at the validated load: ``which`` "p0" (MPa) or "b" (mm)."""
    from strainwave.analytic.reference import Reference
    _, h, _, _ = closed_form(params)
    value, unit = (h.peak_pressure_MPa, "MPa") if which == "p0" else (h.half_width_mm, "mm")
    return Reference(None, value, unit, f"Hertz line contact (Johnson sec. 4.2) at {h.load_N_per_mm:.4g} N/mm, "
                                        f"R* = {h.relative_radius_mm:.4g} mm (analytic/hertz_line.py)")


def allowances(params) -> dict[str, float]:
    from strainwave.fea.flank_hertz import initial_gap_mm
    pair, h, _, end = closed_form(params)
    b = h.half_width_mm
    x = np.linspace(-b, b, 41)
    c3, c2 = np.linalg.lstsq(np.column_stack([x ** 3, x ** 2]), initial_gap_mm(pair, x), rcond=None)[0]
    d = min(end, pair.r_fs_mm - pair.r_bore_mm, pair.r_held_cs_mm - pair.r_cs_mm)
    return {"the relative curvature's change across the contact (3 |c3| b / c2 of the real gap)": 3 * abs(c3) * b / c2,
            f"the finite body ((b/d)^2, d = {d:.3g} mm to the nearest flank end or held face)": (b / d) ** 2,
            "the normal's turn across the contact, not followed (b / rho_f)": b / pair.rho_fs_mm}


def fe_quantities(params):
    """(p0 and b with their GCI, the three solves) at the validated load (solved once per pair and material in a
    process: validate's builders and the suite's several check lists of one gear share it)."""
    pair, h, _, _ = closed_form(params)
    m = params.material
    return _solved(pair, m.youngs_modulus_MPa, m.poisson_ratio, h.load_N_per_mm, h.half_width_mm)


@functools.lru_cache(maxsize=4)
def _solved(pair, E_MPa: float, nu: float, load_N_per_mm: float, b: float):
    from strainwave.fea.assembly import Lame
    from strainwave.fea.flank_hertz import solve_contact
    from strainwave.fea.refinement import converged_quantity
    lame = Lame.from_young(E_MPa, nu)
    solves = [solve_contact(pair, lame, load_N_per_mm, ZONE_OVER_B * b, b / n, FAR_OVER_M * pair.module_mm, GRADE)
              for n in MESHES[::-1]][::-1]
    if any(s.zone_edge_loaded for s in solves):
        raise StageError("flank contact: the pressure reached the candidate zone's end")
    hs = [s.h_contact_mm for s in solves]
    # the pressure is piecewise linear on P2 bodies: order 2 for both readings (Fs 3 unless the meshes confirm it)
    p0 = converged_quantity("flank_peak_pressure_MPa", "MPa", hs, [s.peak_pressure_MPa for s in solves], order=2.0)
    bq = converged_quantity("flank_half_width_mm", "mm", hs, [s.half_width_mm for s in solves], order=2.0)
    return p0, bq, solves


def _note(params, solves, which: str) -> str:
    pair, h, flank, end = closed_form(params)
    t = tooth_thickness_mm(pair)
    return (f"{which}; plane strain, the cup's tooth (held at its bore) against the circular spline's (held "
            f"{pair.r_held_cs_mm - pair.r_cs_mm:.3g} mm outside the contact), at the study's major-axis contact: r = "
            f"{pair.r_fs_mm:.4g} / {pair.r_cs_mm:.4g} mm, rho = {pair.rho_fs_mm:.4g} / -{pair.rho_cs_mm:.4g} mm, R* = "
            f"{pair.relative_radius_mm:.4g} mm; line load {h.load_N_per_mm:.4g} N/mm: Hertz b = {h.half_width_mm:.4g} mm"
            f" = {h.half_width_mm / flank:.3g} x the working flank ({flank:.3g} mm) and "
            f"{h.half_width_mm / t:.3g} x the tooth thickness ({t:.3g} mm), criterion <= {CRITERION:g}; meshes of "
            f"{', '.join(str(s.dofs) for s in solves)} dofs; FE edge of the loaded hats "
            f"{solves[0].edge_half_width_mm:.4g} mm, contact centre x = {solves[0].centre_mm:.3g} mm (the teeth's tilt "
            f"under load: a linear gap term moves the contact, not p0 or b); FE approach "
            f"{solves[0].approach_mm:.4g} mm (both bodies to their "
            "held faces)")


def _check(cid, quantity, unit, q, ref, params, solves, sources) -> Check:
    tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances(params),
                        basis=q.convergence.basis if q.convergence is not None else "")
    return evaluate(Check(cid, quantity, unit, q.value, q.uncertainty, {"corrected": ref}, "corrected", tol,
                          note=_note(params, solves, quantity), sources=sources))


def hertz_checks(params, solved=None, rated_load_N_per_mm: float | None = None) -> list[Check]:
    """Both checks on ``solved`` = fe_quantities(params) (solved here when None); with the study's rated peak flank
    load, the notes say what Hertz's half-width is there (the FE at that load: ``rated_record``)."""
    try:
        _, h, flank, _ = closed_form(params)
    except ValueError as exc:       # a pair whose flanks conform or separate has no Hertz contact: reported
        return [not_evaluated(cid, cid, "", f"no Hertz line contact for this flank pair: {exc}")
                for cid in (CHECK_P0, CHECK_B)]
    names = ((CHECK_P0, "peak contact pressure of the flank pair at a small line load", "MPa", h.peak_pressure_MPa),
             (CHECK_B, "contact half-width of the flank pair at a small line load", "mm", h.half_width_mm))
    try:
        p0, bq, solves = solved or fe_quantities(params)
    except (StageError, ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
        return [not_evaluated(cid, qn, unit, f"the flank contact FE failed: {exc}", analytic={"corrected": ref})
                for cid, qn, unit, ref in names]
    sources = {"fea": "fea/flank_hertz.py (validate's own three meshes)",
               "analytic": "analytic/hertz_line.py (Johnson, Contact Mechanics, sec. 4.2)"}
    checks = [_check(cid, qn, unit, q, ref, params, solves, sources) for (cid, qn, unit, ref), q in zip(names, (p0, bq))]
    if rated_load_N_per_mm is None:
        return checks
    _, hr, _, _ = closed_form(params, rated_load_N_per_mm)
    more = f"; {rated_statement(rated_load_N_per_mm, hr.half_width_mm, flank)} (the FE there: records[{CHECK_P0}])"
    return [dataclasses.replace(c, note=c.note + more) for c in checks]


def rated_peak_line_load(book, label: str | None, params) -> tuple[float | None, str]:
    """(the tooth-mesh study's largest flank load at rated over its face width, N/mm) or None and why."""
    from strainwave.geometry.mesh_geometry import mesh_geometry
    result = None if label is None or book is None else book.result(label)
    forces = None if result is None else result.meta.get("forces_at_rated_N")
    if not forces:
        return None, f"no {STUDY} case with flank loads at rated"
    return float(max(forces)) / mesh_geometry(params).face_width_mm, ""


def rated_record(params, load_N_per_mm: float | None, why: str = "") -> dict:
    """The FE and Hertz at the rated peak flank load, beside the checks (not asserted): the contact zone is the
    whole working flank; where the pressure reaches its ends the contact spans the flank and Hertz does not hold."""
    if load_N_per_mm is None:
        return {"rated": None, "why": why}
    try:
        pair, h, flank, end = closed_form(params, load_N_per_mm)
    except ValueError as exc:
        return {"rated": None, "why": f"no Hertz line contact for this flank pair: {exc}"}
    try:
        fe = _rated_fe(params, pair, load_N_per_mm, flank, end)
    except (StageError, ValueError, RuntimeError, np.linalg.LinAlgError) as exc:   # reported, not raised
        fe = [{"failed": str(exc)}]
    ratio = h.half_width_mm / flank
    return {"rated": {
        "line_load_N_per_mm": load_N_per_mm, "hertz_half_width_mm": h.half_width_mm,
        "hertz_peak_pressure_MPa": h.peak_pressure_MPa, "working_flank_mm": flank,
        "b_over_flank": ratio, "criterion": CRITERION, "hertz_holds": ratio <= CRITERION, "fe": fe,
        "statement": rated_statement(load_N_per_mm, h.half_width_mm, flank) + _fe_words(fe, h.peak_pressure_MPa)}}


def _fe_words(fe: list[dict], p0_hertz: float) -> str:
    """What the FE shows at rated, in words, from its numbers (fe: finest mesh first)."""
    if not fe or "failed" in fe[0]:
        return f"; the FE failed there: {fe[0]['failed'] if fe else 'no mesh'}"
    peaks = ", ".join(f"{f['peak_pressure_MPa']:.4g} MPa at h = {f['h_contact_mm']:.3g} mm" for f in fe)
    x = fe[0]["peak_at_x_mm"]
    words = (f"; the FE there: peak {peaks} at x = {x:.3g} mm, pressure at the study's contact point "
             f"{fe[0]['centre_pressure_MPa']:.3g} MPa, against Hertz's p0 {p0_hertz:.3g} MPa")
    if fe[0]["zone_ends_loaded"]:
        where = "the cup tooth's tip corner" if x > 0 else "the spline tooth's tip corner"
        words += f": the contact reaches the working flank's end ({where})"
    if len(fe) > 1 and fe[0]["peak_pressure_MPa"] > 1.02 * fe[1]["peak_pressure_MPa"]:
        words += "; its peak grows as the mesh refines (a corner's singularity): no converged value"
    return words


def rated_statement(load_N_per_mm: float, b_mm: float, flank_mm: float) -> str:
    ratio = b_mm / flank_mm
    return (f"at the rated peak flank load ({load_N_per_mm:.4g} N/mm) Hertz's half-width {b_mm:.3g} mm is {ratio:.3g} x "
            f"the working flank ({flank_mm:.3g} mm): "
            + ("inside the criterion" if ratio <= CRITERION else
               f"beyond the criterion {CRITERION:g}, Hertz's assumptions fail there; these checks cover small loads "
               "only"))


def _rated_fe(params, pair, load_N_per_mm: float, flank: float, end: float) -> list[dict]:
    """The contact FE at the rated load on RATED_MESHES, the zone the working flank (its nearer end either side)."""
    from strainwave.fea.flank_hertz import solve_contact
    lame = _lame(params)
    fe = []
    for n in RATED_MESHES:
        k = n // 2                    # the zone ends on the nearer flank end exactly (not beyond a tooth's tip)
        s = solve_contact(pair, lame, load_N_per_mm, end * (1 - 1e-12), end / k, FAR_OVER_M * pair.module_mm, GRADE)
        fe.append({"h_contact_mm": s.h_contact_mm, "peak_pressure_MPa": float(s.pressure_MPa.max()),
                   "centre_pressure_MPa": float(np.interp(0.0, s.x_mm, s.pressure_MPa)),
                   "zone_ends_loaded": s.zone_edge_loaded, "approach_mm": s.approach_mm,
                   "peak_at_x_mm": float(s.x_mm[int(np.argmax(s.pressure_MPa))]),
                   "x_mm": s.x_mm.tolist(), "pressure_MPa": s.pressure_MPa.tolist()})
    return fe
