"""The seeds' inconsistencies as data (the seed formula audit, seed-formula-audit.md, items 1-18, plus 19-21).

Every effect value is computed by calling the formula functions for the given
parameters (the default parameters are the seeds' own examples), not typed in.
``fea_check`` names the comparison check id that can arbitrate the item, or None.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from strainwave.analytic import bearing_stiffness, crack_series, torsion
from strainwave.analytic.seed000 import seed000_summary
from strainwave.analytic.seed003 import seed003_summary
from strainwave.analytic.variant import Variant


@dataclass(frozen=True)
class AuditRecord:
    """One inconsistency of a seed paper."""

    id: int
    seed: str                 # "000" or "003"
    equation: str             # where in the seed
    what_is_wrong: str
    effect_on_example: str    # one line, numbers formatted from effect_values
    effect_values: tuple[tuple[str, float | None], ...]
    fea_check: str | None     # comparison check id that can arbitrate, or None

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["effect_values"] = {k: v for k, v in self.effect_values}
        return d


class _Undefined:
    """Stands in for a value the formulas cannot give for these parameters (e.g. eq 14 has no real root)."""

    def __format__(self, spec: str) -> str:
        return "undefined"


def _rec(id_, seed, eq, wrong, fmt, values: dict, check):
    shown = {k: _Undefined() if v is None else v for k, v in values.items()}
    return AuditRecord(id_, seed, eq, wrong, fmt.format(**shown), tuple(values.items()), check)


def audit_records(params, s000: dict | None = None, s003: dict | None = None) -> tuple[AuditRecord, ...]:
    """All audit records evaluated for ``params`` (pass precomputed seed summaries to avoid recomputing)."""
    s000 = s000 or seed000_summary(params)
    s003 = s003 or seed003_summary(params)
    return (*_seed003_records(s003), *_seed000_crack_records(params, s000), *_seed000_example_records(params, s000))


def _seed003_records(s003: dict) -> list[AuditRecord]:
    co, tn, th = s003["coefficients"], s003["tooth_number_min"], s003["thick_ring"]
    return [
        _rec(1, "003", "eqs 10, 11", "sigma_m and sigma_a printed as sigma_max + sigma_min (no /2, sign dropped); "
             "eq 11 carries the label sigma_m and says 'difference' for half the difference",
             "literal coefficients {lit_m:.4f} / {lit_a:.4f} vs half sum {m:.4f} and half difference {a_:.4f}",
             {"lit_m": co["sigma_m_published_literal"], "lit_a": co["sigma_a_published_literal"],
              "m": co["sigma_m"], "a_": co["sigma_a"]}, "ring.sigma_max"),
        _rec(2, "003", "eq 14", "|sigma_m| used although eq 8-10 make the outer-fibre mean stress compressive",
             "C = {c:.4f} with |sigma_m| vs {cs:.4f} signed; dZ=2 root {r2:.2f} vs {r2s:.2f}",
             {"c": tn["constant"], "cs": tn["constant_signed_mean"], "r2": tn["dZ2"],
              "r2s": tn["signed_mean_stress"]["dZ2"]}, "ring.sigma_min"),
        _rec(3, "003", "eqs 8, 9 text", "stresses taken at the outer fibre, but the teeth (and roots) are internal: "
             "the root sits on the inner fibre where the mean stress is tensile",
             "Winkler-Bach inner/outer curvature factors {fi:.4f} / {fo:.4f}",
             {"fi": th["curvature_factor_inner"], "fo": th["curvature_factor_outer"]}, "ring.stress_concentration"),
        _rec(4, "003", "example", "printed roots 71.2765 / 148.0406 are ~0.13 % high; they fit C = 12.2640",
             "exact roots {r2:.4f} / {r4:.4f}; paper implies C = {cp:.4f}; dZ=4 needs Z_R >= {z4} not > 148",
             {"r2": tn["dZ2"], "r4": tn["dZ4"], "cp": tn["paper_implied_constant"]["dZ2"], "z4": tn["Z_R_min_dZ4"]},
             None),
        _rec(5, "003", "eqs 3-7, Fig. 2", "the deformed mid-layer is not an ellipse: A,B move out by "
             "delta_AB/2 = 0.918 W0, not W0",
             "delta_AB/delta_CD = {q:.5f}", {"q": co["delta_AB_over_delta_CD"]}, "ring.delta_ab"),
    ]


def _seed000_crack_records(params, s000: dict) -> list[AuditRecord]:
    P, C = Variant.PUBLISHED, Variant.CORRECTED
    cr, shaft = params.cracks, params.output_shaft
    a, Ku, Kd = shaft.crack_depth_mm, cr.stress_nonuniformity, cr.dynamic_load_factor
    d_e = shaft.outer_diameter_mm - 2 * a
    return [
        _rec(6, "000", "eq 3", "du = int G/P dA is missing a factor 2 (the expanded form with 2/E' is right)",
             "factor {f:.0f}", {"f": 2.0}, "cup.crack_compliance"),
        _rec(7, "000", "du_H, dK_G", "du_H printed with F_r^2 instead of F_r: dK_G gets units 1/mm and depends on "
             "the load", "du_H published/corrected = {q:.4f} (= F_r * 0.217/0.216717); dK_G {p:.4g} vs {c:.4g}",
             {"q": s000["delta_u_H_mm"]["published"] / s000["delta_u_H_mm"]["corrected"],
              "p": s000["delta_K_G"]["published"], "c": s000["delta_K_G"]["corrected"]}, None),
        _rec(8, "000", "K_G = K_G0 - dK_G", "stiffnesses subtracted; a crack adds compliance in series",
             "published K_G = {p:.4g} N/mm (negative), series K_G = {c:.6g} N/mm",
             {"p": s000["K_G_N_per_mm"]["published"], "c": s000["K_G_N_per_mm"]["corrected"]},
             "bearing.crack_compliance"),
        _rec(9, "000", "dlambda_f", "K_uK_d not squared and 2 pi instead of 4 pi",
             "published/integral = 2/(K_uK_d) = {q:.4f}; {p:.3g} vs {c:.3g} rad/(N mm)",
             {"q": 2.0 / (Ku * Kd), "p": s000["delta_lambda_f"]["published"], "c": s000["delta_lambda_f"]["corrected"]},
             "cup.crack_compliance"),
        _rec(10, "000", "dlambda_so", "penny-crack area dA = 2 pi a da for a circumferential crack (dA = pi d_e da): "
             "scales as a^3 instead of a^2; the mixed M_P term has units 1/N",
             "published/corrected = 4a/(3 d_e) = {q:.4g}; {p:.3g} vs {c:.3g}",
             {"q": 4 * a / (3 * d_e), "p": s000["delta_lambda_so"]["published"],
              "c": s000["delta_lambda_so"]["corrected"]}, "shaft.crack_compliance"),
        _rec(11, "000", "M_P series", "4th term sign and 5th coefficient wrong (Tada F1: -0.1815, +0.3655)",
             "M_P(1) published {p:.4f} vs {c:.4f} (edge crack 1.12)",
             {"p": crack_series.m_p(1.0, P), "c": crack_series.m_p(1.0, C)}, None),
        _rec(12, "000", "lambda_so0", "hollow shaft treated with the solid-bar formula L/(0.1 mu d^4)",
             "published {p:.4g} vs hollow {c:.4g} rad/(N mm)",
             {"p": s000["lambda_so0"]["published"], "c": s000["lambda_so0"]["corrected"]}, "shaft.flexibility"),
    ]


def _seed000_example_records(params, s000: dict) -> list[AuditRecord]:
    P, C = Variant.PUBLISHED, Variant.CORRECTED
    cr, cup, shaft = params.cracks, params.flexspline_cup, params.output_shaft
    Ku, Kd = cr.stress_nonuniformity, cr.dynamic_load_factor
    d_e = shaft.outer_diameter_mm - 2 * shaft.crack_depth_mm
    t = s000["seed_table"]
    lsum_c = s000["lambda_sum"]["corrected"]
    kg0 = torsion.radial_stiffness_implied_N_per_mm(
        t["lambda_H0"], params.gear.force_coefficient, cup.pitch_diameter_mm, params.gear.wave_number,
        params.gear.radial_deformation_mm, params.gear.gear_ratio)
    hertz_args = (*params.wave_generator.contact_semi_axes_mm, params.material.youngs_modulus_MPa,
                  params.material.poisson_ratio)
    table_add = (t["delta_lambda_H"] + t["delta_lambda_f"] + t["delta_lambda_so"]) / t["lambda_sum0"]
    return [
        _rec(13, "000", "example inputs", "K_G0 and r_m not given; the table's lambda_so0 needs L_s = 110 mm, "
             "not the stated 200 mm; the implied K_G0 is softer than one ball's two Hertz contacts at the seed's "
             "own ellipse a' x b' (no model of the seed reaches it: FEA cannot decide, reported as information)",
             "implied L_s = {ls:.2f} mm; implied K_G0 = {kg:.4g} N/mm vs one ball (two Hertz contacts) {kb:.4g} "
             "N/mm = {nb:.3f} ball",
             {"ls": s000["lambda_so0"]["L_s_implied_by_table_mm"], "kg": kg0,
              "kb": bearing_stiffness.ball_pair_stiffness_N_per_mm(*hertz_args),
              "nb": bearing_stiffness.implied_ball_pairs(kg0, *hertz_args)}, None),
        _rec(14, "000", "K_HD", "printed stiffness 1e3 too small", "1/lambda_sum0 / printed = {f:.2f}",
             {"f": s000["K_HD"]["printed_by_seed"]["slip_factor"]}, "gear.stiffness"),
        _rec(15, "000", "shares", "percent shares 28/19/53 do not follow from the table",
             "table gives {h:.2f} / {f:.2f} / {s:.2f} %",
             dict(zip("hfs", s000["seed_table_shares_percent"])), None),
        _rec(16, "000", "table, 1.2 % claim", "crack additions in the table cannot be reproduced; consistent "
             "formulas give ~1e-5 of the total", "table addition {tp:.3f} % vs corrected {cp:.2g} %",
             {"tp": 100 * table_add, "cp": lsum_c["reduction_percent"]}, "shaft.crack_compliance"),
        _rec(17, "000", "dlambda_f, K_I of the ring", "dynamic factor K_d inside a compliance makes stiffness "
             "load-dependent; Hertzian contact stress is compressive; the crack front should be the ring width, "
             "not t_i", "(K_uK_d)^2 = {k:.4f} multiplies dlambda_f", {"k": (Ku * Kd) ** 2}, "bearing.crack_compliance"),
        _rec(18, "000", "material", "E, nu and mu mutually inconsistent: E/(2(1+nu)) differs from mu",
             "E/(2(1+nu)) / mu - 1 = {d:+.3f} %",
             {"d": 100 * (params.material.implied_shear_modulus_MPa / params.material.shear_modulus_MPa - 1)},
             "shaft.flexibility"),
        _rec(19, "000", "lambda_f0, lambda_so0", "polar factor 0.1 instead of pi/32 (approximate)",
             "lambda_f0 {p:.5g} vs {c:.5g} rad/(N mm): {low:.2f} % low",
             {"p": s000["lambda_f0_variants"]["published"], "c": s000["lambda_f0_variants"]["corrected"],
              "low": 100 * (1 - s000["lambda_f0_variants"]["published"] / s000["lambda_f0_variants"]["corrected"])},
             "cup.flexibility"),
        _rec(20, "000", "M_M series", "leading coefficient 0.376 should be 3/8 = 0.375",
             "M_M(d_e/d_s) published {p:.5f} vs {c:.5f}",
             {"p": crack_series.m_m(d_e / shaft.outer_diameter_mm, P),
              "c": crack_series.m_m(d_e / shaft.outer_diameter_mm, C)}, None),
        _rec(21, "000", "dlambda_so closed forms", "d_e and M_M frozen at the final depth inside the integral",
             "growing-crack integral / closed form = {q:.6f}",
             {"q": s000["delta_lambda_so"]["corrected_growing_crack"] / s000["delta_lambda_so"]["corrected"]},
             "shaft.crack_compliance"),
    ]


def audit_as_dicts(params, s000: dict | None = None, s003: dict | None = None) -> list[dict]:
    """JSON-able list of the audit records."""
    return [rec.to_dict() for rec in audit_records(params, s000, s003)]

