"""encoder_error: an angle encoder's interpolation error, periodic in the measured angle.

An incremental encoder interpolates between the lines of its scale from two quadrature signals; their offsets,
unequal amplitudes and phase error give an error that repeats every line pitch, at once and twice the line
frequency (Heidenhain, "Interpolation and digitizing electronics"), whatever the load or the time. The measured
twist carries it as a function of the reading itself. The line pitch is searched on the recording
(periodic.response_line, on the residual of a straight line in the load) and refined within half a Fourier bin
of the recorded range by the fit. Model (y the measured response, f the line frequency):
    y += a1 cos 2 pi f y + b1 sin 2 pi f y + a2 cos 4 pi f y + b2 sin 4 pi f y.
The error is a fraction of the line pitch P: the position within a signal period is atan2 of the two signals, so
an offset delta (of the amplitude) errs by up to delta P/(2 pi) at once the line frequency, an amplitude mismatch
eps by eps P/(4 pi) and a phase error phi by phi P/(4 pi) at twice it. Signals that still decode (their Lissajous
figure encloses its centre: delta < 1, eps < 1, phi < pi/2) bound the errors by P/(2 pi) and P/8.
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


# the largest interpolation errors of quadrature signals that still decode, per harmonic, in line pitches
MAX_ERROR_PITCHES = {1: 1.0 / (2.0 * math.pi), 2: 1.0 / 8.0}


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    """An "error" larger than the decodable bound is not an interpolation error: a curve in the load fitted by a
    line pitch near the noise (the noise correlates with the phase of its own reading there)."""
    pitch = 1.0 / _frequency(ctx, theta)
    out = []
    for i, k in enumerate((1, 2)):
        amp = math.hypot(theta[1 + 2 * i], theta[2 + 2 * i])
        if amp > MAX_ERROR_PITCHES[k] * pitch:
            out.append(f"interpolation error {amp * ctx.Y:.3g} {ctx.response_unit} at {k}x the line frequency is "
                       f"{amp / pitch:.2g} line pitches ({pitch * ctx.Y:.3g} {ctx.response_unit}); quadrature "
                       f"signals that still decode err by at most {MAX_ERROR_PITCHES[k]:.3g} of a pitch")
    return out


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
    plausible=_plausible,
)
