"""ONE set of a drive's catalogue numbers: K1, K2, K3, T1, T2, hysteresis loss and lost motion.

Harmonic Drive reads them on a +/- rated torque cycle (catalogue_values.py has the definitions). Where the
diagnosis has named a model, the numbers are that model's (the stiffening's K1..T2 with their errors; the loop's
width as the quantities report it; the lost motion read on the named model's own loop at +/-4 % of the rated
torque), so they agree with the fit by construction. The model-free branch fit (catalogue_values.py) stands only
where no loop is fitted (no model, or one without a friction loop). Numbers are given only for a +/- cycle (both
load signs reached, each within PM_CYCLE of the largest, and at least two reversals), never negative: a negative
reading is left out with a warning that the recording does not resolve it.
"""
from __future__ import annotations

import numpy as np

from strainwave.compare.diagnose.catalogue_values import LOST_MOTION_FRACTION, SOURCE, CatalogueValues, \
    catalogue_values
from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.effects.loop import ARCMIN_PER_RAD, load_path_model, reference_cycle
from strainwave.compare.diagnose.fit import Fit

PM_CYCLE = 0.8          # each load sign must reach this fraction of the largest load: a +/- T cycle
_STIFFENING = ("K1", "K2", "K3", "T1", "T2")


def pm_cycle(ctx: Context) -> bool:
    """Both load signs reached (each within PM_CYCLE of the largest) and at least two reversals."""
    return bool(ctx.u.max() >= PM_CYCLE and ctx.u.min() <= -PM_CYCLE and ctx.reversals >= 2)


def drive_numbers(ctx: Context, fit: Fit | None, ranked, quantities: dict,
                  rated_torque: float | None, curve=None) -> CatalogueValues | None:
    """The catalogue's numbers (see the module doc); ``ranked`` the named model's RankedEffect, ``quantities``
    its loop quantities; ``fit`` None where nothing is named; ``curve`` the baseline's DriveCurve (a catalogue
    unit's), whose bend was taken out of the twist before the fit."""
    if ctx.response_unit != "rad" or not pm_cycle(ctx):
        return None
    if fit is None or not any(e.loop for e in fit.effects):
        if curve is not None:
            return None                        # the model-free reading would read the curve with its bend removed
        free = catalogue_values(ctx, rated_torque)
        return None if free is None else _non_negative(free.values, list(free.warnings), free.source)
    values: dict = {}
    multi = len(fit.effects) > 1
    inv = f"{ctx.load_unit}/{ctx.response_unit}"
    warnings = []
    if curve is not None:
        values.update(_unit_slopes(ctx, fit, curve, warnings))
    elif any(e.id == "nonlinear_stiffness" for e in fit.effects):
        for name in _STIFFENING:
            key = f"nonlinear_stiffness.{name}" if multi else name
            if key in ranked.parameters:
                v, unit = ranked.parameters[key]
                values[name] = (v, ranked.errors.get(key, 0.0), unit)
    else:
        k = 1.0 / (fit.scale * ctx.c0)           # no stiffening named: the curve is the line
        se = k * float(np.sqrt(max(fit.cov[-1, -1], 0.0))) / fit.scale if fit.cov is not None else 0.0
        values.update({n: (k, se, inv) for n in ("K1", "K2", "K3")})
    if "hysteresis_loss_arcmin" in quantities:
        loss = quantities["hysteresis_loss_arcmin"][0]
        se = quantities.get("hysteresis_loss_std_error_arcmin", (0.0,))[0]
        values["hysteresis_loss_arcmin"] = (loss, se, "arcmin")
    if rated_torque is not None:
        values["lost_motion_arcmin"] = _lost_motion(ctx, fit, rated_torque)
    amplitude = float(np.max(np.abs(ctx.u))) * ctx.X
    values["loop_amplitude"] = (amplitude, 0.0, ctx.load_unit)
    if rated_torque is not None and LOST_MOTION_FRACTION * rated_torque > amplitude:
        warnings.append("the lost-motion torque lies beyond the recorded range: the lost motion is extrapolated")
    return _non_negative(values, warnings, f"{SOURCE}; read from the named model {fit.label}")


def _unit_slopes(ctx: Context, fit: Fit, curve, warnings: list[str]) -> dict:
    """A catalogue unit's slopes as the recording scales them (K_i / s; T1, T2 the unit's), where no stiffening
    departs from its curve; beside a named stiffening the slopes are that departure's (its parameters)."""
    if any(e.id == "nonlinear_stiffness" for e in fit.effects):
        warnings.append("the named stiffening departs from the unit's curve: K1..T2 are not read (see its "
                        "parameters)")
        return {}
    inv = f"{ctx.load_unit}/{ctx.response_unit}"
    rel = float(np.sqrt(max(fit.cov[-1, -1], 0.0))) / fit.scale if fit.cov is not None else 0.0
    out = {}
    for name in ("K1", "K2", "K3"):
        k = getattr(curve, f"{name}_Nm_per_rad") * 1e3 / fit.scale          # N*mm/rad
        out[name] = (k, k * rel, inv)
    out["T1"] = (curve.T1_Nm * 1e3, 0.0, ctx.load_unit)
    out["T2"] = (curve.T2_Nm * 1e3, 0.0, ctx.load_unit)
    warnings.append("T1, T2 are the unit's: the recording follows its curve, scaled by the fitted stiffness")
    return out


def _lost_motion(ctx: Context, fit: Fit, rated: float) -> tuple[float, float, str]:
    """Unloading branch at +4 % of the rated torque minus loading branch at -4 %, on the named model's own loop
    (reference cycle over the recording's range), with its error from the fit's covariance of (theta, s)."""
    ref, start = reference_cycle(ctx)
    a = LOST_MOTION_FRACTION * rated / ctx.X

    def reading(theta: np.ndarray, s: float) -> float:
        trial = Fit(fit.effects, theta, (0.0, 0.0, s), fit.model, fit.rss, fit.bic, fit.k)
        y = s * ref.u + load_path_model(ref, trial)
        u, y = ref.u[start:], y[start:]
        k = int(np.argmin(u))
        down = float(np.interp(a, u[:k + 1][::-1], y[:k + 1][::-1]))
        up = float(np.interp(-a, u[k:], y[k:]))
        return (down - up) * ctx.Y * ARCMIN_PER_RAD

    x = np.append(np.asarray(fit.theta, dtype=float), fit.scale)
    value = reading(x[:-1], float(x[-1]))
    if fit.cov is None or fit.cov.shape[0] != len(x):
        return value, 0.0, "arcmin"
    J = np.zeros(len(x))
    for j in range(len(x)):
        h = 1e-6 * max(abs(x[j]), 1e-3)
        xh = x.copy()
        xh[j] += h
        J[j] = (reading(xh[:-1], float(xh[-1])) - value) / h
    return value, float(np.sqrt(max(J @ fit.cov @ J, 0.0))), "arcmin"


def _non_negative(values: dict, warnings: list[str], source: str) -> CatalogueValues:
    """Negative or non-finite numbers left out, each with a warning (a stiffness, a torque, a loss or a lost
    motion is never negative: a negative reading means the recording does not resolve it)."""
    kept = {}
    for name, (v, se, unit) in values.items():
        if np.isfinite(v) and v >= 0.0:
            kept[name] = (float(v), float(se), unit)
        else:
            warnings.append(f"{name} is not resolved by this recording (its reading {v:.3g} {unit} is not a "
                            f"non-negative number)")
    return CatalogueValues(kept, tuple(warnings), source)


__all__ = ["PM_CYCLE", "drive_numbers", "pm_cycle"]
