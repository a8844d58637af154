"""Checks of seed 000's torsional model: shaft, cup, bearing ring and the assembled drive stiffness.

What each check asserts (and why):
- ``*.flexibility``: agreement with the CORRECTED closed form within
  the GCI (Fs inside, once) plus the stated modelling allowances (for the cup, "corrected" is strainwave's series shell
  model, tube + diaphragm + hub: seed 000 has no diaphragm term). The published form being off (e.g. the
  solid-shaft formula for a hollow shaft) is the audit's finding, reported with its error, not a failure.
- ``*.crack_compliance``: agreement with the CORRECTED closed form at the sweep depth the FEA resolves
  best (smallest relative GCI; the seed's 0.1 mm crack is usually near the resolution limit, and its
  value is in the sweep table).
- ``gear.stiffness``: in ``wg_bearing_checks`` (issue 34: lambda_H from the FEA's K_G, not the seed's K_G0).
"""
from __future__ import annotations

import math

from strainwave.analytic import cracks, tube_crack
from strainwave.analytic.reference import Reference
from strainwave.analytic.variant import Variant
from strainwave.registry import FLEX_UNIT, study_of_component
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated
from strainwave.compare.validate.fea_book import FeaBook, Sweep

# the uncracked flexibility each torsion study reports (registry)
SHAFT_FLEX, CUP_FLEX = (study_of_component(c).flexibility.name for c in ("shaft", "cup"))


def mu_gap(params) -> tuple[str, float]:
    """The seed's mu against the G the FEA uses (audit 18): a stated allowance, not an error."""
    m = params.material
    gap = abs(m.implied_shear_modulus_MPa / m.shear_modulus_MPa - 1.0)
    return (f"mu = {m.shear_modulus_MPa:g} (closed form) vs E/2(1+nu) = {m.implied_shear_modulus_MPa:.0f} MPa "
            "(FEA), audit 18", gap)


def variants(entry: dict | None) -> dict[str, float]:
    if not isinstance(entry, dict):
        return {}
    return {k: float(entry[k]) for k in ("published", "corrected") if isinstance(entry.get(k), (int, float))}


def _from_quantity(check_id: str, quantity: str, unit: str, book: FeaBook, label: str, name: str,
                   analytic: dict, allowances: dict, note: str, sources: dict) -> Check:
    q, why = book.quantity(label, name)
    if q is None:
        return not_evaluated(check_id, quantity, unit, why, analytic=analytic)
    tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances,
                        basis=gci_basis(q))
    return evaluate(Check(check_id, quantity, unit, q.value, q.uncertainty, analytic, "corrected", tol,
                          note=note, sources=sources))


def shaft_flexibility_reference(params, s000: dict | None = None) -> Reference:
    """published L/(0.1 mu d^4); corrected 32 L/(pi G (d^4 - d_i^4)), G = E/2(1+nu); corrected_mu with the seed's mu."""
    if s000 is None:
        from strainwave.analytic.seed000 import seed000_summary
        s000 = seed000_summary(params)
    lso = s000["lambda_so0"]
    return Reference(lso["published"], lso["corrected_E_nu"], FLEX_UNIT, "seed 000 lambda_so0 (corrected: G = E/2(1+nu))",
                     (("corrected_mu", lso["corrected"]),))


def shaft_flexibility(book: FeaBook, label: str, s000: dict, params) -> Check:
    """The FEA against the closed form of the SAME problem, 32 L/(pi G (d^4 - d_i^4)) with G = E/2(1+nu), within
    its GCI and no allowance (issue 37); the seed's mu (audit 18) is a material gap reported apart, not absorbed."""
    reason, gap = mu_gap(params)
    lso = s000.get("lambda_so0", {})
    analytic = shaft_flexibility_reference(params, s000).variants()
    note = (f"published = L/(0.1 mu d^4), the bore ignored; asserted (corrected) = 32 L/(pi G (d^4 - d_i^4)) with "
            f"G = E/2(1+nu), the problem the FEA solves; material gap apart: {reason}, "
            f"{100 * gap:.2f} %: 32 L/(pi mu (d^4 - d_i^4)) = {lso.get('corrected', float('nan')):.5g} {FLEX_UNIT}")
    return _from_quantity("shaft.flexibility", "output shaft torsional flexibility lambda_so0", FLEX_UNIT, book,
                          label, SHAFT_FLEX, analytic, {}, note,
                          {"fea": f"FEA {label}", "analytic": "seed 000 lambda_so0 (corrected: G = E/2(1+nu))"})


def cup_model_flexibility(params, G_MPa: float) -> tuple[float, float]:
    """(series shell model + the junction compliance, the series model alone) rad/(N mm): the corrected cup
    closed form (``analytic.cup_junction``), also the cup's share of ``gear.stiffness``."""
    from strainwave.analytic.cup_junction import junction_compliance
    from strainwave.analytic.seed000 import cup_series_model
    series = cup_series_model(params, G_MPa).total
    return series + junction_compliance(params, G_MPa), series


def cup_flexibility_reference(params, s000: dict | None = None) -> Reference:
    """corrected: the series shell model + the calibrated junction compliance; published: seed 000's lambda_f0."""
    from strainwave.analytic.seed000 import seed000_summary

    lf = (seed000_summary(params) if s000 is None else s000)["lambda_f0_variants"]
    corrected, series = cup_model_flexibility(params, params.material.implied_shear_modulus_MPa)
    return Reference(lf["published"], corrected, FLEX_UNIT,
                     "published: seed 000 lambda_f0 (k_f, k_G); corrected: strainwave series shell model + junctions",
                     (("series_model", series),))


def cup_flexibility(book: FeaBook, label: str, s000: dict, params) -> Check:
    """Cup flexibility: published = seed 000's lambda_f0 (0.1, k_f k_G), corrected = the series shell model
    (tube + diaphragm + hub, G = E/2(1+nu)) plus the junction compliance calibrated on other cups.

    The seed's lambda_f0 is a bare tube (scaled by k_G = 0.83 for a cup) and omits the diaphragm, whose
    torsional compliance is as large as the tube's. The FEA is the toothless cup's exact (r, z) section.
    """
    from strainwave.analytic.cup_junction import JUNCTION, in_calibrated_range
    from strainwave.analytic.seed000 import cup_series_model

    lf = s000.get("lambda_f0_variants", {})
    G = params.material.implied_shear_modulus_MPa
    series = cup_series_model(params, G)
    corrected, _ = cup_model_flexibility(params, G)
    inside, why = in_calibrated_range(params)
    analytic = cup_flexibility_reference(params, s000).variants()
    note = (f"published = seed 000's lambda_f0 = k_f k_G c_L/(0.1 mu [1-(1-2c_delta)^4] d1^3) with "
            f"k_f = {s000.get('k_f')}, k_G = {s000.get('k_G')}; corrected = strainwave's series shell model "
            f"(tube + diaphragm + hub, G = E/2(1+nu)): tube {series.tube:.4g} + diaphragm {series.diaphragm:.4g} "
            f"+ hub {series.hub:.4g} = {series.total:.5g} {FLEX_UNIT}, plus the junctions' compliance "
            f"{corrected - series.total:.4g} (G d1^3 Delta lambda = {JUNCTION.intercept:.4g} + "
            f"({JUNCTION.slope:.4g}) delta/d1, fitted on {len(_fit_cups())} cups of other proportions, analytic/"
            f"cup_junction.py) = {corrected:.5g}; the seed's lambda_f0 omits the diaphragm; pi/32 tube-only value "
            f"(k_f k_G) = {lf.get('corrected', float('nan')):.5g}, with G = E/2(1+nu) "
            f"{lf.get('corrected_E_nu', float('nan')):.5g} {FLEX_UNIT}"
            + ("" if inside else f"; FLAGGED: the junction calibration is used outside its range ({why})"))
    allowances = {"scatter of the junction calibration over its fit cups (analytic/cup_junction.py)": JUNCTION.scatter}
    return _from_quantity("cup.flexibility", "flexspline cup torsional flexibility lambda_f0", FLEX_UNIT, book,
                          label, CUP_FLEX, analytic, allowances, note,
                          {"fea": f"FEA {label}", "analytic": "published: seed 000 lambda_f0 (k_f, k_G); "
                                                              "corrected: strainwave series shell model + junctions"})


def _fit_cups() -> dict:
    from strainwave.analytic.cup_junction import FIT_CUPS
    return FIT_CUPS


# ---- crack compliances: evaluated at the shallowest resolved depth of the sweep ----

def shaft_crack_curve(params, depth_mm: float) -> Reference:
    """published: seed 000's 512 M_M^2 a^3/(3 mu d_e^6); corrected: the thick-tube form (analytic.tube_crack,
    G = E/2(1+nu) as the FEA); beside them the hollow-tube strip form and the solid-bar a^2 form (mu)."""
    sh, mat = params.output_shaft, params.material
    d_s, mu, G = sh.outer_diameter_mm, mat.shear_modulus_MPa, mat.implied_shear_modulus_MPa
    r_o, r_i = 0.5 * d_s, 0.5 * sh.inner_diameter_mm
    return Reference(cracks.shaft_crack_flexibility(d_s, depth_mm, mu, Variant.PUBLISHED),
                     tube_crack.thick_tube_flexibility(r_o, r_i, depth_mm, G), FLEX_UNIT,
                     "published: seed 000 (solid-bar K_III); corrected: thick-tube form (analytic/tube_crack.py)",
                     (("hollow_tube_strip", tube_crack.hollow_tube_strip_flexibility(r_o, r_i, depth_mm, G)),
                      ("solid_bar_a2", cracks.shaft_crack_flexibility(d_s, depth_mm, mu, Variant.CORRECTED))))


def shaft_form_note(params, depth_mm: float) -> str:
    """How much the thick-tube fit matters at ``depth_mm`` (its factor A^m), and a flag outside its confirmed
    range (analytic.tube_crack.range_note)."""
    sh = params.output_shaft
    r_o, r_i = 0.5 * sh.outer_diameter_mm, 0.5 * sh.inner_diameter_mm
    ratio, a_over_t = r_i / r_o, depth_mm / (r_o - r_i)
    factor = tube_crack.thick_tube_amplification(r_o, r_i, depth_mm) ** tube_crack.THICK_TUBE_EXPONENT
    text = f"at a/t = {a_over_t:.3g} the fitted factor A^m = {factor:.4f}"
    if abs(factor - 1.0) < 0.01:
        text += " (about 1: this depth hardly tests the fit; the sweep's deeper points and tests/test_analytic_tube_crack.py do)"
    outside = tube_crack.range_note(ratio, a_over_t)
    return text + (f"; {outside}" if outside else "; inside the form's confirmed range")


def cup_crack_curve(params, depth_mm: float) -> Reference:
    """The seed's flexspline crack as the FEA solves it: through the wall, half-length a, 45 deg, in the fully
    loaded tube (mid-surface radius r_m = d1/2 - delta/2). Both tips of the through crack give
    a^2/(2 pi E r_m^4 delta) in plane stress and (1 - nu^2) of it in plane strain; the 3D front of a wall lies
    between, so corrected (asserted) is the midpoint, (1 - nu^2/2) x plane stress, and the half spread is the
    check's allowance (``cup_crack_allowances``), the rule of ring.delta_cd_solid. published: seed 000's
    K_u K_d a^2/(2 pi E r_m^4 delta) (plane stress); audit_one_tip: the audit's (K_u K_d)^2 a^2/(4 pi E r_m^4
    delta) (one tip, dA = delta da). K_u = K_d = 1: the FEA load is static and uniform (the seed's 1.2 x 1.1 are
    load factors, audit 17)."""
    cup, E, nu = params.flexspline_cup, params.material.youngs_modulus_MPa, params.material.poisson_ratio
    r_m, wall = 0.5 * (cup.pitch_diameter_mm - cup.wall_thickness_mm), cup.wall_thickness_mm
    plane_stress = cracks.flexspline_through_crack_flexibility(r_m, wall, depth_mm, E, tips=2)
    return Reference(cracks.flexspline_crack_flexibility(r_m, wall, 1.0, 1.0, depth_mm, E, Variant.PUBLISHED),
                     plane_stress * (1.0 - 0.5 * nu ** 2), FLEX_UNIT,
                     "published: seed 000 at K_u = K_d = 1; corrected: both tips of the through crack, midway "
                     "between plane stress and plane strain",
                     (("plane_stress", plane_stress), ("plane_strain", plane_stress * (1.0 - nu ** 2)),
                      ("audit_one_tip",
                       cracks.flexspline_crack_flexibility(r_m, wall, 1.0, 1.0, depth_mm, E, Variant.CORRECTED))))


def cup_crack_allowances(params, depth_mm: float) -> dict[str, float]:
    """Named allowances of the through-crack form, fixed by theory: the 3D front lies between plane stress (E)
    and plane strain (E/(1 - nu^2)); the midpoint is asserted, so half that spread, (nu^2/2)/(1 - nu^2/2), is
    allowed; the wall's curvature (shell parameter lambda = a/sqrt(r_m delta)) bulges the crack by O(lambda^2)."""
    cup, nu = params.flexspline_cup, params.material.poisson_ratio
    r_m = 0.5 * (cup.pitch_diameter_mm - cup.wall_thickness_mm)
    lam2 = depth_mm ** 2 / (r_m * cup.wall_thickness_mm)
    return {f"3D front between plane stress and plane strain, midpoint asserted, half spread "
            f"(nu^2/2)/(1 - nu^2/2), nu = {nu:g}": 0.5 * nu ** 2 / (1.0 - 0.5 * nu ** 2),
            f"shell curvature lambda^2 = a^2/(r_m delta) = {lam2:.2g}": lam2}


def bearing_crack_curve(params, depth_mm: float, radial_force_N: float) -> Reference:
    """delta u_H / F_r in mm/N: the added radial compliance of the cracked ring (seed 000)."""
    wg, cr, E = params.wave_generator, params.cracks, params.material.youngs_modulus_MPa
    du = {v: cracks.bearing_displacement_mm(radial_force_N, wg.bearing_width_mm, wg.beta,
                                            wg.contact_semi_axes_mm, depth_mm, E, cr.surface_crack_shape_factor, v)
          / radial_force_N for v in Variant}
    return Reference(du[Variant.PUBLISHED], du[Variant.CORRECTED], "mm/N", "seed 000 du_H / F_r")


def crack_check(check_id: str, quantity: str, unit: str, sweep: Sweep | None, curve, allowances: dict,
                note: str, sources: dict, default_depth_mm: float, depth_note=None) -> Check:
    """Compare at the sweep depth with the smallest relative FEA uncertainty (see the module docstring).
    ``depth_note(depth) -> str``: what the note adds about the closed form at the depth chosen."""
    if sweep is None:
        return not_evaluated(check_id, quantity, unit, "no cracked case produced the crack compliance",
                             analytic=curve(default_depth_mm))
    resolved = sweep.resolved(3.0)  # the crack effect must stand out of its own GCI band
    if not resolved.any():
        return not_evaluated(check_id, quantity, unit,
                             f"the crack effect is below 3 x its GCI at every depth {list(sweep.depths_mm)} mm",
                             analytic=curve(default_depth_mm))
    # The depth the FEA resolves best: the smallest relative GCI among the resolved depths (deeper cracks
    # change the compliance more, so their difference of two solutions carries less discretization noise).
    rel = [u / v if ok else float("inf") for u, v, ok in zip(sweep.uncertainties, sweep.values, resolved)]
    i = min(range(len(rel)), key=lambda k: (rel[k], sweep.depths_mm[k]))
    depth, value, unc = sweep.depths_mm[i], sweep.values[i], sweep.uncertainties[i]
    if callable(allowances):
        allowances = allowances(depth)
    where = (f"at the seed's a = {depth:g} mm" if math.isclose(depth, default_depth_mm) else
             f"at a = {depth:g} mm, the depth the FEA resolves best (GCI {100 * rel[i]:.2g} %); the seed's "
             f"{default_depth_mm:g} mm is in the sweep table")
    tol = fea_tolerance(value, unc, allowances=allowances)
    if depth_note is not None:
        note += "; " + depth_note(depth)
    return evaluate(Check(check_id, f"{quantity} {where}", unit, value, unc, curve(depth), "corrected", tol,
                          note=note, sources=sources))
