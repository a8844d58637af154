"""thick_ring: shear, normal-force and curvature deformation that thin-ring theory (seed 003 eq 3) omits.

Zero free parameters: the correction is predicted from the geometry by Roark's thick-ring formula
(Table 9.2 case 1, alpha = e/R, beta = 2F(1+nu)e/R, I -> A e R; strainwave.analytic.thick_ring):
    delta_CD = rho * delta_CD,thin,   y += (rho - 1) u.
Only a compliance change matching this prediction (within the baseline uncertainty) earns the name, and
only where the prediction itself exceeds the baseline uncertainty: for a thinner rim, thin-ring theory is
adequate by definition and a free zero-parameter shift would be picked up for nothing.
"""
from __future__ import annotations

from strainwave.compare.diagnose.effects.base import Context, Effect


def _rho(ctx: Context) -> float:
    return float(ctx.geometry["thick_ring_factor"])


def _contribution(ctx: Context, theta):
    return (_rho(ctx) - 1.0) * ctx.u


def _report(ctx: Context, theta, s: float) -> dict:
    rho = _rho(ctx)
    g = ctx.geometry
    return {"predicted_compliance_factor": (rho, "1"),
            "rim_thickness_to_radius": (g["rim_thickness_mm"] / g["r_m_mm"], "1"),
            "measured_compliance_factor": (s + rho - 1.0, "1")}


EFFECT = Effect(
    id="thick_ring",
    kinds=("ring_compression",),
    params=(),
    contribution=_contribution,
    report=_report,
    explanation=("the rim is too thick for thin-ring theory: shear and hoop-force deformation and the "
                 "curved-beam neutral-axis shift add compliance that Roark's thick-ring formula predicts"),
    applicable=lambda ctx: ("thick_ring_factor" in ctx.geometry
                            and abs(ctx.geometry["thick_ring_factor"] - 1.0) >= ctx.uncertainty),
    degenerate_with=("compliance_offset",),     # both are a pure linear compliance change
)
