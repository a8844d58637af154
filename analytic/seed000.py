"""Seed 000's whole calculation for a parameter set: published and corrected side by side.

Returns plain JSON-able dicts. Flexibilities in rad/(N*mm), stiffnesses in N*mm/rad
(radial ones in N/mm), displacements in mm.

Choice of the flexspline radius r_m (the seed never gives it): the default is the
mid-wall radius (d1 - delta)/2, consistent with lambda_f0, which treats d1 as the
OUTER diameter of a tube of wall delta; it is also the only value (78.88 mm) for which
the seed's table entry for dlambda_f is matched (by K_uK_d a^2/(pi E r_m^4 delta)).
The pitch radius d1/2 is reported next to it.
"""
from __future__ import annotations

from types import SimpleNamespace

from strainwave.analytic import cracks, torsion
from strainwave.analytic.variant import Variant

P, C = Variant.PUBLISHED, Variant.CORRECTED


def flexspline_radii_mm(params) -> dict:
    """Both readings of r_m for the seed-000 flexspline: mid-wall (chosen) and pitch radius."""
    cup = params.flexspline_cup
    return {"mid_wall": 0.5 * (cup.pitch_diameter_mm - cup.wall_thickness_mm),
            "pitch": 0.5 * cup.pitch_diameter_mm}


def cup_series_model(params, G_MPa: float) -> torsion.CupSeriesFlexibility:
    """strainwave's series shell model of the cup (tube + diaphragm + hub) on the FEA's geometry.

    The hub, diaphragm and band proportions are those of ``strainwave.geometry.flexspline_cup``
    (hub radius HUB_RATIO d1, bore HUB_BORE_RATIO d1, height BOSS_HEIGHT_WALLS delta with the diaphragm
    as its top wall, band BAND_RATIO d1), imported here so the model follows the CAD.
    """
    from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS, HUB_BORE_RATIO, HUB_RATIO

    cup = params.flexspline_cup
    d1, t = cup.pitch_diameter_mm, cup.wall_thickness_mm
    return torsion.cup_series_flexibility(
        d1, t, cup.length_mm, G_MPa, hub_radius_mm=HUB_RATIO * d1, hub_bore_radius_mm=HUB_BORE_RATIO * d1,
        hub_height_mm=BOSS_HEIGHT_WALLS * t, diaphragm_thickness_mm=t, band_length_mm=BAND_RATIO * d1,
        diaphragm_z_mm=(BOSS_HEIGHT_WALLS - 0.5) * t)


def _dlambda_H(params, K_G0: float, delta_K_G: float, variant: Variant):
    """Extra wave-generator flexibility; None where the published K_G0 - dK_G is not positive."""
    g, cup = params.gear, params.flexspline_cup
    K_G = torsion.cracked_radial_stiffness_N_per_mm(K_G0, delta_K_G, variant)
    if K_G <= 0.0:
        return None, K_G
    lam = lambda K: torsion.wave_generator_flexibility(g.force_coefficient, K, cup.pitch_diameter_mm,
                                                      g.wave_number, g.radial_deformation_mm, g.gear_ratio)
    return lam(K_G) - lam(K_G0), K_G


def _seed000_terms(params) -> SimpleNamespace:
    """The seed-000 terms the summary lists, each per Variant where the seed and the correction differ."""
    mat, g, cup, shaft = params.material, params.gear, params.flexspline_cup, params.output_shaft
    wg, cr = params.wave_generator, params.cracks
    E, mu, G_impl = mat.youngs_modulus_MPa, mat.shear_modulus_MPa, mat.implied_shear_modulus_MPa
    # each component's own crack depth (seed 000 uses one a for all three)
    a_shaft, a_cup, a_bearing = shaft.crack_depth_mm, cup.root_crack_depth_mm, wg.bearing_crack_depth_mm
    k_f = torsion.shape_coefficient(cup.shape.value == "bell")
    k_G = torsion.structure_coefficient(cup.cup)
    radii = flexspline_radii_mm(params)
    r_m = radii["mid_wall"]

    lf = {v: torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm, cup.length_mm, mu,
                                            k_f, k_G, v) for v in Variant}
    lf_Enu = torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm, cup.length_mm,
                                            G_impl, k_f, k_G, C)
    series = cup_series_model(params, G_impl)
    lso = {v: torsion.shaft_flexibility(shaft.length_mm, shaft.outer_diameter_mm, shaft.inner_diameter_mm, mu, v)
           for v in Variant}
    lso_Enu = torsion.shaft_flexibility(shaft.length_mm, shaft.outer_diameter_mm, shaft.inner_diameter_mm, G_impl, C)
    lso_table = torsion.shaft_flexibility_table_reconstruction(shaft.length_mm, shaft.outer_diameter_mm,
                                                               shaft.inner_diameter_mm, mu)
    K_G0 = wg.uncracked_radial_stiffness_N_per_mm
    lH0 = torsion.wave_generator_flexibility(g.force_coefficient, K_G0, cup.pitch_diameter_mm, g.wave_number,
                                             g.radial_deformation_mm, g.gear_ratio)
    F_r = torsion.radial_force_N(g.force_coefficient, g.output_torque_Nmm, cup.pitch_diameter_mm)

    bearing = dict(radial_force_N=F_r, ring_thickness_mm=wg.bearing_width_mm, beta=wg.beta,
                   semi_axes_mm=wg.contact_semi_axes_mm, a_mm=a_bearing, E_MPa=E, Q=cr.surface_crack_shape_factor)
    du = {v: cracks.bearing_displacement_mm(variant=v, **bearing) for v in Variant}
    dK = {v: cracks.bearing_crack_stiffness(variant=v, **bearing) for v in Variant}
    dlH = {v: _dlambda_H(params, K_G0, dK[v], v) for v in Variant}

    Ku, Kd = cr.stress_nonuniformity, cr.dynamic_load_factor
    dlf = {v: cracks.flexspline_crack_flexibility(r_m, cup.wall_thickness_mm, Ku, Kd, a_cup, E, v) for v in Variant}
    dlf_pitch = {v: cracks.flexspline_crack_flexibility(radii["pitch"], cup.wall_thickness_mm, Ku, Kd, a_cup, E, v)
                 for v in Variant}
    d_s = shaft.outer_diameter_mm
    dlso = {v: cracks.shaft_crack_flexibility(d_s, a_shaft, mu, v) for v in Variant}

    def totals(v: Variant) -> dict:
        sum0 = torsion.total_flexibility(lH0, lf[v], lso[v])
        extra = dlH[v][0]
        sum1 = None if extra is None else sum0 + extra + dlf[v] + dlso[v]
        sh = torsion.shares(lH0 + (extra or 0.0), lf[v] + dlf[v], lso[v] + dlso[v])
        return {"uncracked": sum0, "cracked": sum1,
                "K_HD_uncracked": torsion.drive_stiffness_Nmm_per_rad(sum0),
                "K_HD_cracked": None if sum1 is None else torsion.drive_stiffness_Nmm_per_rad(sum1),
                "reduction_percent": None if sum1 is None else 100.0 * (1.0 - sum0 / sum1),
                "shares_percent": {"wave_generator": 100 * sh[0], "flexspline": 100 * sh[1],
                                   "output_shaft": 100 * sh[2]}}

    tot = {v: totals(v) for v in Variant}
    tab = torsion.SEED000_TABLE
    tab_shares = torsion.shares(tab["lambda_H0"] + tab["delta_lambda_H"], tab["lambda_f0"] + tab["delta_lambda_f"],
                                tab["lambda_so0"] + tab["delta_lambda_so"])
    return SimpleNamespace(E=E, mu=mu, G_impl=G_impl, a_shaft=a_shaft, k_f=k_f, k_G=k_G, radii=radii, r_m=r_m, lf=lf, lf_Enu=lf_Enu, series=series, lso=lso, lso_Enu=lso_Enu, lso_table=lso_table, K_G0=K_G0, lH0=lH0, F_r=F_r, du=du, dK=dK, dlH=dlH, dlf=dlf, dlf_pitch=dlf_pitch, d_s=d_s, dlso=dlso, tot=tot, tab=tab, tab_shares=tab_shares)


def seed000_summary(params) -> dict:
    """Every seed-000 quantity for ``params`` (the default parameters are the seed's example)."""
    t = _seed000_terms(params)
    E, mu, G_impl, r_m, radii, d_s, tab = t.E, t.mu, t.G_impl, t.r_m, t.radii, t.d_s, t.tab
    lf, lso, du, dK, dlH, dlf, dlf_pitch, dlso, tot = t.lf, t.lso, t.du, t.dK, t.dlH, t.dlf, t.dlf_pitch, t.dlso, t.tot
    k_f, k_G, F_r, lf_Enu, series, lso_Enu, lso_table = t.k_f, t.k_G, t.F_r, t.lf_Enu, t.series, t.lso_Enu, t.lso_table
    K_G0, lH0, a_shaft, tab_shares = t.K_G0, t.lH0, t.a_shaft, t.tab_shares
    mat, shaft = params.material, params.output_shaft
    return {
        "material": {
            "youngs_modulus_MPa": E, "shear_modulus_MPa": mu, "poisson_ratio": mat.poisson_ratio,
            "implied_shear_modulus_MPa": G_impl,
            "note": ("lambda_f0, lambda_so0 and dlambda_so use mu = shear_modulus_MPa (as seed 000); "
                     "dlambda_f and du_H use E (plane stress E' = E); FEA uses E and nu, i.e. G = E/(2(1+nu)); "
                     "the *_E_nu values repeat the corrected formulas with that G for a like-for-like comparison"),
        },
        "r_m_mm": {"chosen": r_m, "choice": "mid-wall (d1 - delta)/2", "pitch_radius": radii["pitch"],
                   "note": "seed gives no r_m; 78.88 (mid-wall) is the only value matching its table dlambda_f"},
        "k_f": k_f, "k_G": k_G,
        "F_r_N": F_r,
        "lambda_f0": lf[P],
        "lambda_f0_variants": {"published": lf[P], "corrected": lf[C], "corrected_E_nu": lf_Enu,
                               "series_shell_E_nu": series.total},
        "lambda_f0_series_shell_parts_E_nu": {
            **series.to_dict(),
            "note": ("strainwave's series shell model (not seed 000): tube L_eff/(G J) + annular diaphragm "
                     "(1/(4 pi G t))(1/r_hub^2 - 1/r_m^2) + hub, G = E/2(1+nu); seed 000's lambda_f0 is the "
                     "tube alone (times k_f k_G) and omits the diaphragm")},
        "lambda_so0": {"published": lso[P], "corrected": lso[C], "corrected_E_nu": lso_Enu,
                       "table_reconstruction": lso_table,
                       "L_s_implied_by_table_mm": torsion.shaft_length_implied_mm(
                           tab["lambda_so0"], d_s, shaft.inner_diameter_mm, mu)},
        "K_G0_N_per_mm": K_G0,
        "lambda_H0": lH0,
        "delta_u_H_mm": {"published": du[P], "corrected": du[C]},
        "delta_K_G": {"published": dK[P], "corrected": dK[C],
                      "units": "published 1/mm (load-dependent), corrected N/mm"},
        "K_G_N_per_mm": {"published": dlH[P][1], "corrected": dlH[C][1]},
        "delta_lambda_H": {"published": dlH[P][0], "corrected": dlH[C][0]},
        "delta_lambda_f": {"published": dlf[P], "corrected": dlf[C],
                           "published_pitch_radius": dlf_pitch[P], "corrected_pitch_radius": dlf_pitch[C]},
        "delta_lambda_so": {"published": dlso[P], "corrected": dlso[C],
                            "corrected_growing_crack": cracks.shaft_crack_flexibility_growing(d_s, a_shaft, mu),
                            "published_mixed_axial_term_per_N": cracks.shaft_mixed_axial_term(d_s, a_shaft, E)},
        "lambda_sum": {"published": tot[P], "corrected": tot[C]},
        "K_HD": {"published": tot[P]["K_HD_uncracked"], "corrected": tot[C]["K_HD_uncracked"],
                 "published_cracked": tot[P]["K_HD_cracked"], "corrected_cracked": tot[C]["K_HD_cracked"],
                 "printed_by_seed": {"uncracked": tab["K_HD0_printed"], "cracked": tab["K_HD_printed"],
                                     "from_table_uncracked": 1.0 / tab["lambda_sum0"],
                                     "from_table_cracked": 1.0 / tab["lambda_sum"],
                                     "slip_factor": torsion.printed_stiffness_slip(tab["lambda_sum0"],
                                                                                   tab["K_HD0_printed"])},
                 "note": "published/corrected = uncracked 1/lambda_sum; *_cracked include the crack terms "
                         "(None where the published K_G0 - dK_G is negative)"},
        "seed_table": {k: (list(v) if isinstance(v, tuple) else v) for k, v in tab.items()},
        "seed_table_shares_percent": [100 * s for s in tab_shares],
    }
