"""kinematic_error: the twist ripples with the wave generator's input angle (transmission error).

Harmonic drives show a kinematic (transmission) error dominated by the second harmonic of the wave
generator rotation (the elliptical wave generator deflects the flexspline twice per turn) and, smaller,
the fourth (Tuttle and Seering, "A nonlinear model of a harmonic drive gear transmission", IEEE TRA 1996).
Needs the optional column ``input_angle_rad``. Model (linear in its four amplitudes):
    y += a2 cos 2 theta + b2 sin 2 theta + a4 cos 4 theta + b4 sin 4 theta.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param

ARCSEC_PER_RAD = 3600.0 * 180.0 / math.pi
HARMONICS = (2, 4)


def _contribution(ctx: Context, theta):
    out = np.zeros_like(ctx.u)
    for i, k in enumerate(HARMONICS):
        out += theta[2 * i] * np.cos(k * ctx.angle) + theta[2 * i + 1] * np.sin(k * ctx.angle)
    return out


def _report(ctx: Context, theta, s: float) -> dict:
    out = {}
    for i, k in enumerate(HARMONICS):
        amp = math.hypot(theta[2 * i], theta[2 * i + 1]) * ctx.Y
        out[f"amplitude_{k}x"] = (amp, ctx.response_unit)
        if ctx.response_unit == "rad":
            out[f"amplitude_{k}x_arcsec"] = (amp * ARCSEC_PER_RAD, "arcsec")
        out[f"phase_{k}x"] = (math.atan2(-theta[2 * i + 1], theta[2 * i]), "rad")
    return out


EFFECT = Effect(
    id="kinematic_error",
    kinds=("torsion",),
    params=tuple(Param(f"{c}{k}", -1.0, 1.0, (0.0,)) for k in HARMONICS for c in ("a", "b")),
    contribution=_contribution,
    report=_report,
    explanation=("the elliptical wave generator deflects the flexspline twice per input turn, so the output "
                 "lags and leads the ideal ratio in a ripple at twice (and four times) the wave generator "
                 "frequency: the gear's kinematic (transmission) error"),
    applicable=lambda ctx: ctx.angle is not None,
    load_path=False,
)
