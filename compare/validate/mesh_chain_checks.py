"""The drive as it carries torque (issue 48, item 4): the tooth mesh, the flexspline cup and the wave generator
in series, each from the FEA, against Harmonic Drive's catalogue (check ``gear.catalogue_stiffness``).

- Members: the mesh's K3 (study tooth-mesh: the loop's high-torque slope, read by the catalogue's rules), the
  cup's torsional flexibility (cup-torsion), the wave generator's lambda_H from the FEA's radial stiffness K_G
  (wg-bearing, seed 000's form). The output shaft is a member of K_HD but no part of a catalogue unit (the
  catalogue twists the output flange against the circular spline): it is reported, not compared.
- Reference: the CHA table's K3 of the gear's ratio column (``analytic/catalogue.py``: ">50" holds i > 50),
  as the table's own power law in size (least squares of log K3 on log size over every row of that column,
  size = d1 / 2.54 mm), at this gear's size. Beyond the table's sizes the value is extrapolated and says so.
- Tolerance = 3 x the members' propagated GCI + the catalogue's scatter about its own power law (the fit's
  rms residual, in log). K1 of the chain is recorded beside it, not asserted.
- Not in validate's required list: on both shipped gears the chain misses (docs/tooth_mesh.md); it stays a
  comparison that can fail, for the lead to list once the missing compliance is modelled.
"""
from __future__ import annotations

from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, not_evaluated

STUDY = "tooth-mesh"


def catalogue_power_law(params, name: str = "K3_Nm_per_rad") -> tuple[float, float, str, bool]:
    """(value in N mm/rad at this gear's size, rms log residual, column label, extrapolated)."""
    from strainwave.analytic.catalogue_power_law import power_law_at
    v, scatter, label, outside = power_law_at(params, name)
    return 1e3 * v, scatter, label, outside


def chain(book, labels: dict, wg_label: str, mesh_label: str | None, params) -> tuple[dict | None, str]:
    """The series members and the chain's K1/K3 (N mm/rad) with their uncertainty, or None and why."""
    from strainwave.analytic import torsion
    from strainwave.compare.validate.torsion_checks import CUP_FLEX, SHAFT_FLEX
    if mesh_label is None:
        return None, f"no {STUDY} case"
    got = {k: book.quantity(*a) for k, a in {
        "cup": (labels["cup"], CUP_FLEX), "shaft": (labels["shaft"], SHAFT_FLEX),
        "kg": (wg_label, "radial_stiffness_N_per_mm"), "K3": (mesh_label, "K3_Nmm_per_rad"),
        "K1": (mesh_label, "K1_Nmm_per_rad")}.items()}
    why = "; ".join(w for q, w in got.values() if q is None)
    if why:
        return None, why
    q = {k: v[0] for k, v in got.items()}
    g, cup = params.gear, params.flexspline_cup
    lam_H = torsion.wave_generator_flexibility(g.force_coefficient, q["kg"].value, cup.pitch_diameter_mm,
                                               g.wave_number, g.radial_deformation_mm, g.gear_ratio)
    rel = lambda x: (x.uncertainty or 0.0) / abs(x.value)  # noqa: E731
    body = cs_body(params, "face")   # the free bound (decision 070) is a benchmark's, not validate's: 5 CPU-s
    lam_cs, u_cs = body.twist.value, body.twist.convergence.gci_fine
    # decision 073-assembled48: the assembly's wave generator (its lobes as springs K_G) replaces seed 000's
    # lambda_H, and the wall's extra under the teeth's zones (net of the plane rim the study holds) joins the chain
    from strainwave.compare.validate.drive_assembled_checks import assembled
    a, why_a = assembled(book, mesh_label, wg_label, params)
    zone, u_zone, wg_form = 0.0, 0.0, f"seed 000's lambda_H (no assembly: {why_a})"
    if a is not None:
        lam_H, zone, wg_form = a["finest"].lambda_wg_lobes, a["zone"].value, "lobes (decision 073-assembled48)"
        u_zone = abs(a["zone"].uncertainty or 0.0)
    rest = lam_H + q["cup"].value + lam_cs + zone
    out = {"lambda_H_rad_per_Nmm": lam_H, "lambda_cup_rad_per_Nmm": q["cup"].value,
           "lambda_shaft_rad_per_Nmm": q["shaft"].value, "lambda_cs_body_rad_per_Nmm": lam_cs,
           "lambda_zone_rad_per_Nmm": zone, "wave_generator_form": wg_form}
    for k in ("K1", "K3"):
        lam_m = 1.0 / q[k].value
        total = lam_m + rest
        out[f"lambda_mesh_{k}_rad_per_Nmm"] = lam_m
        out[f"{k}_chain_Nmm_per_rad"] = 1.0 / total
        out[f"{k}_chain_rel_unc"] = (lam_m * rel(q[k]) + lam_H * rel(q["kg"]) + q["cup"].value * rel(q["cup"]) + u_zone
                                     + lam_cs * u_cs) / total
        out[f"{k}_with_shaft_Nmm_per_rad"] = 1.0 / (total + q["shaft"].value)
    return out, ""


def cs_body(params, restraint: str):
    """This gear's circular spline body under the two mesh zones (analytic.cs_housing, decision 070): its
    mounting face clamped to a rigid housing ("face", in the chain) or free in its plane ("free", the soft bound)."""
    from strainwave.analytic.cs_housing import body_case_of_params, cs_body_term_of_case
    return cs_body_term_of_case(body_case_of_params(params, restraint))


def gear_line(book, plan, params) -> str:
    """The report's sentence on this gear's chain (teeth in mesh + cup + wave generator, FEA) against the CHA
    power law of its ratio column; a comparison, not a check (the shipped gears are not catalogue designs)."""
    from strainwave.compare.validate.wg_bearing_checks import STUDY as WG
    labels = {c: case.label for c, case in plan.headline.items()}
    c, why = chain(book, labels, plan.label_of(WG) or "", plan.label_of(STUDY), params)
    ref, scatter, label, extrapolated = catalogue_power_law(params)
    size = params.flexspline_cup.pitch_diameter_mm / 2.54
    if c is None:
        return f"This gear's drive with the teeth in mesh: not evaluated ({why})."
    K, u = c["K3_chain_Nmm_per_rad"], c["K3_chain_rel_unc"]
    return (f"This gear's drive with the teeth in mesh (FEA tooth-mesh K3 + cup + wave generator + circular spline "
            f"body in series, the "
            f"output shaft left out as in a catalogue unit): K3 = {1e-3 * K:.4g} N m/rad (+-{100 * u:.2g} %), "
            f"K1 = {1e-3 * c['K1_chain_Nmm_per_rad']:.4g} (+-{100 * c['K1_chain_rel_unc']:.2g} %; the mesh's K1 "
            f"with the backlash's dead band taken out, decision 073); the CHA column {label}'s power law at size "
            f"{size:.3g}"
            f"{' (extrapolated beyond sizes 14-58)' if extrapolated else ''}: K3 {1e-3 * ref:.4g} N m/rad "
            f"(scatter +-{100 * scatter:.2g} %), predicted / catalogue {K / ref:.2f}. Members (rad/(N mm)): mesh "
            f"{c['lambda_mesh_K3_rad_per_Nmm']:.3g}, cup {c['lambda_cup_rad_per_Nmm']:.3g}, the cup's wall under the "
            f"teeth's zones {c['lambda_zone_rad_per_Nmm']:.3g}, wave generator {c['lambda_H_rad_per_Nmm']:.3g} "
            f"({c['wave_generator_form']}), circular spline body with its face clamped "
            f"{c['lambda_cs_body_rad_per_Nmm']:.3g} (free in its plane it would be 20-45x that: decision 070). "
            f"This gear is not a catalogue design (its cup and teeth follow "
            f"the seeds); the catalogue's own design rules are compared row by row with "
            f"`strainwave catalogue TABLE.csv` (docs/tooth_mesh.md).")


def catalogue_check(book, labels: dict, wg_label: str, mesh_label: str | None, params) -> Check:
    cid, quantity, unit = "gear.catalogue_stiffness", "drive K3: tooth mesh + cup + wave generator in series", \
        "N*mm/rad"
    ref, scatter, label, extrapolated = catalogue_power_law(params)
    analytic = {"corrected": ref}
    c, why = chain(book, labels, wg_label, mesh_label, params)
    if c is None:
        return not_evaluated(cid, quantity, unit, why, analytic=analytic)
    K = c["K3_chain_Nmm_per_rad"]
    tol = fea_tolerance(K, c["K3_chain_rel_unc"] * K, allowances={
        f"the CHA table's scatter about its power law in size (rms, column {label})": scatter})
    note = (f"CHA column {label}, K3 at size {params.flexspline_cup.pitch_diameter_mm / 2.54:.3g}"
            f"{' (EXTRAPOLATED beyond sizes 14-58)' if extrapolated else ''}; members (rad/(N mm)): mesh "
            f"{c['lambda_mesh_K3_rad_per_Nmm']:.3g}, cup {c['lambda_cup_rad_per_Nmm']:.3g}, wall's zones "
            f"{c['lambda_zone_rad_per_Nmm']:.3g}, WG {c['lambda_H_rad_per_Nmm']:.3g} ({c['wave_generator_form']}), "
            f"CS body (face clamped) {c['lambda_cs_body_rad_per_Nmm']:.3g}; shaft "
            f"{c['lambda_shaft_rad_per_Nmm']:.3g} (not in a catalogue unit); "
            f"chain K1 {c['K1_chain_Nmm_per_rad']:.3g} N mm/rad beside catalogue K1 "
            f"{catalogue_power_law(params, 'K1_Nm_per_rad')[0]:.3g} (recorded, not asserted; "
            f"the study's K1 with the backlash's dead band taken out, decision 073)")
    return evaluate(Check(cid, quantity, unit, K, c["K3_chain_rel_unc"] * K, analytic, "corrected", tol, note=note,
                          sources={"fea": "FEA tooth-mesh + cup-torsion + wg-bearing", "analytic": "CHA table"}))
