"""Analytic reference values for each comparison check id (what the FEA is compared with).

Each entry names the public functions behind it, the unit, and the PUBLISHED and
CORRECTED values for ``params``. The comparison stage should read these rather than
re-deriving formulas.
"""
from __future__ import annotations

from strainwave.analytic import bearing_stiffness
from strainwave.analytic.seed000 import seed000_summary
from strainwave.analytic.seed003 import seed003_summary

CHECK_FUNCTIONS = {
    "shaft.flexibility": ("torsion.shaft_flexibility", "torsion.shaft_flexibility_table_reconstruction"),
    "shaft.crack_compliance": ("cracks.shaft_crack_flexibility", "cracks.shaft_crack_flexibility_growing",
                               "cracks.crack_compliance_integral"),
    "cup.flexibility": ("torsion.flexspline_flexibility", "torsion.cup_series_flexibility"),
    "cup.crack_compliance": ("cracks.flexspline_crack_flexibility", "cracks.crack_compliance_integral"),
    "bearing.radial_compliance": ("torsion.wave_generator_flexibility", "torsion.cracked_radial_stiffness_N_per_mm"),
    "bearing.crack_compliance": ("cracks.bearing_displacement_mm", "cracks.bearing_crack_stiffness"),
    "ring.delta_cd": ("ring.delta_cd_mm", "thick_ring.deflections_mm"),
    "ring.delta_ab": ("ring.delta_ab_mm", "thick_ring.deflections_mm"),
    "ring.sigma_max": ("ring.sigma_max_MPa", "thick_ring.winkler_bach_stress_MPa"),
    "ring.sigma_min": ("ring.sigma_min_MPa", "thick_ring.winkler_bach_stress_MPa"),
    "ring.tooth_influence": ("fatigue.stress_MPa", "tooth_factors.tooth_influence"),
    "ring.stress_concentration": ("fatigue.normal_safety_factor", "tooth_factors.stress_concentration"),
    "gear.stiffness": ("torsion.drive_stiffness_Nmm_per_rad", "torsion.total_flexibility"),
}


def bearing_hertz_info(params, K_G0_N_per_mm: float) -> dict:
    """The seed's K_G0 next to the Hertz stiffness of its own contact ellipse (analytic/bearing_stiffness.py)."""
    wg, mat = params.wave_generator, params.material
    a, b = wg.contact_semi_axes_mm
    E, nu = mat.youngs_modulus_MPa, mat.poisson_ratio
    return {"hertz_contact_stiffness_N_per_mm": bearing_stiffness.hertz_contact_stiffness_N_per_mm(a, b, E, nu),
            "ball_pair_stiffness_N_per_mm": bearing_stiffness.ball_pair_stiffness_N_per_mm(a, b, E, nu),
            "implied_ball_pairs": bearing_stiffness.implied_ball_pairs(K_G0_N_per_mm, a, b, E, nu),
            "method": "Hertz elliptical contact (Johnson 1985), tangent stiffness pi a E*/K(e); one ball = two "
                      "contacts in series (Palmgren / Harris ball deflection, load shared by >= 1 ball)"}


def reference_values(params, s000: dict | None = None, s003: dict | None = None) -> dict:
    """{check_id: {unit, published, corrected, functions, note, ...}} for ``params``."""
    s000 = s000 or seed000_summary(params)
    s003 = s003 or seed003_summary(params)
    g, th, st = s003["geometry"], s003["thick_ring"], s003["stresses_MPa"]
    F_r = s000["F_r_N"]
    e = params.ewg_drive
    tf = s003["tooth_factors"]

    def entry(cid, unit, published, corrected, note="", **extra):
        return {"unit": unit, "published": published, "corrected": corrected,
                "functions": list(CHECK_FUNCTIONS[cid]), "note": note, **extra}

    lso, dlso = s000["lambda_so0"], s000["delta_lambda_so"]
    lf = s000["lambda_f0_variants"]
    F = s003["force_for_W0_N"]
    # Every ring reference is evaluated at ONE force, the thin-ring force for W0 (the comparison stage
    # rescales all four linearly to the FEA's force); the thick-ring stresses were computed at the thick
    # force for W0, so they are rescaled to F here.
    wb = {k: v * F / th["force_for_W0_N"] for k, v in th["winkler_bach_stress_MPa"].items()}
    out = {
        "shaft.flexibility": entry("shaft.flexibility", "rad/(N*mm)", lso["published"], lso["corrected"],
                                   "corrected_E_nu uses G = E/(2(1+nu)) like the FEA",
                                   corrected_E_nu=lso["corrected_E_nu"], table_reconstruction=lso["table_reconstruction"]),
        "shaft.crack_compliance": entry("shaft.crack_compliance", "rad/(N*mm)", dlso["published"], dlso["corrected"],
                                        "solid-bar K_III; growing-crack integral alongside",
                                        corrected_growing_crack=dlso["corrected_growing_crack"]),
        "cup.flexibility": entry("cup.flexibility", "rad/(N*mm)", lf["published"], lf["series_shell_E_nu"],
                                 "published: seed lambda_f0 with k_f k_G (0.83 for a cup), a bare tube; corrected: "
                                 "strainwave's series shell model (tube + diaphragm + hub, G = E/2(1+nu)); "
                                 "the seed's formula omits the diaphragm",
                                 tube_only_pi_over_32=lf["corrected"], tube_only_E_nu=lf["corrected_E_nu"]),
        "cup.crack_compliance": entry("cup.crack_compliance", "rad/(N*mm)", s000["delta_lambda_f"]["published"],
                                      s000["delta_lambda_f"]["corrected"], "r_m = mid-wall radius (d1 - delta)/2"),
        "bearing.radial_compliance": entry("bearing.radial_compliance", "mm/N",
                                           1.0 / s000["K_G0_N_per_mm"], 1.0 / s000["K_G0_N_per_mm"],
                                           "information, not a check: K_G0 is an input the seed implies, no model; "
                                           "Hertz stiffness of the seed's own contact ellipse beside it",
                                           **bearing_hertz_info(params, s000["K_G0_N_per_mm"])),
        "bearing.crack_compliance": entry("bearing.crack_compliance", "mm/N",
                                          s000["delta_u_H_mm"]["published"] / F_r, s000["delta_u_H_mm"]["corrected"] / F_r,
                                          "du_H / F_r; published is load-dependent (F_r^2)", F_r_N=F_r),
        "ring.delta_cd": entry("ring.delta_cd", "mm", s003["delta_CD_mm"],
                               th["delta_CD_mm"] * s003["force_for_W0_N"] / th["force_for_W0_N"],
                               "at the thin-ring force F for W0; corrected = Roark thick ring",
                               force_N=s003["force_for_W0_N"], coefficient_published=s003["coefficients"]["delta_CD"],
                               coefficient_corrected=th["D_V_coefficient"]),
        "ring.delta_ab": entry("ring.delta_ab", "mm", s003["delta_AB_mm"],
                               th["delta_AB_mm"] * s003["force_for_W0_N"] / th["force_for_W0_N"],
                               "at the thin-ring force F for W0; corrected = Roark thick ring",
                               force_N=s003["force_for_W0_N"], coefficient_published=s003["coefficients"]["delta_AB"],
                               coefficient_corrected=th["D_H_coefficient"]),
        "ring.sigma_max": entry("ring.sigma_max", "MPa", st["sigma_max"], wb["D_outer"],
                                "outer fibre at the load point at force_N; corrected = Winkler-Bach thick ring",
                                inner_fibre_corrected=wb["D_inner"], force_N=F, W0_mm=g["W0_mm"]),
        "ring.sigma_min": entry("ring.sigma_min", "MPa", st["sigma_min"], wb["B_outer"],
                                "outer fibre at the free point at force_N; corrected = Winkler-Bach thick ring",
                                inner_fibre_corrected=wb["B_inner"], force_N=F, W0_mm=g["W0_mm"]),
        "ring.tooth_influence": entry("ring.tooth_influence", "1", e.tooth_influence, tf["tooth_influence"],
                                      "K_delta: toothed / smooth outer-fibre stress amplitude at equal W0; published = "
                                      "the seed's assumption (1.05..1.10); corrected = equivalent-rim model "
                                      "(analytic/tooth_factors.py) at this rim", seed_range=[1.05, 1.10], **tf),
        "ring.stress_concentration": entry("ring.stress_concentration", "1", e.stress_concentration,
                                           tf["stress_concentration"],
                                           "K_sigma = root-fillet peak / (K_delta x smooth inner fibre), the factor "
                                           "eq 13 applies to sigma_a (which already holds K_delta); published = the "
                                           "seed's assumption (1.8..2.0); corrected = tooth-factor model at this rim "
                                           "and fillet", seed_range=[1.8, 2.0], **tf),
        "gear.stiffness": entry("gear.stiffness", "N*mm/rad", s000["K_HD"]["published"], s000["K_HD"]["corrected"],
                                "uncracked; printed seed value is 1e3 too small",
                                printed_by_seed=s000["K_HD"]["printed_by_seed"]["uncracked"]),
    }
    return out
