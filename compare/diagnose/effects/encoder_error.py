"""encoder_error: an angle encoder's interpolation error, periodic in the measured angle.

An incremental encoder interpolates between the lines of its scale from two quadrature signals; their offsets,
unequal amplitudes and phase error give an error that repeats every line pitch, at once and twice the line
frequency (Heidenhain, "Interpolation and digitizing electronics"), whatever the load or the time. The measured
twist carries it as a function of the reading itself. The line pitch is searched on the recording
(periodic.response_line, on the residual of a straight line in the load) and refined within half a Fourier bin
of the recorded range by the fit. Model (y the measured response, f the line frequency):
    y += a1 cos 2 pi f y + b1 sin 2 pi f y + a2 cos 4 pi f y + b2 sin 4 pi f y.
"""
from __future__ import annotations

import math

from strainwave.compare.diagnose.periodic import recorded_line, response_columns, response_grid
from strainwave.compare.diagnose.effects.base import Context, Effect, Param
from strainwave.compare.diagnose.effects.kinematic_error import ARCSEC_PER_RAD

def line(ctx: Context) -> tuple[float, float]:
    """(line frequency in cycles per normalised response unit, recorded span of the response)."""
    return recorded_line(ctx)


def _frequency(ctx: Context, theta) -> float:
    f, span = line(ctx)
    return f + theta[0] / span


def _contribution(ctx: Context, theta):
    return response_columns(ctx, _frequency(ctx, theta)) @ theta[1:]


def _report(ctx: Context, theta, s: float) -> dict:
    f = _frequency(ctx, theta)
    pitch = ctx.Y / f
    out = {"period": (pitch, ctx.response_unit)}
    if ctx.response_unit == "rad":
        out["lines_per_revolution"] = (2.0 * math.pi / pitch, "count")
    for i, k in enumerate((1, 2)):
        amp = math.hypot(theta[1 + 2 * i], theta[2 + 2 * i]) * ctx.Y
        out[f"amplitude_{k}x"] = (amp, ctx.response_unit)
        if ctx.response_unit == "rad":
            out[f"amplitude_{k}x_arcsec"] = (amp * ARCSEC_PER_RAD, "arcsec")
    return out


EFFECT = Effect(
    id="encoder_error",
    kinds=("torsion",),
    params=(Param("bin_offset", -0.5, 0.5, (0.0,)),) + tuple(Param(f"{c}{k}", -0.2, 0.2, (0.0,))
                                                          for k in (1, 2) for c in ("a", "b")),
    contribution=_contribution,
    report=_report,
    explanation=("the angle encoder's interpolation between the lines of its scale is imperfect (offsets, unequal "
                 "amplitudes, phase error of its quadrature signals): the reading carries an error that repeats "
                 "every line pitch of the measured angle, whatever the load: a sensor error, not the specimen"),
    applicable=lambda ctx: len(response_grid(ctx)) > 0 and line(ctx)[0] > 0.0,
    load_path=False,
)
