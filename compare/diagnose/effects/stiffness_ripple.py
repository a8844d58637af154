"""stiffness_ripple: a torsional stiffness that ripples with the wave generator's input angle.

The flexspline's teeth engage along the major axis of the elliptical wave generator, which passes every tooth
twice per input turn: the mesh stiffness varies at twice the input angle (and its harmonics), and so does a
breathing crack in the flexspline as the major axis passes it. The twist of a compliance that varies with the
angle grows with the torque, unlike the kinematic error, a ripple at any load. Needs ``input_angle_rad``.
Model (linear in its amplitudes):
    y += u (a2 cos 2 theta + b2 sin 2 theta + a4 cos 4 theta + b4 sin 4 theta).
"""
from __future__ import annotations

import math

from strainwave.compare.diagnose.periodic import angle_load_columns
from strainwave.compare.diagnose.effects.base import Context, Effect, Param
from strainwave.compare.diagnose.effects.kinematic_error import ARCSEC_PER_RAD

HARMONICS = (2, 4)


def _basis(ctx: Context):
    return angle_load_columns(ctx, HARMONICS)


def _contribution(ctx: Context, theta):
    return _basis(ctx) @ theta


def _report(ctx: Context, theta, s: float) -> dict:
    out = {}
    for i, k in enumerate(HARMONICS):
        amp = math.hypot(theta[2 * i], theta[2 * i + 1])
        # the compliance ripple relative to the specimen's mean compliance s c0
        out[f"compliance_ripple_{k}x_percent"] = (100.0 * amp / s, "%")
        if ctx.response_unit == "rad":
            out[f"twist_ripple_{k}x_at_full_load_arcsec"] = (amp * ctx.Y * ARCSEC_PER_RAD, "arcsec")
        out[f"phase_{k}x"] = (math.atan2(-theta[2 * i + 1], theta[2 * i]), "rad")
    return out


EFFECT = Effect(
    id="stiffness_ripple",
    kinds=("torsion",),
    params=tuple(Param(f"{c}{k}", -0.5, 0.5, (0.0,)) for k in HARMONICS for c in ("a", "b")),
    contribution=_contribution,
    report=_report,
    explanation=("the torsional stiffness varies with the wave generator's angle, twice per input turn: the mesh "
                 "stiffness changes as the major axis passes the teeth, or a crack in the flexspline opens and "
                 "closes as the major axis passes it; the twist ripple grows with the torque"),
    applicable=lambda ctx: ctx.angle is not None,
    basis=_basis,
    load_path=False,
)
