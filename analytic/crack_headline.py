"""What a crack costs a designer (seed 000's headline), from the crack forms the FEA confirmed.

Seed 000 claims a 1.2 % drop of K_HD from a 0.1 mm crack in each component. With the forms that
`strainwave validate` confirms against FEA:
- output shaft: the thick-tube form (``tube_crack.thick_tube_flexibility``; confirmed on d_i/d = 0.643 and
  0.9 up to a/t = 3/4, fitted on 0.5 and 0.8), G = E/2(1+nu);
- flexspline: the seed's through-wall 45 deg crack, both tips, a^2/(2 pi E r_m^4 delta)
  (``cracks.flexspline_through_crack_flexibility``; confirmed at a = 1.12 mm; a flat-sheet form, so valid
  while the shell parameter a/sqrt(r_m delta) stays small);
- wave-generator bearing ring: the crack at the centre of the Hertz patch is compressed and stays shut
  (FEA with crack-face contact): it adds no compliance at any depth.
The uncracked drive is lambda_H0 (seed's K_G0) + the series shell cup + the hollow shaft, all with G = E/2(1+nu)
(the members the gear.stiffness check confirms).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from scipy import optimize

from strainwave.analytic import cracks, torsion, tube_crack
from strainwave.analytic.variant import Variant

__all__ = ["ComponentCrackCost", "CrackHeadline", "crack_headline", "TARGET_DROP", "SEED_CLAIM_PERCENT"]

TARGET_DROP = 0.01            # the K_HD drop a designer asks about: 1 %
SEED_CLAIM_PERCENT = 1.2      # seed 000's "stiffness reduction of about 1.2 %"
SHAFT_CONFIRMED_A_OVER_T = 0.75     # deepest a/t at which the thick-tube form was checked against FEA
CUP_SHELL_PARAMETER_LIMIT = 0.5     # a/sqrt(r_m delta) up to which a flat-sheet crack form is taken as valid


@dataclass(frozen=True)
class ComponentCrackCost:
    component: str
    form: str
    depth_mm: float                          # the parameter set's crack of this component (seed 000: 0.1 mm)
    delta_lambda_at_seed_depth: float        # rad/(N mm)
    drop_at_seed_depth: float                # relative K_HD drop, this crack alone
    depth_for_target_mm: float | None        # crack depth (half-length for the cup) costing TARGET_DROP
    depth_note: str

    def __post_init__(self):
        if self.delta_lambda_at_seed_depth < 0 or not 0 <= self.drop_at_seed_depth < 1:
            raise ValueError(f"{self.component}: a crack cannot stiffen the drive")


@dataclass(frozen=True)
class CrackHeadline:
    seed_depth_mm: float                     # the largest of the components' depths (all 0.1 mm in seed 000)
    lambda_sum_uncracked: float
    K_HD_uncracked: float
    components: tuple[ComponentCrackCost, ...]
    drop_all_three: float                    # all three cracks of the seed's depth together

    def to_dict(self) -> dict:
        return {"seed_depth_mm": self.seed_depth_mm, "lambda_sum_uncracked": self.lambda_sum_uncracked,
                "K_HD_uncracked_Nmm_per_rad": self.K_HD_uncracked, "drop_all_three": self.drop_all_three,
                "seed_claim_percent": SEED_CLAIM_PERCENT, "target_drop": TARGET_DROP,
                "components": [c.__dict__.copy() for c in self.components]}


def _drop(lambda_sum: float, delta: float) -> float:
    return delta / (lambda_sum + delta)


def _depth_for(fn, lambda_sum: float, a_max: float) -> float | None:
    """Depth in (0, a_max] where fn(a) costs TARGET_DROP of K_HD, or None if a_max does not reach it."""
    g = lambda a: _drop(lambda_sum, fn(a)) - TARGET_DROP   # noqa: E731
    if g(a_max) < 0:
        return None
    return float(optimize.brentq(g, 1e-9 * a_max, a_max, xtol=1e-9 * a_max))


def crack_headline(params) -> CrackHeadline:
    """Seed 000's headline recomputed from confirmed forms (module docstring)."""
    from strainwave.analytic.seed000 import cup_series_model

    mat, sh, cup, g, wg = params.material, params.output_shaft, params.flexspline_cup, params.gear, params.wave_generator
    G, E = mat.implied_shear_modulus_MPa, mat.youngs_modulus_MPa
    a_s, a_f, a_b = sh.crack_depth_mm, cup.root_crack_depth_mm, wg.bearing_crack_depth_mm
    lam_H0 = torsion.wave_generator_flexibility(g.force_coefficient, wg.uncracked_radial_stiffness_N_per_mm,
                                                cup.pitch_diameter_mm, g.wave_number, g.radial_deformation_mm,
                                                g.gear_ratio)
    lam_f0 = cup_series_model(params, G).total
    lam_so0 = torsion.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G, Variant.CORRECTED)
    lam = lam_H0 + lam_f0 + lam_so0

    r_o, r_i = 0.5 * sh.outer_diameter_mm, 0.5 * sh.inner_diameter_mm
    shaft_fn = lambda s: tube_crack.thick_tube_flexibility(r_o, r_i, s, G)   # noqa: E731
    a_shaft_max = SHAFT_CONFIRMED_A_OVER_T * (r_o - r_i)
    r_m, wall = 0.5 * (cup.pitch_diameter_mm - cup.wall_thickness_mm), cup.wall_thickness_mm
    cup_fn = lambda s: cracks.flexspline_through_crack_flexibility(r_m, wall, s, E)   # noqa: E731
    a_cup_max = CUP_SHELL_PARAMETER_LIMIT * math.sqrt(r_m * wall)

    d_shaft, d_cup = shaft_fn(a_s), cup_fn(a_f)
    a_shaft = _depth_for(shaft_fn, lam, a_shaft_max)
    a_cup = _depth_for(cup_fn, lam, a_cup_max)
    # flat-sheet extrapolation beyond the form's range, quoted only to say how far out of reach it is
    a_cup_flat = math.sqrt(TARGET_DROP / (1 - TARGET_DROP) * lam / cup_fn(1.0))
    components = (
        ComponentCrackCost("output shaft", "circumferential crack, thick-tube form", a_s, d_shaft, _drop(lam, d_shaft),
                           a_shaft, f"confirmed range a/t <= {SHAFT_CONFIRMED_A_OVER_T:g}, wall {r_o - r_i:g} mm"
                           + ("" if a_shaft is None else f", a/t = {a_shaft / (r_o - r_i):.3g}")),
        ComponentCrackCost("flexspline", "through-wall 45 deg crack of half-length a, both tips", a_f, d_cup,
                           _drop(lam, d_cup), a_cup,
                           f"not within a/sqrt(r_m delta) <= {CUP_SHELL_PARAMETER_LIMIT:g} (a <= {a_cup_max:.3g} mm); "
                           f"the flat-sheet form would need a = {a_cup_flat:.3g} mm" if a_cup is None else
                           "within the flat-sheet range"),
        ComponentCrackCost("wave-generator bearing ring", "surface crack at the Hertz centre: compressed, shut",
                           a_b, 0.0, 0.0, None, "a crack under the contact never opens (FEA with face contact); the "
                                           "seed's tensile form applies to a crack outside the patch, not checked"),
    )
    total = d_shaft + d_cup
    return CrackHeadline(max(a_s, a_f, a_b), lam, 1.0 / lam, components, _drop(lam, total))
