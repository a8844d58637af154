"""compliance_offset: a linear series compliance the model lacks (fixture, omitted bore, bearing, contact).

Model: y += d u, i.e. measured compliance (s + d) c0. The stiffness scale s carries the prior
1 +/- baseline_uncertainty, so only a difference beyond the stated uncertainty earns this effect.
"""
from __future__ import annotations

from strainwave.compare.diagnose.effects.base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    return theta[0] * ctx.u


def _report(ctx: Context, theta, s: float) -> dict:
    extra = theta[0] * ctx.c0
    total = (s + theta[0]) * ctx.c0
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    unit = f"{ctx.response_unit}/{ctx.load_unit}"
    return {"extra_compliance": (extra, unit), "measured_stiffness": (1.0 / total, inv),
            "baseline_stiffness": (1.0 / ctx.c0, inv), "compliance_change_percent": (100.0 * (s + theta[0] - 1.0), "%")}


EFFECT = Effect(
    id="compliance_offset",
    kinds=("torsion", "ring_compression"),
    params=(Param("d", -0.9, 10.0, (0.2, -0.2)),),
    contribution=_contribution,
    report=_report,
    explanation=("a linear compliance in series with the modelled part (fixture, clamping, an omitted bore "
                 "or bearing) makes the whole specimen uniformly softer or stiffer than simulated"),
    series_compliance=True,
)
