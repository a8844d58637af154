"""The crack-compliance checks of the torsion studies, each as one builder of ``check_list.CHECKS``: the FEA's
sweep of added compliance against the closed form (``CheckSpec.reference``) at the depth it resolves best."""
from __future__ import annotations

from strainwave.analytic import tube_crack
from strainwave.compare.validate.torsion_checks import (FLEX_UNIT, crack_check, cup_crack_allowances,
                                                        shaft_form_note)

__all__ = ["shaft_crack", "cup_crack", "crack_sweep_of", "shaft_range_note"]

SHAFT_NOTE = ("published 512 M_M^2 a^3/(3 mu d_e^6) (seed 000: penny-crack area, solid-bar K_III); asserted "
              "(corrected): strainwave's thick-tube form, the hollow-tube strip form (Tada's anti-plane edge-cracked "
              "strip of the wall t under tau_o = T r_o/J_hollow, dA = 2 pi r_o da) times the tube's net-section "
              "amplification^m, m fitted on d_i/d = 0.5 and 0.8 only (analytic/tube_crack.py), so the default "
              "d_i/d is a geometry it was not fitted on; beside them the strip form itself and the solid-bar "
              "128 M_M^2 a^2/(mu d_e^5) (audit 10, 12)")
CUP_NOTE = ("the crack seed 000 describes: through the wall, half-length a, 45 deg to the axis (pure mode I, "
            "K_I = tau sqrt(pi a)), in the fully loaded tube between diaphragm and tooth band (not in the band, "
            "where the torque enters as surface shear and the section carries less than T). Asserted "
            "(corrected): both tips, a^2/(2 pi E r_m^4 delta) x (1 - nu^2/2), midway between plane stress and "
            "plane strain (both shown); the seed's published K_u K_d a^2/(2 pi ...) is "
            "that form (its 2 pi is right for a through crack), evaluated at K_u = K_d = 1 (static uniform load, "
            "audit 17); audit_one_tip = the audit's a^2/(4 pi ...), which integrates one tip only")


def crack_sweep_of(ctx, spec):
    """(case labels, the FEA sweep of the crack delta) of the study ``spec`` stands beside."""
    from strainwave.registry import STUDIES
    study, name = spec.beside[0]
    component = STUDIES[study].component
    labels = [ctx.plan.headline[component].label] + [c.label for c in ctx.plan.sweeps[component]]
    return STUDIES[study], labels, ctx.book.sweep(component, labels, name)


def _curve(ctx, spec):
    from strainwave.compare.validate.check_list import At
    return lambda a: spec.reference(ctx.params, At(crack_depth_mm=a)).variants()


def shaft_range_note(params, depth_mm: float) -> str:
    s = params.output_shaft
    r_o, r_i = 0.5 * s.outer_diameter_mm, 0.5 * s.inner_diameter_mm
    return tube_crack.range_note(r_i / r_o, depth_mm / (r_o - r_i))


def shaft_crack(ctx, spec=None):
    from strainwave.compare.validate.check_list import check_spec
    spec = spec or check_spec("shaft.crack_compliance")
    study, labels, sweep = crack_sweep_of(ctx, spec)
    params = ctx.params
    s = params.output_shaft
    ratio = s.inner_diameter_mm / s.outer_diameter_mm
    fitted = any(abs(ratio - x) < 0.02 for x in tube_crack.THICK_TUBE_FIT_RATIOS)
    allowances = {f"thick-tube form: largest deviation on the geometries m was fitted on (d_i/d = "
                  f"{', '.join(f'{x:g}' for x in tube_crack.THICK_TUBE_FIT_RATIOS)}; this shaft d_i/d = "
                  f"{ratio:.3g}, {'one of them' if fitted else 'not fitted on'})": tube_crack.THICK_TUBE_FIT_SCATTER}
    hollow = 1.0 / (1.0 - ratio ** 4)
    note = SHAFT_NOTE + (f"; the bore raises the outer-fibre shear stress by {hollow:.3f} and so a shallow crack's "
                         f"compliance by {hollow ** 2:.3f} over the solid-bar forms; G = E/2(1+nu) as the FEA")
    return crack_check(spec.id, "added torsional flexibility of the circumferential shaft crack", FLEX_UNIT, sweep,
                       _curve(ctx, spec), allowances, note,
                       {"fea": "FEA " + ", ".join(labels), "analytic": "seed 000"},
                       params.crack_depth_mm(study.crack_key), depth_note=lambda a: shaft_form_note(params, a))


def cup_crack(ctx, spec=None):
    from strainwave.compare.validate.check_list import check_spec
    spec = spec or check_spec("cup.crack_compliance")
    study, labels, sweep = crack_sweep_of(ctx, spec)
    params = ctx.params
    return crack_check(spec.id, "added torsional flexibility of the seed's through-wall 45 deg flexspline crack",
                       FLEX_UNIT, sweep, _curve(ctx, spec), lambda a: cup_crack_allowances(params, a), CUP_NOTE,
                       {"fea": "FEA " + ", ".join(labels), "analytic": "seed 000"},
                       params.crack_depth_mm(study.crack_key))
