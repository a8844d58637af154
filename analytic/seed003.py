"""Seed 003's whole calculation for a parameter set (EWG flexspline ring, fatigue, tooth number).

Thin-ring values (eqs 1-15) are the seed's model; Roark's thick-ring corrections and
Winkler-Bach curved-beam stresses are reported next to them as a separate named model.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.errors import InputError
from strainwave.analytic import fatigue, ring, thick_ring, tooth_factors, tooth_number
from strainwave.analytic.variant import Variant

P, C = Variant.PUBLISHED, Variant.CORRECTED


def design_from_params(params) -> fatigue.ToothDesign:
    """The eq-14 assumptions taken from ``params.ewg_drive``."""
    e = params.ewg_drive
    return fatigue.ToothDesign(e.tooth_influence, e.stress_concentration, e.mean_stress_influence,
                               e.rim_thickness_ratio, e.dedendum_coefficient)


def tooth_numbers(params, tooth_difference: int) -> dict:
    """Minimal flexspline tooth number by eq 14: root and integer, |sigma_m| and signed sigma_m."""
    e, mat = params.ewg_drive, params.material
    design = design_from_params(params)
    c = fatigue.tooth_offset(design)
    out = {}
    for key, signed in (("abs", False), ("signed", True)):
        try:
            root = fatigue.minimal_teeth_root(tooth_difference, e.permissible_safety, mat.fatigue_limit_MPa,
                                              mat.youngs_modulus_MPa, fatigue.tooth_constant(design, signed), c)
        except ValueError:
            root = None
        out[key] = root
    return out


def tooth_factor_summary(params) -> dict:
    """K_delta, K_sigma and the equivalent rim of ``params``' ring by the fitted model (analytic/tooth_factors.py)."""
    e = params.ewg_drive
    model = tooth_factors.FITTED
    h = tooth_factors.tooth_height_mm(e.module_mm, e.dedendum_coefficient)
    delta = e.rim_thickness_mm
    hd, md = h / delta, e.module_mm / delta
    fitted_on = [(r.teeth, r.delta_over_m) for r in tooth_factors.FITTING_SET]
    held_out = all(not (r.teeth == e.flexspline_teeth and abs(r.delta_over_m - delta / e.module_mm) < 1e-6)
                   for r in tooth_factors.FITTING_SET)
    return {"model": "equivalent rim delta + c h (stiffness), K_delta = 1 + (R - 1) tanh(k m/delta), "
                     "K_delta K_sigma = P0 + a (K_delta - 1)",
            "c": model.c, "k": model.k, "p0": model.p0, "a": model.a,
            "tooth_height_mm": h, "h_over_delta": hd, "m_over_delta": md,
            "equivalent_rim_mm": delta + model.c * h,
            "stiffness_ratio": tooth_factors.stiffness_ratio(hd, model),
            "tooth_influence": tooth_factors.tooth_influence(hd, md, model),
            "stress_concentration": tooth_factors.stress_concentration(hd, md, model),
            "root_product": tooth_factors.root_product(hd, md, model),
            "fit_residuals": tooth_factors.fit_residuals(tooth_factors.FITTING_SET, model),
            "fitted_on_teeth_and_delta_over_m": fitted_on, "held_out": held_out,
            "delta_over_m": 1.0 / md, "range": tooth_factors.range_note(1.0 / md),
            "model_root_fillet_coefficient": tooth_factors.MODEL_ROOT_FILLET_COEFFICIENT,
            "root_fillet_coefficient": e.root_fillet_coefficient}


def tooth_numbers_with_model(params) -> dict:
    """Seed 003's Z_R,min (eq 14) with K_delta(Z_R), K_sigma(Z_R) from the tooth-factor model, dZ = 2 and 4."""
    e, mat = params.ewg_drive, params.material
    design = design_from_params(params)
    out = {}
    for dz in (2, 4):
        try:
            r = tooth_number.minimal_teeth_with_model(dz, e.permissible_safety, mat.fatigue_limit_MPa,
                                                      mat.youngs_modulus_MPa, design)
        except ValueError as exc:
            # Eq 14 has no answer here (no tooth count up to the search limit reaches [n], or [n] is so
            # low that eq 14 has no real root): the design question itself is ill-posed for these
            # parameters, which is the user's to change, not an internal failure.
            raise InputError("ewg_drive.permissible_safety", e.permissible_safety,
                             f"seed 003 eq 14 gives no minimal tooth number with material.fatigue_limit_MPa = "
                             f"{mat.fatigue_limit_MPa:g} and these ring proportions ({exc})") from None
        out[f"dZ{dz}"] = {"Z_R_min": r.Z_R_min, "seed_constant_Z_R_min": r.seed_constant_Z_R_min,
                          "n_sigma": r.n_sigma, "K_delta": r.tooth_influence, "K_sigma": r.stress_concentration,
                          "h_over_delta": r.h_over_delta, "delta_over_m": r.delta_over_m}
    out["assumptions"] = {"rim_thickness_ratio": e.rim_thickness_ratio, "dedendum_coefficient": e.dedendum_coefficient,
                          "root_fillet_coefficient": tooth_factors.MODEL_ROOT_FILLET_COEFFICIENT,
                          "psi_sigma": e.mean_stress_influence, "permissible_safety": e.permissible_safety,
                          "fatigue_limit_MPa": mat.fatigue_limit_MPa, "mean_stress": "|sigma_m| as the seed"}
    return out


def seed003_summary(params) -> dict:
    """Every seed-003 quantity for ``params`` (default parameters: the seed's example, dZ = 2, Z_R = 72)."""
    e, mat = params.ewg_drive, params.material
    E, nu = mat.youngs_modulus_MPa, mat.poisson_ratio
    m, Z_R, dZ = e.module_mm, e.flexspline_teeth, e.tooth_difference
    delta = e.rim_thickness_mm
    r_m = ring.mid_layer_radius_mm(m, Z_R, delta, e.dedendum_coefficient)
    d_m = 2.0 * r_m
    Z_G = fatigue.circular_spline_teeth(Z_R, dZ)
    b = ring.short_semi_axis_mm(m, Z_G, delta, e.dedendum_coefficient)
    I = ring.second_moment_mm4(e.face_width_mm, delta)
    W0 = ring.radial_deformation_from_teeth_mm(m, dZ)
    F = ring.force_for_deformation_N(W0, r_m, E, I)
    K_delta = e.tooth_influence

    s_max = ring.sigma_max_MPa(W0, E, delta, d_m)
    s_min = ring.sigma_min_MPa(W0, E, delta, d_m)
    s_m = fatigue.stress_MPa(fatigue.mean_stress_coefficient(C), K_delta, W0, E, delta, d_m)
    s_a = fatigue.stress_MPa(fatigue.amplitude_coefficient(C), K_delta, W0, E, delta, d_m)
    n_abs = fatigue.normal_safety_factor(mat.fatigue_limit_MPa, e.stress_concentration, s_a,
                                         e.mean_stress_influence, abs(s_m))
    n_signed = fatigue.normal_safety_factor(mat.fatigue_limit_MPa, e.stress_concentration, s_a,
                                            e.mean_stress_influence, s_m)
    design = design_from_params(params)
    offset = fatigue.tooth_offset(design)
    const, const_signed = fatigue.tooth_constant(design), fatigue.tooth_constant(design, True)

    phi_deg = np.arange(0.0, 91.0, 10.0)
    w = ring.radial_displacement_mm(np.radians(phi_deg), F, r_m, E, I)
    return {
        "inputs": {"module_mm": m, "Z_R": Z_R, "tooth_difference": dZ, "Z_G": Z_G, "rim_thickness_mm": delta,
                   "face_width_mm": e.face_width_mm, "youngs_modulus_MPa": E, "K_delta": K_delta,
                   "K_sigma": e.stress_concentration, "psi_sigma": e.mean_stress_influence,
                   "permissible_safety": e.permissible_safety, "fatigue_limit_MPa": mat.fatigue_limit_MPa},
        "geometry": {"r_m_mm": r_m, "d_m_mm": d_m, "d_R_mm": m * Z_R, "d_G_mm": m * Z_G, "b_mm": b,
                     "I_mm4": I, "W0_mm": W0, "W0_from_r_m_minus_b_mm": r_m - b,
                     "rim_over_radius": delta / r_m},
        "coefficients": {
            "delta_CD": ring.delta_cd_coefficient(), "delta_AB": ring.delta_ab_coefficient(),
            "sigma_max": ring.sigma_max_coefficient(), "sigma_min": ring.sigma_min_coefficient(),
            "sigma_m": fatigue.mean_stress_coefficient(C), "sigma_a": fatigue.amplitude_coefficient(C),
            "sigma_m_printed": fatigue.printed_mean_stress_coefficient(),
            "sigma_m_published_literal": fatigue.mean_stress_coefficient(P),
            "sigma_a_published_literal": fatigue.amplitude_coefficient(P),
            "delta_AB_over_delta_CD": ring.delta_ab_coefficient() / ring.delta_cd_coefficient(),
        },
        "force_for_W0_N": F,
        "delta_CD_mm": ring.delta_cd_mm(F, r_m, E, I), "delta_AB_mm": ring.delta_ab_mm(F, r_m, E, I),
        "stresses_MPa": {"sigma_max": s_max, "sigma_min": s_min, "sigma_m": s_m, "sigma_a": s_a,
                         "note": "sigma_max/min: eqs 8, 9 (outer fibre, no K_delta); sigma_m, sigma_a: eqs 10, 11 "
                                 "corrected (half sum, half difference, with K_delta)"},
        "safety": {"n_sigma_abs_mean": n_abs, "n_sigma_signed_mean": n_signed,
                   "n_sigma_eq14": fatigue.safety_from_teeth(Z_R, dZ, mat.fatigue_limit_MPa, E, const, offset),
                   "n_combined": fatigue.combined_safety_factor(n_abs),
                   "permissible": e.permissible_safety, "ok": n_abs >= e.permissible_safety},
        "tooth_number_min": _tooth_number_record(params, const, const_signed, offset),
        "tooth_factors": tooth_factor_summary(params),
        "tooth_number_min_with_fea_factors": tooth_numbers_with_model(params),
        "thick_ring": _thick_ring_record(r_m, delta, e.face_width_mm, W0, E, nu, I),
        "mid_layer": {"phi_from_B_deg": phi_deg.tolist(), "radial_displacement_mm": w.tolist(),
                      "note": "thin ring, not an ellipse; full outline: ring.deformed_mid_layer_mm(W0, r_m)"},
    }


def _thick_ring_record(r_m: float, delta: float, face_width: float, W0: float, E: float, nu: float, I: float) -> dict:
    """A separate model of the same rim: Roark's thick ring and Winkler-Bach's curved-beam stresses."""
    sec = thick_ring.RingSection(r_m, delta, face_width)
    f_thick = thick_ring.thick_ring_factors(sec, nu)
    W_thick = 2.0 * W0 * E * thick_ring.effective_I_mm4(sec, True) / (thick_ring.dv_coefficient(f_thick) * r_m ** 3)
    dv, dh = thick_ring.deflections_mm(W_thick, sec, E, nu, thick=True)
    # Winkler sign: M > 0 puts the outer fibre in tension. D flattens (outer fibre compressed), B bends up.
    M_D = -thick_ring.moment_at_load_Nmm(W_thick, r_m, f_thick)
    M_B = thick_ring.moment_at_free_point_Nmm(W_thick, r_m, f_thick)
    # Hoop force: -W/2 at B, 0 at D (shear carries the load there); seed sign: outer fibre at D compressive.
    wb = {
        "D_outer": thick_ring.winkler_bach_stress_MPa(M_D, 0.0, sec.r_outer_mm, sec),
        "D_inner": thick_ring.winkler_bach_stress_MPa(M_D, 0.0, sec.r_inner_mm, sec),
        "B_outer": thick_ring.winkler_bach_stress_MPa(M_B, -0.5 * W_thick, sec.r_outer_mm, sec),
        "B_inner": thick_ring.winkler_bach_stress_MPa(M_B, -0.5 * W_thick, sec.r_inner_mm, sec),
    }
    inner_f, outer_f = thick_ring.curvature_stress_factors(sec)
    return {
        "model": "Roark Table 9.2 case 1 (thick ring, I -> A e R) + Winkler-Bach",
        "alpha": f_thick.alpha, "beta": f_thick.beta, "k1": f_thick.k1, "k2": f_thick.k2,
        "D_V_coefficient": thick_ring.dv_coefficient(f_thick), "D_H_coefficient": thick_ring.dh_coefficient(f_thick),
        "force_for_W0_N": W_thick, "delta_CD_mm": dv, "delta_AB_mm": dh,
        "compliance_ratio_to_thin": (dv / W_thick) / (ring.delta_cd_mm(1.0, r_m, E, I)),
        "curvature_factor_inner": inner_f, "curvature_factor_outer": outer_f,
        "winkler_bach_stress_MPa": wb,
    }


def _tooth_number_record(params, const: float, const_signed: float, offset: float) -> dict:
    """Seed 003 eq 14's least tooth number, for dZ = 2, 4 and the parameters' own, beside the paper's roots."""
    Z_R, dZ = params.ewg_drive.flexspline_teeth, params.ewg_drive.tooth_difference
    roots = {dz: tooth_numbers(params, dz) for dz in sorted({2, 4, dZ})}
    return {
        "constant": const, "constant_signed_mean": const_signed, "offset": offset,
        "dZ2": roots[2]["abs"], "dZ4": roots[4]["abs"],
        "Z_R_min_dZ2": _ceil(roots[2]["abs"]), "Z_R_min_dZ4": _ceil(roots[4]["abs"]),
        "signed_mean_stress": {"dZ2": roots[2]["signed"], "dZ4": roots[4]["signed"],
                               "Z_R_min_dZ2": _ceil(roots[2]["signed"]),
                               "Z_R_min_dZ4": _ceil(roots[4]["signed"])},
        "for_params": {"tooth_difference": dZ, "root": roots[dZ]["abs"], "Z_R_min": _ceil(roots[dZ]["abs"]),
                       "root_signed_mean": roots[dZ]["signed"], "Z_R_min_signed": _ceil(roots[dZ]["signed"]),
                       "Z_R_given": Z_R},
        "paper_roots": {"dZ2": fatigue.PAPER_ROOTS[2], "dZ4": fatigue.PAPER_ROOTS[4]},
        "paper_implied_constant": {f"dZ{dz}": fatigue.constant_implied_by_root(
            r, dz, fatigue.PAPER_EXAMPLE["permissible_safety"], fatigue.PAPER_EXAMPLE["fatigue_limit_MPa"],
            fatigue.PAPER_EXAMPLE["youngs_modulus_MPa"], fatigue.tooth_offset()) for dz, r in
            fatigue.PAPER_ROOTS.items()},
    }


def _ceil(root):
    return None if root is None else math.ceil(root - 1e-9)
