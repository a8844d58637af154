"""Every analytic quantity of both seeds for a parameter set, as JSON-able dict or text table.

Called by ``strainwave analytic [--params FILE] [--json]``.
"""
from __future__ import annotations

import math

from strainwave.analytic.audit import audit_as_dicts
from strainwave.analytic.crack_headline import crack_headline
from strainwave.analytic.checks import reference_values
from strainwave.analytic import tooth_factors
from strainwave.analytic.tooth_number import FEA_AT_MINIMUM, supported_minimum
from strainwave.analytic.seed000 import seed000_summary
from strainwave.analytic.seed003 import seed003_summary


def analytic_summary(params) -> dict:
    """{seed000, seed003, checks, audit} for ``params``: plain floats, ints, strings, lists, None."""
    s000 = seed000_summary(params)
    s003 = seed003_summary(params)
    return {
        "units": {"flexibility": "rad/(N*mm)", "stiffness": "N*mm/rad", "length": "mm", "stress": "MPa",
                  "force": "N"},
        "seed000": s000,
        "seed003": s003,
        "crack_headline": crack_headline(params).to_dict(),
        "checks": reference_values(params, s000, s003),
        "audit": audit_as_dicts(params, s000, s003),
        "design": design_summary(params),
    }


def design_summary(params) -> dict:
    """The design factors in closed form (analytic/design_factors.py), the bearing's ratings, the materials and
    Z_R,min by the same Goodman line the validate verdict uses."""
    from strainwave.analytic import design_factors as df

    zmin = {}
    for dz in (2, 4):
        try:
            r = df.minimal_teeth(params, dz)
            zmin[f"dZ{dz}"] = {"Z_R_min": r.Z_R_min, "n": r.n_sigma, "K_delta": r.tooth_influence,
                               "K_sigma": r.stress_concentration}
        except ValueError as exc:
            zmin[f"dZ{dz}"] = {"Z_R_min": None, "reason": str(exc)}
    try:
        ratings = df.bearing_ratings(params)
    except ValueError as exc:   # ISO 281's table ends at D_w/D_pw = 0.4 and D_w = 25.4 mm: outside, no rating
        ratings = {"reason": str(exc)}
    return _finite({"factors": [f.to_dict() for f in df.closed_form_factors(params)], "ratings": ratings,
                    "materials": df.materials_table(params), "Z_R_min_goodman": zmin,
                    "required": params.ewg_drive.permissible_safety, "fit_margin": df.fit_margin(),
                    "buckling": buckling_summary(params)})


def buckling_summary(params) -> dict:
    """The flexspline's torsional buckling in closed form (analytic/cylinder_buckling.py, the check
    cup.buckling_torque's reference), over the rated torque, and the shear yield's torque beside it."""
    from strainwave.analytic.cylinder_buckling import cup_tube, torsional_buckling
    (R, t, L), m = cup_tube(params), params.material
    cb = torsional_buckling(R, t, L, m.youngs_modulus_MPa, m.poisson_ratio)
    rated = params.gear.rated_output_torque_Nmm
    yield_torque = m.yield_strength_MPa / math.sqrt(3.0) * 2.0 * math.pi * R * R * t
    return {**cb.to_dict(), "over_rated": cb.torque_Nmm / rated, "shear_yield_torque_over_rated": yield_torque / rated}


def _finite(value):
    """The JSON form: an infinite factor (no stress demand) becomes None, as an unevaluated one."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def _n3(v) -> str:
    return "inf (no demand)" if v is None else f"{v:.3g}"


def design_lines(d: dict) -> list[str]:
    """The design verdict in closed form: one line per factor, Z_R,min by the same method, the bearing's ratings."""
    z = d["Z_R_min_goodman"]
    out = [f"DESIGN FACTORS (closed form; Goodman n = 1/(K sigma_a/sigma_-1 + sigma_m+/R_m) and static n = "
           f"R_p0.2/(|sigma_m| + K sigma_a), [n] = {d['required']:g}; validate's verdict uses the same line on the FEA)",
           f"  Z_R,min by this line (tooth factors fitted at each Z_R, at [n] x (1 + {d['fit_margin']:.3f}), the fit's "
           "error where the toothed-ring FEA checked it): " + ", ".join(f"dZ = {k[2:]}: {v['Z_R_min']}" for k, v in z.items())]
    for f in d["factors"]:
        out.append(f"  {f['title']}: n = {_n3(f['n'])}, static {_n3(f['static_n'])}, {f['verdict']}; sigma_a = "
                   f"{f['amplitude_MPa']:.4g}, sigma_m = {f['mean_MPa']:.4g} MPa, K = {f['notch_K']:.3g}, {f['material']}"
                   + (f"; advice: {f['advice']}" if f["advice"] else "")
                   + (f"; admissible: {f['admissible']}" if f.get("admissible") else ""))
        if (f.get("extra") or {}).get("governs"):
            out.append(f"    NOT THE VERDICT: {f['extra']['governs']} (validate's design verdict carries it)")
    b = d.get("buckling")
    if b:
        first = (f"; the wall's shear yields first, at {b['shear_yield_torque_over_rated']:.3g} x rated"
                 if b["shear_yield_torque_over_rated"] < b["over_rated"] else "; it buckles before the wall yields")
        out.append(f"  Flexspline torsional buckling (closed form, Batdorf's Galerkin of Donnell's equation, n = "
                   f"{b['n_waves']}, Z = {b['Z']:.4g}; validate's check cup.buckling_torque holds the FE to it): "
                   f"{b['torque_Nmm'] / 1e3:.4g} N m = {b['over_rated']:.3g} x rated" + first)
    r = d["ratings"]
    if "reason" in r:
        return out + [f"  WG bearing ratings: not evaluated ({r['reason']})"]
    out.append(f"  WG bearing: Hertz p0 = {r['p0_max_MPa']:.4g} MPa (most loaded ball, Q = {r['max_ball_load_N']:.4g} N), "
               f"ISO 76 static n = {r['static_contact_n']:.3g}; C_r = {r['C_r_N']:.4g} N, L10 = {r['L10_h']:.4g} h "
               f"(ISO 281, F_r = {r['radial_force_N']:.4g} N)")
    return out


def _fmt(v) -> str:
    if v is None:
        return "n/a"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else f"{v:.6g}"
    return str(v)


_ROWS_000 = [
    ("lambda_f0 (published 0.1)", ("lambda_f0_variants", "published"), ("lambda_f0_variants", "corrected"), "rad/(N mm)"),
    ("lambda_f0 series shell model (strainwave, G = E/2(1+nu))", ("lambda_f0_variants", "series_shell_E_nu"),
     ("lambda_f0_variants", "series_shell_E_nu"), "rad/(N mm)"),
    ("lambda_so0", ("lambda_so0", "published"), ("lambda_so0", "corrected"), "rad/(N mm)"),
    ("lambda_H0", ("lambda_H0",), ("lambda_H0",), "rad/(N mm)"),
    ("du_H", ("delta_u_H_mm", "published"), ("delta_u_H_mm", "corrected"), "mm"),
    ("dK_G", ("delta_K_G", "published"), ("delta_K_G", "corrected"), "1/mm | N/mm"),
    ("K_G", ("K_G_N_per_mm", "published"), ("K_G_N_per_mm", "corrected"), "N/mm"),
    ("dlambda_H", ("delta_lambda_H", "published"), ("delta_lambda_H", "corrected"), "rad/(N mm)"),
    ("dlambda_f", ("delta_lambda_f", "published"), ("delta_lambda_f", "corrected"), "rad/(N mm)"),
    ("dlambda_so", ("delta_lambda_so", "published"), ("delta_lambda_so", "corrected"), "rad/(N mm)"),
    ("lambda_sum uncracked", ("lambda_sum", "published", "uncracked"), ("lambda_sum", "corrected", "uncracked"),
     "rad/(N mm)"),
    ("lambda_sum cracked", ("lambda_sum", "published", "cracked"), ("lambda_sum", "corrected", "cracked"), "rad/(N mm)"),
    ("K_HD uncracked", ("K_HD", "published"), ("K_HD", "corrected"), "N mm/rad"),
    ("K_HD cracked", ("K_HD", "published_cracked"), ("K_HD", "corrected_cracked"), "N mm/rad"),
]


def _get(d: dict, path: tuple):
    for k in path:
        d = d[k]
    return d


def designer_headline(s3: dict) -> list[str]:
    """The opening lines for a designer: seed 003's minimal tooth number with the FEA-fitted tooth factors."""
    zm, tf = s3["tooth_number_min_with_fea_factors"], s3["tooth_factors"]
    a = zm["assumptions"]
    seed_design = (a["rim_thickness_ratio"], a["dedendum_coefficient"], a["psi_sigma"], a["permissible_safety"],
                   a["fatigue_limit_MPa"]) == (0.012, 1.35, 0.12, 1.4, 625.0)
    out = ["SEED 003'S OWN LINE (eq 14, psi_sigma, shown beside the design method above; the fitted tooth factors, "
           "analytic/tooth_factors.py, and the toothed-ring FEA where it was solved)"]
    for dz in (2, 4):
        r = zm[f"dZ{dz}"]
        z, basis = supported_minimum(dz, r["Z_R_min"], a["permissible_safety"], seed_design)
        out.append(f"  dZ = {dz}: Z_R,min = {z} (basis: {basis}; seed's constants K_delta 1.07, K_sigma 1.9: "
                   f"{r['seed_constant_Z_R_min']}); model at Z_R = {r['Z_R_min']}: delta/m = {r['delta_over_m']:.3f}, "
                   f"h/delta = {r['h_over_delta']:.3f}, K_delta = {r['K_delta']:.3f}, K_sigma = {r['K_sigma']:.3f}, "
                   f"n_sigma = {r['n_sigma']:.4f}")
    if seed_design:   # the stored FEA was solved for the seed's design assumptions only
        out.append("  toothed-ring FEA at those rims (analytic/tooth_number.FEA_AT_MINIMUM): " + "; ".join(
        f"Z_R {z}: K_delta {v['tooth_influence']:.3f}, K_sigma {v['stress_concentration']:.3f}, n_sigma "
            f"{v['n_sigma']:.3f} -> Z_R,min {v['Z_R_min_with_these_factors']}" for (z, _), v in FEA_AT_MINIMUM.items()))
    out.append(f"  rim delta = {a['rim_thickness_ratio']:g} d_R, h_f = {a['dedendum_coefficient']:g} m, root fillet "
               f"{a['root_fillet_coefficient']:g} m, psi = {a['psi_sigma']:g}, [n] = {a['permissible_safety']:g}, "
               f"sigma_-1 = {a['fatigue_limit_MPa']:g} MPa, {a['mean_stress']}; factors evaluated at each Z_R "
               f"(h/delta changes with Z_R)")
    out.append(f"  this ring: K_delta = {tf['tooth_influence']:.3f}, K_sigma = {tf['stress_concentration']:.3f} "
               f"(seed 1.07, 1.9); equivalent rim delta + {tf['c']:.3f} h = {tf['equivalent_rim_mm']:.4g} mm")
    out.append("  tooth-factor form's range: " + "; ".join(
        f"Z_R,min rim dZ = {dz}: {tooth_factors.range_note(zm[f'dZ{dz}']['delta_over_m'])}" for dz in (2, 4))
        + f"; this ring: {tf['range']}")
    return out


def crack_headline_lines(h: dict) -> list[str]:
    """Seed 000's headline (analytic/crack_headline.py) from its JSON form."""
    out = [f"DESIGNER HEADLINE (seed 000): cracks of the seed's depth (a = {h['seed_depth_mm']:g} mm) in all three "
           f"components together lower K_HD = {h['K_HD_uncracked_Nmm_per_rad']:.4g} N mm/rad "
           f"({h['K_HD_uncracked_Nmm_per_rad'] / 1e3:.4g} N m/rad) by "
           f"{100 * h['drop_all_three']:.2g} % (seed: {h['seed_claim_percent']:g} %), from the FEA-confirmed crack forms"]
    for c in h["components"]:
        depth = "none" if c["depth_for_target_mm"] is None else f"a = {c['depth_for_target_mm']:.3g} mm"
        out.append(f"  {c['component']}: {c['form']}; a = {c['depth_mm']:g} mm: K_HD -{100 * c['drop_at_seed_depth']:.2g} %; "
                   f"{100 * h['target_drop']:g} % of K_HD costs {depth} ({c['depth_note']})")
    return out


def _catalogue(path: tuple, s0: dict, unit: str) -> str:
    """The corrected value in the catalogue's unit (N m/rad for K_HD), where it has one."""
    from strainwave.catalogue_units import beside
    value = _get(s0, path)
    return beside(value, unit.replace(" ", "*", 1)).replace(" (", "  (corrected: ", 1) \
        if unit == "N mm/rad" and isinstance(value, float) else ""


def format_summary(summary: dict) -> str:
    """Readable text tables: seed 000 (published | corrected), seed 003, audit list."""
    s0, s3 = summary["seed000"], summary["seed003"]
    lines = ["SEED 000: crack effects on torsional stiffness (r_m = %s mm, %s)" % (
        _fmt(s0["r_m_mm"]["chosen"]), s0["r_m_mm"]["choice"]),
        f"{'quantity':<24}{'published':>16}{'corrected':>16}  unit"]
    for name, p, c, unit in _ROWS_000:
        lines.append(f"{name:<24}{_fmt(_get(s0, p)):>16}{_fmt(_get(s0, c)):>16}  {unit}" + _catalogue(c, s0, unit))
    lines.append(f"{'F_r':<24}{_fmt(s0['F_r_N']):>16}{'':>16}  N")
    pr = s0["K_HD"]["printed_by_seed"]
    lines.append(f"seed prints K_HD = {_fmt(pr['uncracked'])} / {_fmt(pr['cracked'])}; 1/lambda_sum of its table = "
                 f"{_fmt(pr['from_table_uncracked'])} (x{pr['slip_factor']:.0f})")
    lines.append("material: " + s0["material"]["note"])

    co, tn, ge, stv = s3["coefficients"], s3["tooth_number_min"], s3["geometry"], s3["stresses_MPa"]
    lines = (design_lines(summary["design"]) + designer_headline(s3) + crack_headline_lines(summary["crack_headline"])
             + [""] + lines)
    lines += ["", "SEED 003: HGD with external wave generator",
              f"Z_R = {s3['inputs']['Z_R']}, dZ = {s3['inputs']['tooth_difference']}, Z_G = {s3['inputs']['Z_G']}, "
              f"r_m = {_fmt(ge['r_m_mm'])} mm, delta = {_fmt(s3['inputs']['rim_thickness_mm'])} mm, "
              f"I = {_fmt(ge['I_mm4'])} mm^4, W0 = {_fmt(ge['W0_mm'])} mm, F(W0) = {_fmt(s3['force_for_W0_N'])} N"]
    for k in ("delta_CD", "delta_AB", "sigma_max", "sigma_min", "sigma_m", "sigma_a",
              "sigma_m_published_literal", "sigma_a_published_literal"):
        lines.append(f"  coefficient {k:<28}{co[k]:>12.6f}")
    for k in ("sigma_max", "sigma_min", "sigma_m", "sigma_a"):
        lines.append(f"  stress {k:<33}{stv[k]:>12.3f} MPa")
    sf = s3["safety"]
    lines.append(f"  n_sigma (seed 003 eq 13, the seed's constants; not the design method) = {sf['n_sigma_abs_mean']:.4f} "
                 f"(|sigma_m|), {sf['n_sigma_signed_mean']:.4f} (signed); [n] = {sf['permissible']}: "
                 f"{'OK' if sf['ok'] else 'NOT OK'} by eq 13")
    lines.append(f"  eq 14: C = {tn['constant']:.6f} (signed {tn['constant_signed_mean']:.6f}), c = {tn['offset']:.6f}")
    sg = tn["signed_mean_stress"]
    lines.append(f"  minimal Z_R roots: dZ=2 {_fmt(tn['dZ2'])} (signed {_fmt(sg['dZ2'])}), "
                 f"dZ=4 {_fmt(tn['dZ4'])} (signed {_fmt(sg['dZ4'])}); paper {tn['paper_roots']['dZ2']} / "
                 f"{tn['paper_roots']['dZ4']} imply C = {tn['paper_implied_constant']['dZ2']:.4f}")
    th = s3["thick_ring"]
    lines.append(f"  thick ring (Roark): D_V coef {th['D_V_coefficient']:.6f}, D_H coef {th['D_H_coefficient']:.6f}, "
                 f"curvature factors inner {th['curvature_factor_inner']:.4f} / outer {th['curvature_factor_outer']:.4f}")
    lines += ["", "AUDIT (id, seed, equation: what is wrong -> effect) [FEA check]"]
    for rec in summary["audit"]:
        lines.append(f"{rec['id']:>3} {rec['seed']} {rec['equation']}: {rec['what_is_wrong']} -> "
                     f"{rec['effect_on_example']} [{rec['fea_check'] or '-'}]")
    return "\n".join(lines)
