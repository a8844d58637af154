"""`strainwave diagnose`: is the recording consistent with the simulation, and if not, which physics differs?

The diagnosis runs in steps, each a function that hands the next a small record:

0. baseline (analytic or FEA, baseline.py), refused where it is 10x off the recording (check_baseline_scale);
   a long recording is fitted on a strided subsample (rows.py);
1. noise (candidates.read_noise -> `Noise`): the white noise from the data itself; the nuisance model (offsets,
   drift, stiffness within its prior) and every applicable catalogue effect in every model form fitted alone
   (fit.py); the recording's ONE noise model (structure.reference_noise), under which every model is then
   scored (fit.bic_fixed_noise); a mismatch where the residual of the nuisance fit shows structure beyond that
   noise (structure.py), where a plausible catalogue effect beats it by delta BIC > 10 even under each model's
   own profiled filter (the most generous noise), or where a channel is stuck;
2. candidate fits (candidates.fit_candidates -> `Candidates`): pairs of the four best singles, and the best
   single beside a series compliance (Effect.series_compliance) where only its stiffness is off; degenerate
   pairs (Effect.degenerate_with) are not fitted; where no single or pair explains the recording, models of
   three effects (the specimen's normal model, Effect.normal_model, and the best pair beside a third);
3. selection (candidates.select -> `Selection`): a second effect joins only if it is significant given the
   first (its own delta BIC > 10 against the single) AND removes a structure the first leaves, unless the pair
   is the specimen's normal model (Effect.normal_with);
4. verdict (verdict.decide -> `Answer`): the first model (best BIC first) whose residual passes the
   goodness-of-fit test with physical values is named: *explained*; otherwise *unexplained*, the best model kept
   as a suggestion; no mismatch: *agrees*. Each named effect meets its rival (Effect.rival: a rate-dependent
   loop, a specimen exchanged mid-test): better by > 10, *unexplained* (at one loading rate too); within
   6 BIC, ambiguous. A glitch under a verdict that calls the residual noise makes it *unexplained*;
5. quantities (quantities.read_quantities -> `Reading`): BIC weights, parameters with standard errors from the
   Jacobian, warnings (values at a bound, physically implausible), a loop's width and its error;
6. location (`Location`): where the fitted effect acts, cross-checked with the binned residual (locate.py), and
   the residual's structure in physical terms;
7. explanation: the `Diagnosis` and its text (explain.py), JSON, plot.

Before step 1, a drive's tooth ratcheting (events.py) and mains pick-up (mains.py) are named and taken out of
the response; after step 7, where the answer is *unexplained*, events in time (time_events.py: a one-way slip,
creep under a hold, a thermal drift) are taken out and the recording diagnosed again, and named where the rest
is then explained or agrees.
"""
from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from strainwave.errors import InputError
from strainwave.io_atomic import atomic_write_text, json_ready
from strainwave.compare.diagnose.baseline import Baseline, analytic_baseline, fea_baseline
from strainwave.compare.diagnose.candidates import REREAD_PRIOR_SIGMAS, Noise, fit_candidates, read_noise, select
from strainwave.compare.diagnose.context import build_context, find_segments, reversal_threshold
from strainwave.compare.diagnose.diagnosis import Diagnosis, RankedEffect, Verdict
from strainwave.compare.diagnose.events import find_jump, without_jump
from strainwave.compare.diagnose.explain import explain
from strainwave.compare.diagnose.judge import AMBIGUOUS_BIC, BIC_THRESHOLD, MIN_COMPONENT_SIGMAS
from strainwave.compare.diagnose.locate import Located, locate, locate_effect
from strainwave.compare.diagnose.mains import find_mains
from strainwave.compare.diagnose.time_events import find_thermal_drift, find_time_events
from strainwave.compare.diagnose.parallel import usable_workers
from strainwave.compare.diagnose.quantities import Reading, read_quantities
from strainwave.compare.diagnose.recording import Recording, TestFlags, parse_recording
from strainwave.compare.diagnose.rows import MAX_FIT_ROWS, subsample
from strainwave.compare.diagnose.structure import describe
from strainwave.compare.diagnose.units import Display
from strainwave.compare.diagnose.verdict import Answer, decide

# a baseline this many times off the recording's secant stiffness (either way) describes another specimen
BASELINE_OFF = 10.0


def diagnose(rec: Recording, params, baseline: str = "analytic",
             workers: int | None = None, stage: Callable[[str], None] = lambda s: None) -> tuple[Diagnosis, dict]:
    """Run the diagnosis on a parsed recording; returns the diagnosis and the arrays for the plot.

    ``workers``: processes sharing the independent fits (parallel.fit_all; the answer is the same for any
    number); None takes what the machine safely offers (parallel.usable_workers). ``stage`` hears the name of
    each stage as it starts (the CLI's progress line names it)."""
    if baseline not in ("analytic", "fea"):
        raise InputError("--baseline", baseline, "must be analytic or fea")
    stage(f"the {baseline} baseline")
    if baseline == "fea" and rec.specimen == "gear" and rec.baseline_stiffness is None and rec.unit is None:
        from strainwave.compare.diagnose.drive_baseline import curve_baseline
        base, rec = curve_baseline(rec, params, "fea")   # the FE tooth-mesh study's drive curve (issue 48, item 6)
    else:
        base = analytic_baseline(rec, params) if baseline == "analytic" else fea_baseline(rec, params)
    if base.curve is not None:
        # the baseline is the drive's curve: its bend above T1 is taken out of the twist, its first slope stays
        rec = dataclasses.replace(rec, response=rec.response - base.curve.departure_rad(rec.load * 1e-3))
    rec, events = _without_events(rec, base)
    if (mains := find_mains(rec.load, rec.response, rec.time_s)) is not None:
        # a rig's mains pick-up is reported beside the verdict, which is read without it
        rec = dataclasses.replace(rec, response=rec.response - mains.line)
        events = events + (mains.sentence(rec.response_name, rec.response_unit),)
    check_baseline_scale(rec, base)
    stage(f"fitting the effects to {rec.n} rows")
    from threadpoolctl import threadpool_limits
    # Tiny (N x 4) linear-algebra calls: BLAS threads only add overhead (docs/decisions/019-diagnose-speed.md).
    with threadpool_limits(limits=1):
        diag, arrays = _diagnose(rec, base, usable_workers() if workers is None else workers)
        drift_named = False
        # an unexplained recording keeps decision 067's reading (below): a re-clamped specimen read part-way
        # as a drift was named beside "explained"
        if diag.verdict is not Verdict.UNEXPLAINED and (drift := _drift(rec)) is not None:
            # a thermal drift, which the catalogue bends its effects to (decision 069): taken out, the rows it
            # was read on (after the first loading) diagnosed again
            stage("a thermal drift taken out: diagnosing the rest again")
            again, arrays_again = _diagnose(_after(rec, drift), base, usable_workers() if workers is None else workers)
            # named where the rest is read at least as firmly: not unexplained, and not ambiguous where the
            # first answer was not (a sensor's wander taken for a drift left a family-2 Preisach loop ambiguous)
            if again.verdict is not Verdict.UNEXPLAINED and (diag.ambiguous or not again.ambiguous):
                diag, arrays, events, drift_named = again, arrays_again, events + (drift.said,), True
        if not drift_named and diag.verdict is Verdict.UNEXPLAINED and (found := _time_events(rec)) is not None:
            # events in time the catalogue cannot draw: taken out, the rest diagnosed again; named where that
            # rest is explained or agrees (else they are not the story: a re-clamp, a rate-dependent loop
            # read part-way as a drift), the first answer standing
            stage("events in time taken out: diagnosing the rest again")
            again, arrays_again = _diagnose(dataclasses.replace(rec, response=found.response), base,
                                            usable_workers() if workers is None else workers)
            if again.verdict is not Verdict.UNEXPLAINED:
                diag, arrays, events = again, arrays_again, events + found.sentences
    return (dataclasses.replace(diag, events=events) if events else diag), arrays


def _time_events(rec: Recording):
    """time_events.find_time_events on the raw channels, the first loading (up to the first reversal) left out
    of the drift's fit."""
    u = rec.load / (float(np.max(np.abs(rec.load))) or 1.0)
    segments = find_segments(u, reversal_threshold(u))
    first = segments[0][1] if len(segments) > 1 else 0
    return find_time_events(rec.load, rec.response, rec.time_s, first, rec.response_unit)


def _drift(rec: Recording):
    """time_events.find_thermal_drift on the raw channels (decision 069), the first loading left out of its fit."""
    u = rec.load / (float(np.max(np.abs(rec.load))) or 1.0)
    segments = find_segments(u, reversal_threshold(u))
    first = segments[0][1] if len(segments) > 1 else 0
    return find_thermal_drift(rec.load, rec.response, rec.time_s, first, rec.response_unit)


def _after(rec: Recording, drift) -> Recording:
    """The rows a drift was read on (after the first loading, where it is known), the drift taken out."""
    keep = slice(drift.start_row, None)
    return dataclasses.replace(rec, load=rec.load[keep], response=(rec.response - drift.curve)[keep],
                               time_s=None if rec.time_s is None else rec.time_s[keep],
                               extra={c: v[keep] for c, v in rec.extra.items()})


def _without_events(rec: Recording, base: Baseline) -> tuple[Recording, tuple[str, ...]]:
    """A drive's tooth ratcheting (events.py: a jump of one tooth pitch at high torque) taken out of the twist
    before any fit, and named: it is the drive's own failure, not a property any catalogue effect should bend to."""
    ratio = base.geometry.get("gear_ratio")
    if rec.kind.value != "torsion" or not ratio:
        return rec, ()
    jump = find_jump(rec.load, rec.response, ratio)
    if jump is None or not jump.ratchet:
        return rec, ()
    return dataclasses.replace(rec, response=without_jump(rec.response, jump)), (jump.sentence(rec.load_name, ratio),)


def check_baseline_scale(rec: Recording, base: Baseline) -> None:
    """Refuse (exit 2) a baseline more than BASELINE_OFF times off the recording's own secant stiffness, naming
    the key that sets it: no catalogue effect turns one gear into another (a CHA curve diagnosed against the
    default shaft's simulation read "compliance change 6378 %, unexplained, check the rig")."""
    slope = float(np.polyfit(rec.load, rec.response, 1)[0])
    ratio = slope / base.compliance
    if 1.0 / BASELINE_OFF <= ratio <= BASELINE_OFF:
        return
    torsion = rec.kind.value == "torsion"
    key = "baseline_stiffness_Nmm_per_rad" if torsion else "baseline_stiffness_N_per_mm"
    unit = "N*mm/rad" if torsion else "N/mm"
    given = rec.baseline_stiffness is not None
    if slope == 0.0:
        what = (f"the {rec.response_name} does not move with the {rec.load_name} (a stuck or disconnected "
                f"channel)")
    elif (jump := _secant_jump(rec, base)) is not None:
        raise InputError(f"{rec.source}: data row {jump.row + 2}", f"{jump.step:.4g} rad",
                         f"{jump.sentence(rec.load_name)}; it sets the secant ({1.0 / slope:.4g} {unit}), without "
                         f"it the recording is within the baseline's range: the jump, not a channel's sign, is the "
                         f"departure; diagnose the rows before it, or as specimen gear where one tooth pitch is "
                         f"named and kept out of the fit")
    elif ratio < 0.0:
        what = (f"the {rec.response_name} falls as the {rec.load_name} rises (secant {1.0 / slope:.4g} {unit}): "
                f"check the sign of one channel")
    else:
        what = (f"the recording's secant stiffness {1.0 / slope:.4g} {unit} is {1.0 / ratio:.3g} x the "
                f"baseline's {1.0 / base.compliance:.4g} {unit} ({base.source}), which no catalogue effect "
                f"explains: the specimen is not the one the baseline describes")
    fix = (f"correct [test] {key} in the header (or --stiffness)" if given else
           f"set [test] {key} = <the specimen's linear stiffness, {unit}> in the header (or --stiffness), or its "
           f"dimensions in the [params.*] tables (or --params)")
    raise InputError(f"{rec.source}: [test] {key}", rec.baseline_stiffness if given else "not set",
                     f"{what}; {fix}")



def _secant_jump(rec: Recording, base: Baseline):
    """A jump of the response without which the secant would be within BASELINE_OFF of the baseline (None if
    there is no such jump): a refusal then names the jump, never the channels' sign."""
    jump = find_jump(rec.load, rec.response, base.geometry.get("gear_ratio"))
    if jump is None:
        return None
    ratio = float(np.polyfit(rec.load, without_jump(rec.response, jump), 1)[0]) / base.compliance
    return jump if 1.0 / BASELINE_OFF <= ratio <= BASELINE_OFF else None


def _diagnose(rec: Recording, base: Baseline, workers: int) -> tuple[Diagnosis, dict]:
    fit_rec = subsample(rec)
    ctx = build_context(fit_rec, base)
    noise = read_noise(rec, fit_rec, base, ctx, workers)                          # 1
    # beside a drive's own curve as the baseline, its stiffening is no longer part of a normal model to expect:
    # every effect earns its place by the general rule
    normal = rec.specimen if base.curve is None else ""
    cands = fit_candidates(noise, normal)                                          # 2
    answer = decide(noise, select(noise, cands, normal))                           # 3, 4
    reading = read_quantities(noise, cands, answer)                                # 5
    location = locate_answer(noise, answer)                                        # 6
    diag = explained(noise, answer, reading, location)                             # 7
    after = answer.best if answer.verdict is not Verdict.AGREES else noise.base_fit
    arrays = {"load": fit_rec.load, "response": fit_rec.response, "baseline": noise.base_fit.model * ctx.Y,
              "augmented": after.model * ctx.Y, "model_label": after.label}
    return diag, arrays


@dataclass(frozen=True)
class Location:
    """Step 6: where the mismatch is, and the residual's structure in physical terms."""

    located: Located
    structure: str


def locate_answer(noise: Noise, answer: Answer) -> Location:
    """Step 6: where the named effect acts (cross-checked with the binned residual), else where the baseline's
    residual is significant; and the structure of the residual the answer leaves."""
    j, base_fit = noise.judge, noise.base_fit
    ctx, variable = j.ctx, j.rec.load_name
    residual = ctx.y - base_fit.model
    if not answer.mismatch:
        located = locate(ctx, residual, j.sigma, variable, False)
    elif answer.verdict is Verdict.EXPLAINED:
        binned = locate(ctx, residual, j.sigma, variable, True)
        located = locate_effect(ctx, answer.best.effects, answer.best.split_theta(), binned, variable)
    else:
        # unexplained: where the residual the best model leaves is significant
        located = locate(ctx, residual, j.sigma, variable, True)
    dt = None if j.rec.time_s is None else float(np.median(np.diff(j.fit_rec.time_s)))
    # an unexplained verdict whose best model leaves noise (its values are implausible or its effect is not
    # resolved) describes what that model was fitted to, the baseline's residual: "consistent with the noise"
    # beside "not explained" told a user nothing
    shown = noise.gof_base if answer.verdict is Verdict.UNEXPLAINED and not answer.note \
        and not answer.gof_best.structured else answer.gof_best
    structure = describe(shown, ctx, located.description, dt, j.stride) if answer.mismatch else \
        describe(noise.gof_base, ctx, "", dt, j.stride)
    if answer.note:
        structure = f"{answer.note}; {'apart from it, ' if answer.glitch_only else ''}{structure}"
    return Location(located, structure)


def explained(noise: Noise, answer: Answer, reading: Reading, location: Location) -> Diagnosis:
    """Step 7: the diagnosis with its text."""
    j, base_fit, verdict = noise.judge, noise.base_fit, answer.verdict
    ctx, n, rec = j.ctx, j.n, j.rec
    effects = reading.effects
    after = answer.best if verdict is not Verdict.AGREES else base_fit
    shown = answer.mismatch and not answer.glitch_only
    diag = Diagnosis(recording=rec.source, kind=rec.kind.value, specimen=rec.specimen, baseline=j.base,
                     mismatch=answer.mismatch, noise_std=j.sigma * ctx.Y, located=location.located,
                     effects=effects if shown else (), rms_before=base_fit.rms(n) * ctx.Y,
                     rms_after=after.rms(n) * ctx.Y, bic_before=base_fit.bic, bic_after=after.bic,
                     explanation="", n_samples=rec.n, verdict=verdict, named=answer.named,
                     ambiguous=answer.ambiguous, runner_up=answer.runner_up, margin_bic=answer.margin,
                     suggestion=effects[0] if verdict is Verdict.UNEXPLAINED and effects and not answer.glitch_only else None,
                     structure=location.structure, gof_baseline=noise.gof_base,
                     gof_model=answer.gof_best if answer.mismatch else None, quantities=reading.quantities,
                     fitted_rows=n, noise_model=j.noise.describe(), catalogue=reading.catalogue,
                     display=Display.of(rec.units))
    return dataclasses.replace(diag, explanation=explain(diag))


def diagnose_file(path: Path, *, params_path=None, baseline: str = "analytic", json_out: Path | None = None,
                  plot_out: Path | None = None, flags: TestFlags | None = None,
                  progress: Callable[[str], None] | None = None) -> Diagnosis:
    """CLI entry: parse (``flags``: [test] keys from the command line), apply [params] overrides from the header,
    diagnose, write JSON/plot atomically. ``progress`` hears a line naming the stage every ``progress.TICK_S``
    seconds of work that takes longer (nothing for a quick one)."""
    from strainwave.progress import ticking
    now = ["reading the recording"]
    with ticking(lambda: f"diagnose {Path(path).name}: {now[0]}", progress or (lambda m: None),
                 done=f"diagnose {Path(path).name}"):
        return _diagnose_file(path, params_path, baseline, json_out, plot_out, flags, lambda s: now.__setitem__(0, s))


def _diagnose_file(path: Path, params_path, baseline: str, json_out: Path | None, plot_out: Path | None,
                   flags: TestFlags | None, stage: Callable[[str], None]) -> Diagnosis:
    from strainwave.params import load_params
    rec = parse_recording(path, flags)
    params = load_params(params_path, overrides=rec.param_overrides or None, origin=f"{path} [params]")
    diag, arrays = diagnose(rec, params, baseline, stage=stage)
    stage("writing the outputs")
    if json_out is not None:
        atomic_write_text(Path(json_out), json.dumps(json_ready(diag.to_dict()), indent=2, allow_nan=False) + "\n")
    if plot_out is not None:
        from strainwave.compare.diagnose.plot import plot_diagnosis
        title = f"{diag.recording}: {diag.verdict.value}" + (f" - {' + '.join(diag.named)}" if diag.named else "")
        shown = diag.display
        load, load_unit = shown.convert(arrays["load"], rec.load_unit)
        response, response_unit = shown.convert(arrays["response"], rec.response_unit)
        named = (lambda name, unit: f"{name} [{unit}]") if shown.spelling else (lambda name, unit: name)
        plot_diagnosis(Path(plot_out), load=load, response=response,
                       baseline=shown.convert(arrays["baseline"], rec.response_unit)[0],
                       augmented=shown.convert(arrays["augmented"], rec.response_unit)[0],
                       load_label=named(rec.load_name, load_unit),
                       response_label=named(rec.response_name, response_unit), title=title,
                       model_label=f"augmented: {arrays['model_label']}")
    return diag


__all__ = ["AMBIGUOUS_BIC", "BASELINE_OFF", "BIC_THRESHOLD", "Diagnosis", "MAX_FIT_ROWS", "MIN_COMPONENT_SIGMAS",
           "REREAD_PRIOR_SIGMAS", "RankedEffect", "Verdict", "check_baseline_scale", "diagnose", "diagnose_file"]
