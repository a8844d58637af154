"""What both reports say, as plain rows: the Markdown and HTML writers only lay these out.

Everything is read from the results document (the dict written to results.json), so the reports can
never show a number the JSON does not have.
"""
from __future__ import annotations

from strainwave.catalogue_units import beside
from strainwave.compare.validate.gci_table import GCI_COLUMNS, gci_cells  # noqa: F401 - the GCI table's layout, for both writers



def components() -> tuple[tuple[str, str], ...]:
    """(component, title) of the report's sections, from the check list (``check_list.sections``)."""
    from strainwave.compare.validate.check_list import sections
    return sections()

CHECK_COLUMNS = ("check", "quantity", "FEA +/- U", "published (err)", "corrected (err)", "tolerance", "verdict",
                 "result")


def num(value, digits: int = 5) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, str)):   # a count, or a cached record's text as it was written
        return str(value)
    return f"{value:.{digits}g}"


def pct(value) -> str:
    return "n/a" if value is None else f"{100 * value:+.3g} %"


def headline(doc: dict) -> str:
    s = doc["summary"]
    verdict = "PASS" if doc["passed"] else "FAIL"
    text = f"{verdict}: {s['passed']} of {s['checks']} checks pass"
    contradicted = [c for c in s["failed"] if c not in s["not_evaluated"]]
    if contradicted:
        text += f"; FEA contradicts the asserted form in: {', '.join(contradicted)}"
    if s["not_evaluated"]:
        text += f"; not evaluated (counted as failed): {', '.join(s['not_evaluated'])}"
    return text


VALIDATION_QUESTION = "Validation: do the closed forms hold?"
DESIGN_QUESTION = "Design: does this drive meet [n] at the rated load?"


def design_headline(doc: dict) -> str:
    design = doc.get("design")
    return design["headline"] if design else "not evaluated (no stress field at the rated load)"


def design_passed(doc: dict) -> bool:
    return bool(doc.get("design") and doc["design"]["passed"])


# what a factor's band is, and why some have none
DESIGN_BAND_NOTE = ("A band is the factor's range over its stresses' GCI bands: one that straddles [n] is UNDECIDED and "
                    "counted as not met. A factor without a band is read on the finest mesh's stress field alone, "
                    "whose peak carries no GCI.")
DESIGN_COLUMNS = ("component", "safety factor n (band over the GCIs)", "[n]", "stress (MPa)", "limit (MPa)", "result", "load",
                  "definition")


def design_row(f: dict) -> tuple[str, ...]:
    result = f.get("verdict") or ("PASS" if f["passed"] else ("NOT EVALUATED" if f["safety_factor"] is None else "FAIL"))
    band = f.get("band")
    factor = num(f["safety_factor"], 3) + (f" ({band[0]:.3g}..{band[1]:.3g})" if band else "")
    fat = f.get("fatigue") or {}
    extra = "".join([f"; static n = {fat['static_n']:.3g} (R_p0.2)" if fat.get("static_n") is not None else "",
                     f"; advice: {fat['advice']}" if fat.get("advice") else "",
                     f"; admissible: {fat['admissible']}" if fat.get("admissible") else "",
                     _closed_form_beside(fat)])
    return (f["title"], factor, num(f["required"], 3), num(f["stress_MPa"], 4),
            num(f["limit_MPa"], 4), result, f["load"] or "-", f["definition"] + extra + (f"; {f['reason']}" if f["reason"]
                                                                                          else ""))


def _closed_form_beside(fat: dict) -> str:
    """The closed form's factor of the same point beside the FEA's, and which governs (the cup's tooth root)."""
    extra = fat.get("extra") or {}
    if extra.get("closed_form_n") is None:
        return ""
    text = (f"; closed form (analytic/design_factors.py, the wall's bending alone) n = {extra['closed_form_n']:.3g}: "
            f"{extra['governs']}")
    fe = extra.get("fe_mesh_load")
    if fe:
        text += (f"; with the tooth-mesh FE's flank load instead of the closed form's ({fe['source']}; closed form "
                 f"F0 {fe['closed_form_peak_force_N']:.4g} N) n would be {fe['n']:.3g}: not the verdict, since the FE "
                 "mesh is 1.2-2x stiffer than catalogue drives and how many teeth share the load is not settled")
        if fe.get("n_fe_root") is not None:
            text += (f"; with the FE's own root stress from that load ({fe['fe_root_MPa']:.4g} MPa at the filleted "
                     f"root, notched: entered over K_sigma) n would be {fe['n_fe_root']:.3g}: beside, not the verdict "
                     "(the factor's mesh term is a nominal stress under the wave's notch factor; the FE's is the "
                     "tooth-bending fillet peak, a different notch)")
    return text


def design_notes(design: dict) -> list[str]:
    """The materials table and the wave generator bearing's ratings, as sentences under the design table."""
    out = [f"Material of {part}: {m['name']}: sigma_-1 {m['fatigue_limit_MPa']:g}, R_p0.2 {m['yield_strength_MPa']:g}, "
           f"R_m {m['ultimate_strength_MPa']:g} MPa ({m['source']})" for part, m in design.get("materials", {}).items()]
    r = design.get("ratings")
    if r:
        out.append(f"Wave generator bearing: Hertz p0 = {r['p0_max_MPa']:.4g} MPa on the most loaded ball (Q = "
                   f"{r['max_ball_load_N']:.4g} N), static n = {r['static_contact_n']:.3g} ({r['static_contact_source']}); "
                   f"C_r = {r['C_r_N']:.4g} N, L10 = {r['L10_h']:.4g} h ({r['L10_note']})")
    b = design.get("buckling")
    if b and b.get("fe_over_rated") is not None:
        out.append(buckling_line(b))
    if design.get("ratcheting"):
        from strainwave.compare.validate.ratcheting import ratcheting_line
        out.append(ratcheting_line(design["ratcheting"]))
    else:
        out.append("Not computed: the ratcheting torque (no finite value from the tooth-mesh study: not run or failed)")
    if design.get("tooth_root_mesh"):
        from strainwave.compare.validate.tooth_root_record import tooth_root_line
        out.append(tooth_root_line(design["tooth_root_mesh"]))
    return out


def buckling_line(b: dict) -> str:
    """The flexspline's buckling rating: FE and closed form over the rated torque, yield or buckling first, and the
    catalogue's nearest size (shown, not asserted)."""
    first = (f"the wall's shear reaches R_p0.2/sqrt(3) = {b['shear_yield_MPa']:.4g} MPa first, at "
             f"{b['shear_yield_torque_Nmm'] / b['rated_torque_Nmm']:.3g} x rated: the elastic buckling torque is an "
             "upper bound" if b["yields_first"] else "it buckles before the wall yields")
    gci = "none" if b.get("fe_gci_Nmm") is None else f"{b['fe_gci_Nmm'] / 1e3:.3g}"
    return (f"Flexspline torsional buckling (check cup.buckling_torque): FE {b['fe_buckling_torque_Nmm'] / 1e3:.4g} N m "
            f"(GCI {gci}) = {b['fe_over_rated']:.3g} x the rated torque; closed form "
            f"{b['closed_form_torque_Nmm'] / 1e3:.4g} N m ({b['closed_form_over_rated']:.3g} x, n = {b['n_waves']} waves, "
            f"Z = {b['Z']:.4g}); {first}; beside it, CSF size {b['csf_size']}: {b['csf_buckling_torque_Nm']:g} N m "
            f"({b['csf_note']})")


def singular_line(component: str, s: dict) -> str | None:
    """The singular peaks of a crack tip and of a sharp re-entrant edge, shown apart from the design stress (None
    without either)."""
    parts = []
    if s.get("tip_peak_von_mises_MPa") is not None:
        parts.append(f"crack-tip peak {s['tip_peak_von_mises_MPa']:.4g} MPa at {point(s['tip_peak_location_mm'])} mm, "
                     f"within {s['tip_radius_mm']:.3g} mm of the crack front")
    if s.get("corner_peak_von_mises_MPa") is not None:
        parts.append(f"peak {s['corner_peak_von_mises_MPa']:.4g} MPa at {point(s['corner_peak_location_mm'])} mm, "
                     f"within {s['corner_radius_mm']:.3g} mm of a sharp re-entrant edge (the model has no fillet "
                     "there; a real fillet's radius sets its stress)")
    if not parts:
        return None
    return (f"{component}: {'; '.join(parts)}: singular (it grows with refinement), left out of the safety factor "
            "and the colour range")


def run_line(doc: dict) -> str:
    m = doc["metadata"]
    mode = "--quick (coarse meshes, fewer sweep points)" if m["settings"]["quick"] else "full"
    mode += "" if m["settings"].get("step", True) else ", no STEP export (add --step)"
    cached = sum(1 for c in m["cases"] if c["cached"])
    return (f"{mode} run, {len(m['cases'])} FEA cases ({cached} reused from the cache), P{m['settings']['order']} "
            f"elements, total {m['total_s']:.1f} s, {m['created_utc']}, strainwave {m['versions']['strainwave']} "
            f"(code {m['versions']['code_version']})")


def no_step_line(doc: dict) -> str:
    """Why the files list holds no STEP: the run skipped the export, or every part failed to build."""
    if not doc["metadata"]["settings"].get("step", True):
        return "not exported (--quick; run without --quick, or add --step)"
    return "no part could be built (see the STEP errors in results.json metadata.steps)"


NO_PDF = ("report.pdf: not printed: the PDF is this page printed by headless Chromium, which is not installed "
          "(Debian/Ubuntu: sudo apt-get install chromium; then rerun the same command: finished cases are reused). "
          "Your browser's Print > Save as PDF of report.html gives the same pages.")


DRIVE_UNITS = ("N*mm/rad", "N*mm")   # a check in these reports a stiffness or torque: N m/rad, N m beside


def check_row(c: dict) -> tuple[str, ...]:
    fea = "not evaluated" if c["fea"] is None else (
        f"{num(c['fea'])} +/- {num(c['fea_uncertainty'], 2)}" if c["fea_uncertainty"] is not None else num(c["fea"]))
    if c["fea"] is not None and c.get("unit") in DRIVE_UNITS:   # the drive's stiffness also as the catalogue gives it
        fea += beside(c["fea"], c["unit"])
    cells = []
    for variant in ("published", "corrected"):
        value = c["analytic"].get(variant)
        err = c["rel_error"].get(variant)
        cells.append(f"{num(value)} ({pct(err)})" if err is not None else num(value))
    tol = c["tolerance"]
    tolerance = "n/a" if tol["relative"] is None else f"{100 * tol['relative']:.3g} %: {tol['reason']}"
    result = "PASS" if c["passed"] else ("NOT EVALUATED" if c["verdict"] == "not evaluated" else "FAIL")
    verdict = c["verdict"] if c["verdict"] != "not evaluated" else c["reason_not_evaluated"]
    return (c["id"], f"{c['quantity']} [{c['unit']}]", fea, *cells, tolerance, verdict, result)


def check_notes(c: dict) -> str:
    parts = [c["note"]] if c["note"] else []
    if c["sources"]:
        parts.append("sources: " + "; ".join(f"{k} = {v}" for k, v in c["sources"].items()))
    if c.get("relation") == "at_most":
        parts.append(f"asserts FEA <= the {c['asserts']} value (an upper bound) within the tolerance")
    else:
        parts.append(f"asserts agreement with the {c['asserts']} form")
    return " | ".join(parts)


def sweep_rows(sweep: dict) -> list[tuple[str, ...]]:
    rows = []
    for i, depth in enumerate(sweep["depths_mm"]):
        row = [num(depth, 3), num(sweep["fea"][i], 4), num(sweep["fea_uncertainty"][i], 2),
               "yes" if sweep["resolved"][i] else "no"]
        for variant in ("published", "corrected"):
            values = sweep["analytic"].get(variant)
            row.append(num(values[i], 4) if values else "n/a")
        notes = sweep.get("range_notes") or []
        row.append("-" if not notes else ("OUTSIDE: " + notes[i]) if notes[i] else "confirmed")
        rows.append(tuple(row))
    return rows


SWEEP_COLUMNS = ("a (mm)", "FEA", "U (GCI)", "resolved", "published", "corrected", "corrected form's range")


def sweep_fit_line(sweep: dict) -> str:
    fit = sweep.get("fit")
    if not fit:
        return "exponent: not fitted (fewer than two resolved depths)"
    err = f" +/- {fit['stderr']:.2f}" if fit["stderr"] is not None else ""
    exps = ", ".join(f"{k} a^{v:.2f}" for k, v in sweep.get("analytic_exponents", {}).items())
    return (f"np.polyfit of log(delta) vs log(a) over {fit['points']} resolved depths: FEA a^{fit['exponent']:.2f}"
            f"{err}; closed forms over the same depths: {exps}")


AUDIT_COLUMNS = ("#", "seed", "where", "what is wrong", "effect on the example", "FEA check", "FEA evidence")


def audit_row(a: dict) -> tuple[str, ...]:
    return (str(a["id"]), a["seed"], a["equation"], a["what_is_wrong"], a["effect_on_example"],
            a["fea_check"] or "-", a["settled"])


CASE_COLUMNS = ("case", "study", "crack (mm)", "status", "dofs", "time (s)")


def case_row(c: dict) -> tuple[str, ...]:
    status = ("cached" if c["cached"] else "solved") if c["ok"] else f"FAILED: {c['error']}"
    dofs = num(c["result"]["mesh"]["dofs"]) if c.get("result") else "-"
    return (c["label"], c["study"], num(c["crack_depth_mm"], 3), status, dofs, f"{c['seconds']:.1f}")


def failing_line(c: dict) -> str:
    """A failing check with its numbers and the one-sentence reason (not only the verdict)."""
    if c["verdict"] == "not evaluated":
        return f"not evaluated: {c['reason_not_evaluated']}"
    asserted = c["asserts"]
    err = c["rel_error"].get(asserted)
    tol = c["tolerance"]
    unc = f" +/- {num(c['fea_uncertainty'], 2)}" if c["fea_uncertainty"] is not None else ""
    others = ", ".join(f"{v} {num(c['analytic'][v])} ({pct(c['rel_error'][v])})" for v in ("published", "corrected")
                       if v != asserted and c["analytic"].get(v) is not None and c["rel_error"].get(v) is not None)
    bound = "above the upper bound by" if c.get("relation") == "at_most" else "off by"
    return (f"FEA {num(c['fea'])}{unc} {c['unit']} vs the asserted {asserted} form {num(c['analytic'].get(asserted))}: "
            f"rel. error {pct(err)}, tolerance {100 * tol['relative']:.3g} % ({tol['reason']})"
            + (f"; {others}" if others else "") + f". Reason: the FEA is {bound} {abs(100 * err):.3g} %, more than "
            f"the tolerance, so it supports {'neither form' if c['verdict'] == 'neither' else 'the ' + c['verdict'] + ' form only'}.")


INPUT_MESH_COLUMNS = ("mesh", "h (mm)", "dofs", "min element quality")


def input_lines(i: dict) -> list[tuple[str, str]]:
    """(what, value) rows of a component's inputs-and-model record."""
    rows = [(name, value) for name, value in i["dimensions"]]
    rows += [("material", i["material"]), ("load", i["load"]), ("supports", i["supports"]),
             ("element", i["element"]), ("FEA case", f"{i['case']} ({i['study']})")]
    return rows


def input_mesh_rows(i: dict) -> list[tuple[str, ...]]:
    names = ("h1 (fine)", "h2", "h3 (coarse)")
    return [(names[k], num(m["h_mm"], 4), num(m["dofs"]) if m["dofs"] is not None else "not recorded",
             num(m["min_quality"], 3) if m["min_quality"] is not None else "not recorded")
            for k, m in enumerate(i["meshes"])]


RATED_COLUMNS = ("component", "rated load", "peak von Mises (MPa)", "at (x, y, z) mm", "peak displacement (mm)",
                 "fatigue limit (MPa)", "sigma_-1 / peak (not the design factor: see the design table)", "note")


def point(xyz) -> str:
    """(x, y, z) with round-off zeros shown as 0 (a coordinate below 1e-9 of the largest)."""
    big = max(abs(v) for v in xyz) or 1.0
    return "(" + ", ".join(f"{v if abs(v) > 1e-9 * big else 0.0:.4g}" for v in xyz) + ")"


def rated_row(component: str, s: dict) -> tuple[str, ...]:
    return (component, f"{s['load_text']}; fields x {s['load']['scale']:.4g}", num(s["peak_von_mises_MPa"], 4),
            point(s["peak_location_mm"]) + (f" on {', '.join(s['peak_on'])}" if s["peak_on"] else ""),
            num(s["peak_displacement_mm"], 3),
            num(s["fatigue_limit_MPa"], 4), num(s["safety_factor"], 3), s["note"])


def rated_sentence(s: dict) -> str:
    load = s["load"]
    on = f" on {', '.join(repr(g) for g in s['peak_on'])}" if s["peak_on"] else ""
    return (f"at {load['name']} = {load['rated']:.4g} {load['unit']}{beside(load['rated'], load['unit'])}: peak von Mises {s['peak_von_mises_MPa']:.4g} MPa "
            f"at {point(s['peak_location_mm'])} mm{on}, peak displacement {s['peak_displacement_mm']:.3g} mm, safety "
            f"factor {s['safety_factor']:.3g} against sigma_-1 = {s['fatigue_limit_MPa']:g} MPa")


GCI_INTRO = ("ASME V&V 20 (Roache) three-mesh estimate of every FEA quantity: h1 < h2 < h3, f1..f3 the values on "
             "them, r the refinement ratios, p the observed order as found (never clipped; the element's formal "
             "order in brackets), f_ext the Richardson value, GCI_fine = Fs |f2 - f1| / |f1| / (r21^p - 1). By the "
             "book (Roache; Oberkampf & Roy sec. 8.7): in the asymptotic range (monotone, observed p within 10 % of "
             "the formal order) the observed p with Fs = 1.25; otherwise Fs = 3 with the formal p, or the observed "
             "one where lower (never below 0.5); the column 'GCI basis' says which. Three identical values carry no GCI (refused, never 0 %).")

NAFEMS_INTRO = ("NAFEMS TNSB Rev. 3 (1990) linear-elastic benchmarks through the project's own assembly, solver and "
                "stress recovery (nodal averaging, fea/fields.nodal_stress), curved P2 meshes by gmsh. Coarse: run "
                "by this validation, tolerance min(coarse-mesh practice: 5 % LE1/LE10, 12.4 % LE11; 3 GCI + target "
                "rounding). Fine: "
                "`make bench` (benchmarks/bench_nafems.py), PASS when |error| + GCI <= 1 %.")
NAFEMS_COLUMNS = ("case", "quantity", "level", "target (MPa)", "FEA (MPa)", "error", "dofs", "GCI (basis)",
                  "acceptance", "verdict")


def nafems_row(r: dict) -> tuple[str, ...]:
    """One row of the NAFEMS appendix from a ``fea/nafems.NafemsResult.to_dict`` record."""
    gci = r["gci_fine"]
    gci_text = "refused" if gci is None or gci != gci else f"{100 * gci:.3g} %"
    accept = "|error| + GCI <= 1 %" if r["level"] == "fine" else f"|error| <= {100 * r['tolerance_rel']:.3g} %"
    return (f"{r['id']} ({r['title']})", r["quantity"], r["level"], f"{r['target_MPa']:g}", f"{r['value_MPa']:.4g}",
            f"{100 * r['error_rel']:+.3f} %", str(r["dofs"]), f"{gci_text} ({r.get('basis', '-')})", accept,
            "PASS" if r["passed"] else ("MISS" if r["level"] == "fine" else "FAIL"))
