"""Checks of the wave generator bearing's inner ring on the elliptical cam (study wg-bearing, issue 34 item 3).

- ``bearing.race_stress_major`` / ``_minor``: the race hoop stress under the cam against the curved-beam form
  (asserted, ``corrected``) with the thin-ring 3 E t w0/(2 r_m^2) beside it (``published``: the issue's form).
- ``bearing.ball_loads``: Z Q_max/F_r with the balls as Hertz springs on the FEA ring against Stribeck's law
  (zero clearance, rigid rings, the exact sum over the Z balls; ``published``: Stribeck's 4.37).
- ``bearing.crack_compliance``: the race crack's added radial compliance at the major axis, where the cam's
  bending holds it open, against the edge-crack weight function integrated by seed 000's eq 4 at the FEA's own
  uncracked hoop stress on the crack line (``corrected``); ``published``: seed 000's K = 1.95 sigma sqrt(a/Q) at
  the FEA's stress at the mouth. Never the FEA's own uncracked compliance.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.analytic import wg_bearing as wgb
from strainwave.analytic.reference import Reference
from strainwave.analytic.study_loads import wg_bearing_load
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, not_evaluated
from strainwave.compare.validate.fea_book import FeaBook, Sweep
from strainwave.compare.validate.torsion_checks import crack_check

STUDY = "wg-bearing"
IDS = ("bearing.race_stress_major", "bearing.race_stress_minor", "bearing.ball_loads", "bearing.crack_compliance")


def _ring(params):
    from strainwave.fea.wg_bearing import setup_from
    return setup_from(params, **wg_bearing_load(params))


def race_stress_reference(params, axis: str, s=None) -> Reference:
    """corrected: curved beam with the membrane force; published: thin ring 3 E t w0/(2 r_m^2)."""
    s = s or _ring(params)
    phi = 0.0 if axis == "major" else 0.5 * math.pi
    E, t, r_m = s.E_MPa, s.thickness_mm, 0.5 * (s.r_bore_mm + s.r_race_mm)
    return Reference(wgb.thin_ring_race_stress_MPa(E, t, r_m, s.w0_mm, phi),
                     wgb.curved_beam_race_stress_MPa(E, s.r_bore_mm, s.r_race_mm, s.w0_mm, phi), "MPa",
                     "analytic.wg_bearing: thin ring (published), curved beam + membrane force (corrected)")


def race_stress_check(book: FeaBook, label: str, params, axis: str) -> Check:
    check_id, name = f"bearing.race_stress_{axis}", f"race_stress_{axis}_MPa"
    s = _ring(params)
    analytic = race_stress_reference(params, axis, s).variants()
    quantity = f"race hoop stress at the {axis} axis, inner ring forced into w0 cos 2phi by the cam"
    q, why = book.quantity(label, name)
    if q is None:
        return not_evaluated(check_id, quantity, "MPa", why, analytic=analytic)
    tol = fea_tolerance(q.value, q.uncertainty, allowances=wgb.race_stress_allowances(s.r_bore_mm, s.r_race_mm))
    note = (f"w0 = {s.w0_mm:g} mm (gear.radial_deformation_mm), ring r = {s.r_bore_mm:g}..{s.r_race_mm:g} mm; "
            "corrected: curved beam (Winkler neutral radius) with the membrane force N = -M/r_m of a ring under "
            "radial cam pressure; published: thin ring 3 E t w0/(2 r_m^2), tension at the major axis")
    return evaluate(Check(check_id, quantity, "MPa", q.value, q.uncertainty, analytic, "corrected", tol, note=note,
                          sources={"fea": f"FEA {label}", "analytic": "analytic.wg_bearing"}))


def ball_load_reference(params) -> Reference:
    """corrected: Z Q_max / F_r, the exact Stribeck sum over the Z balls; published: Stribeck's 4.37."""
    loads = wg_bearing_load(params)
    _, q = wgb.stribeck_ball_loads(loads["force_N"], params.wave_generator.ball_count)
    return Reference(4.37, params.wave_generator.ball_count * float(q.max()) / loads["force_N"], "1", "Stribeck")


def ball_load_check(book: FeaBook, label: str, params) -> Check:
    check_id, unit = "bearing.ball_loads", "1"
    loads = wg_bearing_load(params)
    psi, q = wgb.stribeck_ball_loads(loads["force_N"], params.wave_generator.ball_count)
    Z, F = params.wave_generator.ball_count, loads["force_N"]
    analytic = ball_load_reference(params).variants()
    quantity = f"Z Q_max / F_r, Z = {Z} balls (Hertz Q = K_n delta^1.5) between the FEA ring and a rigid outer race"
    fea, why = book.quantity(label, "ball_load_ratio")
    if fea is None:
        return not_evaluated(check_id, quantity, unit, why, analytic=analytic)
    s = _ring(params)
    g = wgb.ring_local_compliance_mm_per_N(s.E_MPa, s.thickness_mm, s.width_mm, max(s.patch_half_widths_mm))
    allowance = wgb.stribeck_allowance(float(q.max()), loads["hertz_constant"], g)
    tol = fea_tolerance(fea.value, fea.uncertainty, allowances={
        f"the ring's own compliance under a ball ({g:.3g} mm/N, 45 deg spreading, doubled) against the Hertz "
        "ball's, first order": allowance})
    note = ("Stribeck's law Q_i = Q_max cos^1.5 psi_i (zero clearance, rigid rings); corrected = the exact sum "
            f"F_r / sum cos^2.5 psi_i over the Z balls; published = Stribeck's 4.37 (Z -> infinity); F_r = {F:.4g} N")
    return evaluate(Check(check_id, quantity, unit, fea.value, fea.uncertainty, analytic, "corrected", tol,
                          note=note, sources={"fea": f"FEA {label} + Hertz balls", "analytic": "Stribeck"}))


def crack_sweep(book: FeaBook, label: str) -> Sweep | None:
    """The race crack's added compliance at each depth the case solved."""
    from strainwave.fea.wg_bearing import delta_name

    result = book.result(label)
    if result is None:
        return None
    rows = []
    for depth in result.meta.get("crack_depths_mm", []):
        q, _ = book.quantity(label, delta_name(depth))
        if q is not None:
            rows.append((float(depth), q.value, q.uncertainty or 0.0))
    if not rows:
        return None
    d, v, u = zip(*sorted(rows))
    return Sweep("bearing", "delta_radial_compliance_mm_per_N", "mm/N", d, v, u)


def profile_for(cracks: dict, depth: float) -> dict:
    """The solved crack's facts whose uncracked hoop-stress profile covers ``depth``: its own when that depth was
    solved, else the shallowest solved one reaching that deep, else the deepest (np.interp holds its last value
    beyond it). The profile is the uncracked ring's stress on the crack line: any solved depth's serves, as far as
    it reaches. (A depth the sweep did not solve, e.g. the seed's a when a_max = 0.1 t is shallower, asked a
    missing key before issue 49.)"""
    if f"{depth:g}" in cracks:
        return cracks[f"{depth:g}"]
    solved = sorted(cracks.values(), key=lambda f: f["depth_mm"])
    if not solved:
        raise ValueError("no crack depth was solved")
    return next((f for f in solved if max(f["profile_x_mm"]) >= depth), solved[-1])


def crack_curve(params, result):
    """depth -> {corrected: weight function at the FEA's uncracked hoop stress on the crack line,
    published: seed 000's form at the FEA's hoop stress at the mouth}."""
    s = _ring(params)
    cracks = result.meta["cracks"]

    def curve(depth: float) -> dict[str, float]:
        fact = profile_for(cracks, depth)
        x, sig = np.asarray(fact["profile_x_mm"]), np.asarray(fact["hoop_stress_per_N_MPa"])
        return {"corrected": wgb.edge_crack_compliance_mm_per_N(lambda xx: np.interp(xx, x, sig), depth, s.E_MPa,
                                                                 s.width_mm),
                "published": wgb.seed_form_compliance_mm_per_N(float(sig[0]), depth, s.E_MPa, s.width_mm)}
    return curve


# Tada's half-plane weight function is an approximation (1.3 - 0.3 s^(5/4) gives the uniform-stress 1.1215 to
# 0.06 %); on a stress gradient it is taken at 1 % on K, so 2 % on the compliance (K^2) (docs/decisions/060).
WEIGHT_FUNCTION_ALLOWANCE = 0.02
WEIGHT_FUNCTION_REASON = "Tada's half-plane weight function, 1 % on K"


def bearing_crack_check(book: FeaBook, label: str, params, curve=None) -> Check:
    check_id, unit = "bearing.crack_compliance", "mm/N"
    quantity = "added radial compliance of the race crack at the major axis (cam + ball loads, face contact)"
    sweep, result = crack_sweep(book, label), book.result(label)
    if sweep is None or result is None:
        return not_evaluated(check_id, quantity, unit, f"case {label} produced no crack compliance")
    curve = curve or crack_curve(params, result)
    t = params.wave_generator.bearing_inner_ring_thickness_mm
    allowances = lambda a: {f"back face (the cam-held bore) between half-plane and free strip, a/t = {a / t:.3g}":  # noqa: E731
                            wgb.back_face_allowance(a, t), WEIGHT_FUNCTION_REASON: WEIGHT_FUNCTION_ALLOWANCE}
    comp = result.meta.get("compressed_crack", {})
    net = book.quantity(label, "net_race_stress_major_MPa")[0]
    note = (f"crack at the major axis on the race, where the net hoop stress is "
            f"{net.value if net else float('nan'):+.4g} MPa (cam + rated ball loads): open; under the cam reversed "
            f"(w0 -> -w0) the a = {comp.get('depth_mm', float('nan')):g} mm crack closes "
            f"({comp.get('closed_pairs', '?')} of {comp.get('pairs', '?')} face pairs in contact, delta C = "
            f"{comp.get('delta', float('nan')):.2g} mm/N). corrected: Tada's half-plane edge-crack weight function at "
            "the FEA's uncracked hoop stress on the crack line, seed 000 eq 4 with dA = B da; published: seed 000's "
            "1.95 sigma sqrt(a/Q), Q = 1 (straight front), sigma = the FEA's stress at the mouth")
    return crack_check(check_id, quantity, unit, sweep, curve, allowances, note,
                       {"fea": f"FEA {label}", "analytic": "edge-crack weight function (Tada) at the FEA's stress"},
                       params.wave_generator.bearing_crack_depth_mm)


def wg_bearing_checks(book: FeaBook, label: str, params) -> list[Check]:
    return [race_stress_check(book, label, params, "major"), race_stress_check(book, label, params, "minor"),
            ball_load_check(book, label, params), bearing_crack_check(book, label, params)]


def stribeck_radial_stiffness_N_per_mm(params) -> float:
    """K_G of the bearing with rigid rings and cam (closed form): F_r over the outer race's approach
    delta_0 = (Q_max/K_n)^(2/3) under Stribeck's ball loads."""
    loads = wg_bearing_load(params)
    q_max = max(loads["ball_loads_N"])
    return loads["force_N"] / (q_max / loads["hertz_constant"]) ** (2.0 / 3.0)


def gear_stiffness(book: FeaBook, labels: dict[str, str], wg_label: str, s000: dict, params) -> Check:
    """K_HD = 1/(lambda_H + lambda_f0 + lambda_so0), every member from the FEA: lambda_H from the wave generator's
    radial stiffness K_G of study wg-bearing (Hertz balls on the cam-held ring), not the K_G0 back-calculated
    from the seed's table. Corrected: the same sum of closed forms (Stribeck-Hertz K_G with rigid rings, the
    series shell cup, the hollow shaft; G = E/2(1+nu)); published: the seed's K_HD; ``today``: the FEA cup and
    shaft with the seed's K_G0 (what this check asserted before issue 34)."""
    from strainwave.analytic import torsion
    from strainwave.analytic.variant import Variant
    from strainwave.registry import FLEX_UNIT
    from strainwave.analytic.cup_junction import JUNCTION
    from strainwave.compare.validate.torsion_checks import CUP_FLEX, SHAFT_FLEX, cup_model_flexibility, variants

    unit, quantity = "N*mm/rad", "drive torsional stiffness K_HD (uncracked), wave generator from the FEA"
    analytic = {k: v for k, v in variants(s000.get("K_HD")).items() if k == "published"}
    qf, why_f = book.quantity(labels["cup"], CUP_FLEX)
    qs, why_s = book.quantity(labels["shaft"], SHAFT_FLEX)
    qg, why_g = book.quantity(wg_label, "radial_stiffness_N_per_mm")
    if qf is None or qs is None or qg is None:
        return not_evaluated("gear.stiffness", quantity, unit, "; ".join(w for w in (why_f, why_s, why_g) if w),
                             analytic=analytic)
    g, cup, sh = params.gear, params.flexspline_cup, params.output_shaft
    lam = lambda K: torsion.wave_generator_flexibility(g.force_coefficient, K, cup.pitch_diameter_mm,  # noqa: E731
                                                       g.wave_number, g.radial_deformation_mm, g.gear_ratio)
    lam_H, lam_H0, K_cf = lam(qg.value), s000.get("lambda_H0"), stribeck_radial_stiffness_N_per_mm(params)
    total = lam_H + qf.value + qs.value
    K = 1.0 / total
    unc = K * (lam_H * (qg.uncertainty or 0.0) / qg.value + (qf.uncertainty or 0.0) + (qs.uncertainty or 0.0)) / total
    G = params.material.implied_shear_modulus_MPa
    cup_model = cup_model_flexibility(params, G)[0]   # calibrated (cup check)
    shaft_model = torsion.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G,
                                            Variant.CORRECTED)
    analytic = {**analytic, "corrected": 1.0 / (lam(K_cf) + cup_model + shaft_model)}
    if lam_H0 is not None:
        analytic["today_seed_k_g0"] = 1.0 / (lam_H0 + qf.value + qs.value)
    s = _ring(params)
    loads = wg_bearing_load(params)
    ring_g = wgb.ring_local_compliance_mm_per_N(s.E_MPa, s.thickness_mm, s.width_mm, max(s.patch_half_widths_mm))
    ring_share = ring_g * max(loads["ball_loads_N"]) / (max(loads["ball_loads_N"]) / loads["hertz_constant"]) ** (2 / 3)
    allowances = {f"scatter of the cup's junction calibration, on the cup share {100 * qf.value / total:.0f} %":
                  JUNCTION.scatter * qf.value / total,
                  f"the inner ring's compliance under the balls (rigid in the closed form), on the wave generator "
                  f"share {100 * lam_H / total:.0f} %": ring_share * lam_H / total}
    tol = fea_tolerance(K, unc, allowances=allowances)
    note = (f"K_G = {qg.value:.4g} N/mm (FEA {wg_label}: Hertz balls between the cam-held ring and a rigid outer "
            f"race) vs Stribeck-Hertz rigid rings {K_cf:.4g} and the seed's back-calculated K_G0 = "
            f"{params.wave_generator.uncracked_radial_stiffness_N_per_mm:g} N/mm; lambda_H = {lam_H:.4g}, "
            f"lambda_f0 = {qf.value:.5g} (FEA {labels['cup']}), lambda_so0 = {qs.value:.5g} (FEA {labels['shaft']}) "
            f"{FLEX_UNIT}; the cam and the outer ring are rigid in both (their compliance is not in K_G)")
    return evaluate(Check("gear.stiffness", quantity, unit, K, unc, analytic, "corrected", tol, note=note,
                          sources={"lambda_H": f"FEA {wg_label} (K_G)", "lambda_f0": f"FEA {labels['cup']}",
                                   "lambda_so0": f"FEA {labels['shaft']}"}))
