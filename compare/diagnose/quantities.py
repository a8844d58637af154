"""Step 5 of the diagnosis: the quantities a user reads. Every candidate model ranked with its BIC weight, its
parameters in physical units with standard errors (the Jacobian's, through each effect's report), its warnings;
and a friction loop's shape-free quantities (Effect.loop): its width at zero load (the hysteresis loss) from the
model and from the data, with the error a user should read, and the energy per cycle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose import loop_stiffness
from strainwave.compare.diagnose.candidates import Candidates, Noise
from strainwave.compare.diagnose.catalogue_values import CatalogueValues
from strainwave.compare.diagnose.diagnosis import Verdict
from strainwave.compare.diagnose.drive_numbers import drive_numbers
from strainwave.compare.diagnose.diagnosis import RankedEffect
from strainwave.compare.diagnose.effects.loop import ARCMIN_PER_RAD, load_path_model, loop_quantities, width_load
from strainwave.compare.diagnose.fit import Fit, lag1
from strainwave.compare.diagnose.judge import BIC_THRESHOLD
from strainwave.compare.diagnose.verdict import Answer
from strainwave.compare.diagnose.zero_load_width import full_scale_cycles, zero_load_width

BAND_MARGIN = 1.5         # a band's range (Effect.where) widened this much: its take-up's tails stay out of the width
LOSS_CONTRADICTION = 2.58  # standard errors (99 %): the data's width at zero torque overrides the loop model's


@dataclass(frozen=True)
class Reading:
    """Step 5: the ranked models and the named model's quantities."""

    effects: tuple[RankedEffect, ...]     # every candidate, the answer's model first
    quantities: dict                      # name -> (value, unit)
    catalogue: CatalogueValues | None     # the catalogue's numbers of a gear's loop (catalogue_values.py)


def read_quantities(noise: Noise, cands: Candidates, answer: Answer) -> Reading:
    """Step 5 (see the module doc)."""
    ctx, best, base_fit, n = noise.judge.ctx, answer.best, noise.base_fit, noise.judge.n
    bics = np.array([f.bic for f in answer.ranked]) if answer.ranked else np.zeros(0)
    weights = np.exp(-0.5 * (bics - bics.min())) if len(bics) else bics
    weights = weights / weights.sum() if len(bics) else weights
    effects = tuple(_ranked(ctx, f, base_fit, n, float(w), detail=i < 3)
                    for i, (f, w) in enumerate(zip(answer.ranked, weights)))
    same_set = [f for f in list(noise.singles) + list(cands.pairs) + list(cands.triples)
                if f is not best and f.id == best.id]
    quantities = _quantities(ctx, best, noise.judge.sigma, same_set) \
        if answer.mismatch and best is not base_fit else {}
    if "hysteresis_loss_arcmin" in quantities and effects:
        quantities = _with_loss_error(ctx, best, quantities, next((e for e in effects if e.model == best.label),
                                                                   effects[0]))
    rec = noise.judge.rec
    # a gear's catalogue numbers, or any torsion specimen's where the user states the rated torque: the named
    # model's; model-free only where no loop is fitted (drive_numbers.py)
    catalogue = None
    if rec.specimen == "gear" or rec.rated_torque:
        named = answer.verdict is Verdict.EXPLAINED
        if named or not any(e.loop for e in best.effects):
            ranked = next((e for e in effects if e.model == best.label), None)
            catalogue = drive_numbers(ctx, best if named else None, ranked, quantities, rec.rated_torque,
                                      noise.judge.base.curve)
    return Reading(effects, quantities, catalogue)


def _loop_width(ctx, fit: Fit) -> tuple[float, float]:
    # only what the load history draws: a ripple in the input angle is no part of the loop (and the reference
    # cycle has no angle to run it on)
    return loop_quantities(ctx, lambda c: load_path_model(c, fit))


def _quantities(ctx, fit: Fit, sigma: float, other_forms: list[Fit] = ()) -> dict:
    """Shape-free loop quantities of the model's effects (hysteresis-type effects only). ``other_forms``: fits
    of the same effects in other model forms; those the data do not reject (within 2 x BIC_THRESHOLD) give the
    width's model-form spread, an uncertainty no Jacobian of one form can show."""
    if ctx.response_unit != "rad" or not any(e.loop for e in fit.effects) or ctx.reversals < 1:
        return {}
    thetas = fit.split_theta()
    width, energy = _loop_width(ctx, fit)
    rivals = [_loop_width(ctx, f)[0] for f in other_forms if f.bic - fit.bic < 2.0 * BIC_THRESHOLD]
    spread = 0.5 * (max(rivals + [width]) - min(rivals + [width]))
    model_width, data = width, {}
    # the same width read from the data (zero_load_width.py): the residual without the model's hysteresis
    hyst = sum(e.contribution(ctx, th) for e, th in zip(fit.effects, thetas) if e.loop)
    r = ctx.y - fit.model
    # beside a band at zero load (a backlash, Effect.zero_load_band) the band is left out of the window and the
    # branches are read across it: the flanks' own sliding friction there is no part of the loop's loss
    measured = zero_load_width(ctx, ctx.y - (fit.model - hyst), sigma, lag1(r), float(np.mean(r ** 2)),
                               _bands(ctx, fit))
    source = "model"
    if measured is not None:
        w, se = measured.width * ctx.Y, measured.std_error * ctx.Y
        data = {"hysteresis_loss_data_arcmin": (w * ARCMIN_PER_RAD, "arcmin"),
                "hysteresis_loss_data_std_error_arcmin": (se * ARCMIN_PER_RAD, "arcmin")}
        # the model's width uses the whole loop (smaller variance) and stands while the data agree with it; a
        # width at zero torque the data contradict (99 %) means the loop law has the wrong shape there
        if abs(w - width) > LOSS_CONTRADICTION * se:
            width, source = w, "data"
    return {"hysteresis_loss_arcmin": (width * ARCMIN_PER_RAD, "arcmin"), "hysteresis_loss": (width, "rad"),
            "hysteresis_loss_source": (source, ""),
            "hysteresis_energy_per_cycle_Nmm_rad": (energy, "N*mm*rad"),
            "hysteresis_loss_model_arcmin": (model_width * ARCMIN_PER_RAD, "arcmin"),
            "hysteresis_loss_form_spread_arcmin": (spread * ARCMIN_PER_RAD, "arcmin"),
            "hysteresis_full_scale_cycles": (full_scale_cycles(ctx), "count"),
            "hysteresis_loss_read_at_load": (width_load(ctx) * ctx.X, ctx.load_unit), **data}


def _bands(ctx, fit: Fit) -> tuple[tuple[float, float], ...]:
    """Load ranges (normalised) of the fit's bands at zero load, widened BAND_MARGIN about their centres."""
    out = []
    for e, th in zip(fit.effects, fit.split_theta()):
        if e.zero_load_band and e.where is not None:
            for lo, hi in e.where(ctx, th)[0]:
                c, half = 0.5 * (lo + hi), 0.5 * BAND_MARGIN * (hi - lo)
                out.append((c - half, c + half))
    return tuple(out)


def _with_loss_error(ctx, fit: Fit, quantities: dict, ranked: RankedEffect) -> dict:
    """The loop width's standard error as a user should read it: the fitted form's (Jacobian, GLS), its spread
    over the model forms the data do not reject, and the sensor's wander between the two moments the width is
    read. The width at zero torque is the difference of the unloading and the loading branch at two TIMES
    half a cycle apart, so whatever the sensor drifts in between enters it in full: 2 (gamma(L) - gamma(1)),
    gamma the residual's empirical semivariogram at the lag L between consecutive zero crossings, averaged over
    the K crossings (under a wandering sensor and one full-scale cycle this, not the fit, sets how well the loss
    is known: a width was reported 3.7 of its fit errors from the truth)."""
    names = ("hysteresis_loss_arcmin", *(f"{e.id}.hysteresis_loss_arcmin" for e in fit.effects if e.loop))
    key = next((k for k in names if k in ranked.errors), None)
    fit_se = ranked.errors.get(key, 0.0) if key else 0.0
    r = ctx.y - fit.model
    crossings = np.flatnonzero(np.diff(np.sign(ctx.u)) != 0)
    lags = np.diff(crossings)
    wander = 0.0
    if len(lags):
        L = int(np.median(lags))
        if 1 < L < len(r):
            # only what builds up beyond one sample: the white part is averaged away by the fit (its share is
            # in the fit's error), a wander is not
            gamma = 0.5 * float(np.mean((r[L:] - r[:-L]) ** 2)) - 0.5 * float(np.mean(np.diff(r) ** 2))
            wander = math.sqrt(2.0 * max(gamma, 0.0) / len(lags)) * ctx.Y * ARCMIN_PER_RAD
    spread = quantities.get("hysteresis_loss_form_spread_arcmin", (0.0, ""))[0]
    total = math.sqrt(fit_se ** 2 + wander ** 2 + spread ** 2)
    return {**quantities, "hysteresis_loss_std_error_arcmin": (total, "arcmin"),
            "hysteresis_loss_wander_arcmin": (wander, "arcmin")}


def _ranked(ctx, fit: Fit, base_fit: Fit, n: int, weight: float, detail: bool = True) -> RankedEffect:
    parameters, errors, warnings = {}, {}, []
    multi = len(fit.effects) > 1
    for e, th, cov in zip(fit.effects, fit.split_theta(), fit.split_cov()):
        rep = e.report(ctx, th, fit.scale)
        for k, v in rep.items():
            parameters[f"{e.id}.{k}" if multi else k] = (float(v[0]), v[1])
        if detail and cov is not None and len(th):
            for k, se in _report_errors(ctx, e, th, cov, fit.scale, rep).items():
                errors[f"{e.id}.{k}" if multi else k] = se
        if e.plausible is not None:
            warnings.extend(e.plausible(ctx, th, fit.scale))
    scale_key = "stiffness_scale_within_prior" if not multi else "baseline.stiffness_scale"
    parameters[scale_key] = (fit.scale, "1")
    if detail and fit.cov is not None:
        errors[scale_key] = float(math.sqrt(max(fit.cov[-1, -1], 0.0)))
    if loop_stiffness.applies(fit):
        parameters.update(_loop_readings(ctx, fit, multi, errors))
        prior_sigmas = math.sqrt(fit.prior_chi2)
        stated = "the loop's secant and elastic stiffness are"
    else:
        prior_sigmas = abs(fit.scale - 1.0) / ctx.uncertainty
        stated = f"stiffness scale {fit.scale:.4g} is"
    if prior_sigmas > 3.0:
        warnings.append(f"{stated} {prior_sigmas:.1f} prior sigmas from 1 (implausible "
                        f"for a baseline uncertain by {100 * ctx.uncertainty:.0f} %)")
    warnings.extend(f"{p} ended at a bound of its plausible range" for p in fit.at_bound)
    return RankedEffect(fit.id, tuple(e.id for e in fit.effects), parameters, float(base_fit.bic - fit.bic),
                        fit.rms(n) * ctx.Y, fit.label, errors, weight, tuple(warnings))


def _loop_readings(ctx, fit: Fit, multi: bool, errors: dict) -> dict:
    """The loop's secant and elastic compliance against the baseline (loop_stiffness.readings), the only
    stiffnesses of a friction joint the data support; beside a loop, a series compliance reports the change of
    the secant (the loop's slip tangent at a reversal is no softer specimen)."""
    secant, elastic = loop_stiffness.readings(ctx, fit)
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    out = {"secant_compliance_change_percent": (100.0 * (secant - 1.0), "%"),
           "elastic_compliance_change_percent": (100.0 * (elastic - 1.0), "%"),
           "secant_stiffness": (1.0 / (secant * ctx.c0), inv)}
    series = next((e.id for e in fit.effects if e.series_compliance), None)
    if multi and series is not None:
        out[f"{series}.compliance_change_percent"] = out["secant_compliance_change_percent"]
        out[f"{series}.measured_stiffness"] = out["secant_stiffness"]
        # the offset's own parameter error is not the secant's: the secant is the whole loop's reading
        for k in (f"{series}.compliance_change_percent", f"{series}.measured_stiffness"):
            errors.pop(k, None)
    return out


def _report_errors(ctx, effect, theta, cov, s, rep) -> dict:
    """Standard errors of the reported quantities: J_rep C J_rep^T with J_rep by finite differences over
    (theta, s): a slope read from the stiffness scale (K1 = 1/(s c0)) carries the scale's error."""
    keys = [k for k, v in rep.items() if np.isfinite(v[0]) and v[1] != "count"]   # a count has no derivative
    base = np.array([rep[k][0] for k in keys])
    x = np.append(np.asarray(theta, dtype=float), s)
    J = np.zeros((len(keys), len(x)))
    for j in range(len(x)):
        h = 1e-6 * max(abs(x[j]), 1e-3)
        xh = x.copy()
        xh[j] += h
        r2 = effect.report(ctx, xh[:-1], float(xh[-1]))
        J[:, j] = (np.array([r2[k][0] for k in keys]) - base) / h
    var = np.einsum("ij,jk,ik->i", J, cov, J)
    return {k: float(math.sqrt(v)) for k, v in zip(keys, var) if np.isfinite(v) and v >= 0}



__all__ = ["LOSS_CONTRADICTION", "Reading", "read_quantities"]
