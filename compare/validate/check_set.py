"""All checks of a validation run, plus the crack sweeps and fitted exponents they rest on."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from strainwave.registry import STUDIES
from strainwave.compare.validate.checks import REQUIRED_IDS, Check, not_evaluated
from strainwave.compare.validate.crack_scaling import PowerFit, fit_power_law
from strainwave.compare.validate.fea_book import FeaBook, Sweep
from strainwave.compare.validate.plan import COMPONENT_STUDY, Plan
from strainwave.analytic import tube_crack
from strainwave.compare.validate.ring_checks import ring_checks
from strainwave.compare.validate.wg_bearing_checks import gear_stiffness, wg_bearing_checks
from strainwave.compare.validate.torsion_checks import (FLEX_UNIT, bearing_crack_curve, crack_check,
                             cup_crack_allowances, cup_crack_curve, cup_flexibility, mu_gap,
                             shaft_crack_curve, shaft_flexibility, shaft_form_note)
from strainwave.compare.validate.wg_cup_checks import wg_checks
from strainwave.compare.validate.surface_crack_checks import surface_crack_checks

# component -> the quantity that is its crack's added compliance (registry)
DELTA_NAMES = {c: STUDIES[s].crack_delta.name for c, s in COMPONENT_STUDY.items()}


@dataclass(frozen=True)
class SweepReport:
    sweep: Sweep
    fit: PowerFit | None                       # over the resolved depths
    analytic: dict[str, list[float]]           # variant -> closed form at each depth
    analytic_fits: dict[str, float] = field(default_factory=dict)   # variant -> exponent over resolved depths
    range_notes: tuple[str, ...] = ()          # per depth: "" or why the corrected form is used out of range

    def to_dict(self) -> dict:
        return {**self.sweep.to_dict(), "fit": None if self.fit is None else self.fit.to_dict(),
                "analytic": self.analytic, "analytic_exponents": self.analytic_fits,
                "range_notes": list(self.range_notes)}


@dataclass(frozen=True)
class CheckSet:
    checks: tuple[Check, ...]
    sweeps: dict[str, SweepReport]

    def by_id(self) -> dict[str, Check]:
        return {c.id: c for c in self.checks}


def _curves(params, s000: dict, book: FeaBook, plan: Plan):
    """component -> (depth -> {variant: closed form}) under the FEA's load conditions."""
    F_r = book.applied_force_N(plan.headline["bearing"].label) or s000.get("F_r_N", 1.0)
    return {"shaft": lambda a: shaft_crack_curve(params, a),
            "cup": lambda a: cup_crack_curve(params, a),
            "bearing": lambda a: bearing_crack_curve(params, a, F_r)}


def _shaft_range_note(params):
    s = params.output_shaft
    r_o, r_i = 0.5 * s.outer_diameter_mm, 0.5 * s.inner_diameter_mm
    return lambda a: tube_crack.range_note(r_i / r_o, a / (r_o - r_i))


def _sweep_report(sweep: Sweep, curve, range_note=None) -> SweepReport:
    analytic = {}
    for depth in sweep.depths_mm:
        for variant, value in curve(depth).items():
            analytic.setdefault(variant, []).append(value)
    ok = sweep.resolved(3.0)
    depths = np.asarray(sweep.depths_mm)[ok]
    fit = fit_power_law(depths, np.asarray(sweep.values)[ok])
    analytic_fits = {}
    if fit is not None:
        for variant, values in analytic.items():
            f = fit_power_law(depths, np.asarray(values)[ok])
            if f is not None:
                analytic_fits[variant] = f.exponent
    notes = tuple(range_note(d) for d in sweep.depths_mm) if range_note is not None else ()
    return SweepReport(sweep, fit, analytic, analytic_fits, notes)


CRACK_TEXT = {
    "shaft": ("shaft.crack_compliance", "added torsional flexibility of the circumferential shaft crack", FLEX_UNIT,
              "published 512 M_M^2 a^3/(3 mu d_e^6) (seed 000: penny-crack area, solid-bar K_III); asserted "
              "(corrected): strainwave's thick-tube form, the hollow-tube strip form (Tada's anti-plane edge-cracked "
              "strip of the wall t under tau_o = T r_o/J_hollow, dA = 2 pi r_o da) times the tube's net-section "
              "amplification^m, m fitted on d_i/d = 0.5 and 0.8 only (analytic/tube_crack.py), so the default "
              "d_i/d is a geometry it was not fitted on; beside them the strip form itself and the solid-bar "
              "128 M_M^2 a^2/(mu d_e^5) (audit 10, 12)"),
    "cup": ("cup.crack_compliance", "added torsional flexibility of the seed's through-wall 45 deg flexspline crack",
            FLEX_UNIT,
            "the crack seed 000 describes: through the wall, half-length a, 45 deg to the axis (pure mode I, "
            "K_I = tau sqrt(pi a)), in the fully loaded tube between diaphragm and tooth band (not in the band, "
            "where the torque enters as surface shear and the section carries less than T). Asserted "
            "(corrected): both tips, a^2/(2 pi E r_m^4 delta); the seed's published K_u K_d a^2/(2 pi ...) is "
            "that form (its 2 pi is right for a through crack), evaluated at K_u = K_d = 1 (static uniform load, "
            "audit 17); audit_one_tip = the audit's a^2/(4 pi ...), which integrates one tip only"),
    "bearing": ("bearing.crack_compliance", "added radial compliance of the bearing-ring surface crack", "mm/N",
                "du_H/F_r; published carries F_r^2 (load-dependent), corrected F_r (audit 7)"),
}


def build_checks(book: FeaBook, plan: Plan, summary: dict, params) -> CheckSet:
    s000 = summary.get("seed000", {})
    refs = summary.get("checks", {})
    labels = {c: case.label for c, case in plan.headline.items()}
    # bearing.radial_compliance is information, not a check (analytic checks entry and audit 13): the seed's
    # K_G0 has no model to confirm, and the ring FEA is one member of it under the tool's own bonded bore
    checks = [shaft_flexibility(book, labels["shaft"], s000, params),
              cup_flexibility(book, labels["cup"], s000, params)]
    sweeps = {}
    curves = _curves(params, s000, book, plan)
    for component, (check_id, quantity, unit, note) in CRACK_TEXT.items():
        case_labels = [plan.headline[component].label] + [c.label for c in plan.sweeps[component]]
        sweep = book.sweep(component, case_labels, DELTA_NAMES[component])
        if sweep is not None:
            sweeps[component] = _sweep_report(sweep, curves[component],
                                              _shaft_range_note(params) if component == "shaft" else None)
        allowances, depth_note = {}, None
        if component == "cup":
            allowances = lambda a: cup_crack_allowances(params, a)   # noqa: E731  (depth chosen in crack_check)
        if component == "shaft":
            s = params.output_shaft
            ratio = s.inner_diameter_mm / s.outer_diameter_mm
            fitted = any(abs(ratio - x) < 0.02 for x in tube_crack.THICK_TUBE_FIT_RATIOS)
            allowances = {f"thick-tube form: largest deviation on the geometries m was fitted on (d_i/d = "
                          f"{', '.join(f'{x:g}' for x in tube_crack.THICK_TUBE_FIT_RATIOS)}; this shaft d_i/d = "
                          f"{ratio:.3g}, {'one of them' if fitted else 'not fitted on'})":
                          tube_crack.THICK_TUBE_FIT_SCATTER}
            hollow = 1.0 / (1.0 - ratio ** 4)
            note += (f"; the bore raises the outer-fibre shear stress by {hollow:.3f} and so a shallow crack's "
                     f"compliance by {hollow ** 2:.3f} over the solid-bar forms; G = E/2(1+nu) as the FEA")
            depth_note = lambda a: shaft_form_note(params, a)   # noqa: E731
        if component == "bearing":
            # the 3D ring on a bonded bore stays in the sweep table; the check is the ring on the cam (wg-bearing)
            continue
        checks.append(crack_check(check_id, quantity, unit, sweep, curves[component], allowances, note,
                                  {"fea": "FEA " + ", ".join(case_labels), "analytic": "seed 000"},
                                  params.crack_depth_mm(STUDIES[COMPONENT_STUDY[component]].crack_key),
                                  depth_note=depth_note))
    checks += wg_bearing_checks(book, plan.wg_bearing.label, params)
    checks += ring_checks(book, plan.ring.label, refs, params)
    checks.append(gear_stiffness(book, labels, plan.wg_bearing.label, s000, params))
    wg_label = plan.drive_label("cup-wave-generator")
    if wg_label is not None:
        checks += wg_checks(book, wg_label, params)
    if plan.drive_label("cup-surface-crack") is not None:
        checks += surface_crack_checks(book, plan.drive_label("cup-surface-crack"), params)
    present = {c.id for c in checks}
    checks += [not_evaluated(cid, cid, "", "no builder produced this check") for cid in REQUIRED_IDS
               if cid not in present]
    order = {cid: i for i, cid in enumerate(REQUIRED_IDS)}
    checks.sort(key=lambda c: order.get(c.id, len(order)))
    return CheckSet(tuple(checks), sweeps)
