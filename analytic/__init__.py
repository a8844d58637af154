"""strainwave.analytic: every closed form of the two seed papers, published and corrected.

Seed 000 (cracks and torsional stiffness of a cup strain wave gear) and seed 003 (HGD with
external wave generator). Pure functions of plain floats; ``Variant.PUBLISHED`` is the
formula as printed, ``Variant.CORRECTED`` the one re-derived in the audit and tested.
Nothing is imported here (no work at import time); import the modules directly.

Modules
-------
variant      Variant enum (PUBLISHED / CORRECTED)
ring         seed 003 eqs 1-9: thin ring under two diametral forces, mid-layer shape
thick_ring   Roark Table 9.2 case 1 thick/thin-ring corrections, Winkler-Bach, numerical Castigliano
fatigue      seed 003 eqs 10-15: sigma_m, sigma_a, safety factors, minimal tooth number
torsion      seed 000: lambda_f0, lambda_so0, lambda_H, K_G, F_r, lambda_sum, K_HD, shares
crack_series seed 000: M_P, M_M series (published and Tada)
cracks       seed 000: eq-4 crack-compliance integral and every crack closed form
seed000, seed003   the seeds' calculations assembled for a Params
audit        the inconsistency list (AuditRecord), effects computed
checks       reference_values(params): analytic value per comparison check id
summary      analytic_summary(params) -> dict, format_summary(dict) -> str  (CLI `strainwave analytic`)

Functions the comparison stage should call per check id
------------------------------------------------------
(or read ``checks.reference_values(params)[check_id]``, which evaluates them)

shaft.flexibility          torsion.shaft_flexibility(L_s, d_s, d_s2, mu, variant)
                           [+ torsion.shaft_flexibility_table_reconstruction]
shaft.crack_compliance     cracks.shaft_crack_flexibility(d_s, a, mu, variant),
                           cracks.shaft_crack_flexibility_growing(d_s, a, mu)
cup.flexibility            torsion.flexspline_flexibility(d1, delta, L, mu, k_f, k_G, variant)
cup.crack_compliance       cracks.flexspline_crack_flexibility(r_m, delta, K_u, K_d, a, E, variant)
bearing.radial_compliance  1/K_G0 (input); torsion.wave_generator_flexibility, torsion.cracked_radial_stiffness_N_per_mm
bearing.crack_compliance   cracks.bearing_displacement_mm(F_r, t_i, beta, (a', b'), a, E, Q, variant) / F_r
ring.delta_cd              ring.delta_cd_mm(F, r_m, E, I)  [corrected: thick_ring.deflections_mm(...)[0]]
ring.delta_ab              ring.delta_ab_mm(F, r_m, E, I)  [corrected: thick_ring.deflections_mm(...)[1]]
ring.sigma_max             ring.sigma_max_MPa(W0, E, delta, d_m)  [corrected: thick_ring.winkler_bach_stress_MPa]
ring.sigma_min             ring.sigma_min_MPa(W0, E, delta, d_m)  [corrected: thick_ring.winkler_bach_stress_MPa]
ring.tooth_influence       fatigue.stress_MPa (K_delta, seed range 1.05..1.10)
ring.stress_concentration  fatigue.normal_safety_factor (K_sigma, seed range 1.8..2.0)
gear.stiffness             torsion.drive_stiffness_Nmm_per_rad(torsion.total_flexibility(...))
"""
