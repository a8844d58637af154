"""`strainwave diagnose`: is the recording consistent with the simulation, and if not, which physics differs?

1. baseline (analytic or FEA), white-noise level from the data itself;
2. fit the nuisance model (offsets, drift, stiffness within its prior) and every applicable catalogue
   effect (each in more than one model form) by least squares (fit.py);
3. goodness of fit without the catalogue (structure.py): does the residual of the nuisance fit show
   structure beyond the (possibly coloured) noise? No, and no plausible catalogue effect beats it by
   delta BIC > 10 even under each model's own profiled noise filter (the most generous noise): *agrees*;
4. from here every model is scored under the recording's ONE noise model (structure.reference_noise,
   fit.bic_fixed_noise). Name the best single effect; a second effect joins only if it is significant given
   the first (its own delta BIC > 10 against the single) AND removes a structure the first leaves; the named
   model's residual must pass the same goodness-of-fit test and its parameters must be physical:
   *explained*; otherwise *unexplained*, with the best model kept as a suggestion and the residual's
   structure described physically;
5. a named friction loop meets its rate-dependent rival (rate_loop.py: viscoelastic creep, a lagging
   channel): within 6 BIC, or at one loading rate whatever the margin, the answer is ambiguous; at several
   loading rates a rival better by > 10 makes the loop *unexplained* (friction is rate-independent); a named
   crack meets a specimen exchanged once while unloaded (exchange.py): within 6 BIC ambiguous (a test that
   visits each load sign in one stretch of time cannot tell them apart), better by > 10 *unexplained*;
6. confidence: BIC weights, margin to the runner-up (ambiguous when < 6), parameter standard errors from
   the Jacobian, parameters at a bound and physically implausible values flagged;
7. locate from the fitted effect (cross-checked with the binned residual), JSON, plot.
"""
from __future__ import annotations

import dataclasses
import enum
import itertools
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from strainwave.errors import InputError
from strainwave.io_atomic import atomic_write_text, json_ready
from strainwave.compare.diagnose import exchange, loop_stiffness, periodic, rate_loop
from strainwave.compare.diagnose.baseline import Baseline, analytic_baseline, fea_baseline
from strainwave.compare.diagnose.channels import stuck_channel
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.effects import effects_for
from strainwave.compare.diagnose.effects.loop import ARCMIN_PER_RAD, load_path_model, loop_quantities, width_load
from strainwave.compare.diagnose.explain import explain
from strainwave.compare.diagnose.fit import NOISE_FLOOR, Fit, fit_effects, lag1, rescored
from strainwave.compare.diagnose.glitches import find_glitch
from strainwave.compare.diagnose.locate import Located, locate, locate_effect
from strainwave.compare.diagnose.loop_stiffness import with_loop_prior
from strainwave.compare.diagnose.noise import noise_std
from strainwave.compare.diagnose.parallel import FitTask, fit_all, usable_workers
from strainwave.compare.diagnose.recording import Recording, parse_recording
from strainwave.compare.diagnose.structure import StructureTest, describe, fine_scale_noise, reference_noise, structure_test
from strainwave.compare.diagnose.zero_load_width import full_scale_cycles, zero_load_width

BIC_THRESHOLD = 10.0       # "very strong" on the Kass-Raftery scale
AMBIGUOUS_BIC = 6.0        # "strong": closer than this, the data cannot tell the two apart
MAX_GOF_TRIES = 16         # model forms offered the goodness-of-fit test, best BIC first (3-6 forms per effect)
LOSS_CONTRADICTION = 2.58  # standard errors (99 %): the data's width at zero torque overrides the loop model's
# A named effect must be of a size a user can see: its defining part (Effect.signature: a backlash's clearance,
# not its flanks' stiffening) must swing by this many white-noise sigmas over the record. The benchmarks
# call an effect measurable from 3 sigma (the "signal >= 3x noise", after the nuisance fit, which can
# halve a one-sided effect); half of that leaves a factor two for a fitted contribution short of the true one.
# Below it, many samples make a sub-noise misfit of another model form "significant": a Preisach loop drew a
# crack of open/closed stiffness ratio 0.9994 beside it (peak 1.1 sigma, delta BIC 18; family 2, all three
# seeds), and a contact-spread stiffening a backlash of 0.05 arcmin clearance at 0.1 arcmin noise (heldout4)
MIN_COMPONENT_SIGMAS = 1.5
# a form that rereads the stated stiffness (Effect.rereads) is fitted where the other form's stiffness is more
# than this many prior sigmas off: closer, the prior costs that form under one BIC unit, about all another
# reading of the stiffness could win back (speed)
REREAD_PRIOR_SIGMAS = 1.0
# a baseline this many times off the recording's secant stiffness (either way) describes another specimen
BASELINE_OFF = 10.0
MAX_FIT_ROWS = 2500        # model selection on a strided subsample beyond this (docs/decisions/019-diagnose-speed.md)
# A real drive's recording always shows its stiffening and its loop together: for a gear that pair is the normal
# model, not a second effect that must earn its place by more than BIC_THRESHOLD and by a structure
NORMAL_PAIRS = {"gear": frozenset({"nonlinear_stiffness", "hysteresis"})}
# Pairs that cannot be told apart: both are a pure linear compliance change.
_DEGENERATE = {frozenset({"compliance_offset", "thick_ring"})}
OFFSET = "compliance_offset"


class Verdict(str, enum.Enum):
    """The three answers, decided in this order."""
    AGREES = "agrees"              # residual after the nuisance fit is consistent with the noise
    EXPLAINED = "explained"        # a mismatch, and catalogue effect(s) bring the residual to the noise
    UNEXPLAINED = "unexplained"    # a mismatch no catalogue model brings to the noise


@dataclass(frozen=True)
class RankedEffect:
    id: str
    components: tuple[str, ...]
    parameters: dict            # name -> (value, unit)
    delta_bic: float
    rms: float                  # physical units
    model: str = ""             # id with the model variant, e.g. nonlinear_stiffness[two-slope]
    errors: dict = field(default_factory=dict)      # name -> standard error (same unit)
    weight: float = 0.0         # BIC weight among the ranked models
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        return {"id": self.id, "model": self.model or self.id, "components": list(self.components),
                "parameters": {k: {"value": v, "unit": u, "std_error": self.errors.get(k)}
                               for k, (v, u) in self.parameters.items()},
                "delta_bic": self.delta_bic, "bic_weight": self.weight, "rms": self.rms,
                "warnings": list(self.warnings)}


@dataclass(frozen=True)
class Diagnosis:
    recording: str
    kind: str
    specimen: str
    baseline: Baseline
    mismatch: bool
    noise_std: float
    located: Located
    effects: tuple[RankedEffect, ...]
    rms_before: float
    rms_after: float
    bic_before: float
    bic_after: float
    explanation: str
    n_samples: int
    verdict: Verdict = Verdict.AGREES
    named: tuple[str, ...] = ()                # catalogue ids of the named set (empty unless explained)
    ambiguous: bool = False                    # runner-up within AMBIGUOUS_BIC of the best
    runner_up: str | None = None
    margin_bic: float | None = None            # BIC(runner-up) - BIC(best)
    suggestion: RankedEffect | None = None     # best partial model when unexplained
    structure: str = ""                        # the residual's structure in physical terms
    gof_baseline: StructureTest | None = None
    gof_model: StructureTest | None = None
    quantities: dict = field(default_factory=dict)   # name -> (value, unit) of the best model
    fitted_rows: int = 0
    noise_model: str = ""                      # the recording's noise model the structures were judged against

    def __post_init__(self):
        if not isinstance(self.verdict, Verdict):
            raise ValueError(f"verdict must be a Verdict, got {self.verdict!r}")
        if self.named and self.verdict is not Verdict.EXPLAINED:
            raise ValueError("only an explained diagnosis names effects")

    @property
    def primary(self) -> str | None:
        """The named effect: the first component of the best model (components ordered by own delta BIC)."""
        return self.named[0] if self.named else None

    def quantity(self, name: str) -> float | None:
        """A quantity of the named model (None unless explained or when absent): shape-free loop quantities
        ``hysteresis_loss_arcmin`` (loop width at zero torque), ``hysteresis_energy_per_cycle_Nmm_rad``
        (closed integral of T dphi), or any reported parameter (``K1``, ``T1``, ...)."""
        if self.verdict is not Verdict.EXPLAINED:
            return None
        if name in self.quantities:
            return float(self.quantities[name][0])
        params = self.effects[0].parameters
        for key in (name, *(f"{c}.{name}" for c in self.named)):
            if key in params:
                return float(params[key][0])
        return None

    def to_dict(self) -> dict:
        return {"recording": self.recording, "kind": self.kind, "specimen": self.specimen,
                "baseline": {"source": self.baseline.source, "compliance": self.baseline.compliance,
                             "unit": self.baseline.unit, "uncertainty": self.baseline.uncertainty},
                "verdict": self.verdict.value, "named": list(self.named), "primary": self.primary,
                "ambiguous": self.ambiguous, "mismatch": self.mismatch,
                "confidence": {"runner_up": self.runner_up, "margin_bic": self.margin_bic,
                               "bic_weight": self.effects[0].weight if self.effects else None},
                "quantities": {k: {"value": v, "unit": u} for k, (v, u) in self.quantities.items()},
                "suggestion": self.suggestion.to_dict() if self.suggestion else None,
                "structure": self.structure,
                "goodness_of_fit": {"baseline": self.gof_baseline.to_dict() if self.gof_baseline else None,
                                    "model": self.gof_model.to_dict() if self.gof_model else None,
                                    "noise_model": self.noise_model},
                "noise_std": self.noise_std, "located": self.located.to_dict(),
                "effects": [e.to_dict() for e in self.effects] if self.mismatch else [],
                "fit": {"rms_before": self.rms_before, "rms_after": self.rms_after,
                        "bic_before": self.bic_before, "bic_after": self.bic_after,
                        "fitted_rows": self.fitted_rows},
                "explanation": self.explanation}

    def summary(self) -> str:
        lines = [f"{self.recording}: {self.kind} / {self.specimen}, {self.n_samples} samples; "
                 f"baseline {self.baseline.source}",
                 f"  noise std {self.noise_std:.3g} ({self.noise_model or 'white'}); rms {self.rms_before:.3g} -> {self.rms_after:.3g}; "
                 f"BIC {self.bic_before:.1f} -> {self.bic_after:.1f}",
                 f"  verdict: {self.verdict.value}" + (f" ({' + '.join(self.named)})" if self.named else "")
                 + (" - AMBIGUOUS with " + str(self.runner_up) if self.ambiguous else "")]
        if self.mismatch:
            lines.append(f"  located: {self.located.description}")
            if self.structure and self.verdict is Verdict.UNEXPLAINED:
                lines.append(f"  residual structure: {self.structure}")
            for e in self.effects[:5]:
                lines.append(f"  {e.model or e.id:<52s} delta BIC {e.delta_bic:9.1f}  weight {e.weight:.2f}")
            top = self.effects[0] if self.effects else None
            for name, (v, u) in (top.parameters.items() if top else ()):
                se = top.errors.get(name)
                lines.append(f"    {name:<38s} {v:.6g}" + (f" +/- {se:.2g}" if se is not None else "") + f" {u}")
            for w in (top.warnings if top else ()):
                lines.append(f"    warning: {w}")
        lines.append(f"  {self.explanation}")
        return "\n".join(lines)


def diagnose(rec: Recording, params, baseline: str = "analytic",
             workers: int | None = None) -> tuple[Diagnosis, dict]:
    """Run the diagnosis on a parsed recording; returns the diagnosis and the arrays for the plot.

    ``workers``: processes sharing the independent fits (parallel.fit_all; the answer is the same for any
    number); None takes what the machine safely offers (parallel.usable_workers)."""
    if baseline not in ("analytic", "fea"):
        raise InputError("--baseline", baseline, "must be analytic or fea")
    base = analytic_baseline(rec, params) if baseline == "analytic" else fea_baseline(rec, params)
    check_baseline_scale(rec, base)
    from threadpoolctl import threadpool_limits
    # Tiny (N x 4) linear-algebra calls: BLAS threads only add overhead (docs/decisions/019-diagnose-speed.md).
    with threadpool_limits(limits=1):
        return _diagnose(rec, base, usable_workers() if workers is None else workers)


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
    elif ratio < 0.0:
        what = (f"the {rec.response_name} falls as the {rec.load_name} rises (secant {1.0 / slope:.4g} {unit}): "
                f"check the sign of one channel")
    else:
        what = (f"the recording's secant stiffness {1.0 / slope:.4g} {unit} is {1.0 / ratio:.3g} x the "
                f"baseline's {1.0 / base.compliance:.4g} {unit} ({base.source}), which no catalogue effect "
                f"explains: the specimen is not the one the baseline describes")
    fix = (f"correct [test] {key} in the header" if given else
           f"set [test] {key} = <the specimen's linear stiffness, {unit}> in the header, or its dimensions in the "
           f"[params.*] tables (or --params)")
    raise InputError(f"{rec.source}: [test] {key}", rec.baseline_stiffness if given else "not set",
                     f"{what}; {fix}")


def _stride(n: int) -> int:
    return 1 if n <= MAX_FIT_ROWS else math.ceil(n / MAX_FIT_ROWS)


def _subsample(rec: Recording) -> Recording:
    """Every k-th row (acquisition order kept) so at most MAX_FIT_ROWS are fitted; white noise stays white."""
    if rec.n <= MAX_FIT_ROWS:
        return rec
    k = _stride(rec.n)
    return dataclasses.replace(rec, load=rec.load[::k], response=rec.response[::k],
                               time_s=None if rec.time_s is None else rec.time_s[::k],
                               extra={c: v[::k] for c, v in rec.extra.items()})


def _full_residual(rec: Recording, base: Baseline, ctx, fit: Fit) -> np.ndarray:
    """Data minus ``fit`` on EVERY row of ``rec`` (the fit ran on every k-th, ``ctx``), in the fit's
    normalisation: the same scales and the same map of time onto [0, 1]."""
    stride = _stride(rec.n)
    fitted = rec.time_s[::stride] if rec.time_s is not None else np.arange(0, rec.n, stride, dtype=float)
    full = build_context(rec, base, X=ctx.X, time_map=(float(fitted[0]), float(fitted[-1] - fitted[0])))
    # a line searched on the fitted rows is the fitted model's (the same normalisation), not searched again
    if periodic.CACHE_KEY in ctx.cache:
        full.cache[periodic.CACHE_KEY] = ctx.cache[periodic.CACHE_KEY]
    b0, b1, s = fit.nuisance
    model = b0 + b1 * full.t + s * full.u
    for e, th in zip(fit.effects, fit.split_theta()):
        model = model + e.contribution(full, th)
    return full.y - model


def _explained_rows(rec: Recording, base: Baseline, ctx, fit: Fit) -> np.ndarray:
    """``fit``'s response on every row of ``rec`` (physical units)."""
    if _stride(rec.n) == 1:
        return fit.model * ctx.Y
    return rec.response - _full_residual(rec, base, ctx, fit) * ctx.Y


def _best_per_set(fits: list[Fit]) -> list[Fit]:
    """The best-scoring model form of every distinct set of effect ids, ranked by BIC."""
    best: dict[frozenset, Fit] = {}
    for f in fits:
        key = frozenset(e.id for e in f.effects)
        if key not in best or f.bic < best[key].bic:
            best[key] = f
    return sorted(best.values(), key=lambda f: f.bic)


def _pair_forms(forms: list[Fit], k: int) -> list[Fit]:
    """The first ``k`` of ``forms`` (best BIC first) that a pair tries: the best form of each law class in turn
    (Effect.law_class), then the next best of any class. Two forms of one class can both fail beside another
    effect where a form of the other class fits (family 2's CHA curves with a Bouc-Wen loop: the two Preisach
    densities fitted best alone, by drawing part of the stiffening, and neither fitted beside it)."""
    picked: list[Fit] = []
    classes: set[str] = set()
    for f in forms:
        law = f.effects[0].law_class or f.effects[0].label
        if law not in classes:
            picked.append(f)
            classes.add(law)
    picked += [f for f in forms if all(f is not g for g in picked)]
    return picked[:k]


def _best_plausible_per_effect(ctx, singles: list[Fit]) -> dict[str, Fit]:
    """Per effect id, its best-scoring form among those with plausible values (the best form if none is).

    The first effect of a pair is judged in this form: a form that fits only with values its physics forbids
    explains nothing, so it cannot make a real second effect redundant (heldout5: an elastica form with an
    implausible second coefficient soaked up a ring's plasticity, and the plausible one-term form was named
    alone)."""
    best: dict[str, Fit] = {}
    for f in sorted(singles, key=lambda f: f.bic):
        if f.id not in best or (_implausible(ctx, best[f.id]) and not _implausible(ctx, f)):
            best[f.id] = f
    return best


def _diagnose(rec: Recording, base: Baseline, workers: int) -> tuple[Diagnosis, dict]:
    fit_rec = _subsample(rec)
    ctx = build_context(fit_rec, base)
    u_rel = base.uncertainty
    n = len(ctx.u)
    # noise from the residual of a free linear fit (any smooth trend is cancelled by second differences)
    sigma = max(noise_std(ctx.y - np.polyval(np.polyfit(ctx.u, ctx.y, 1), ctx.u)), NOISE_FLOOR)
    base_fit = fit_effects(ctx, (), sigma, u_rel)
    forms = [e for e in effects_for(rec.kind.value) if e.applicable(ctx)]
    singles = fit_all(ctx, [FitTask((e,)) for e in forms if e.rereads is None], sigma, u_rel, workers)
    reread = {f.effects[0].variant: f for f in singles}
    singles += fit_all(ctx, [FitTask((e,)) for e in forms if e.rereads is not None and e.rereads in reread
                             and reread[e.rereads].prior_chi2 > REREAD_PRIOR_SIGMAS ** 2], sigma, u_rel, workers)
    singles = [with_loop_prior(ctx, f) for f in singles]
    ranked_singles = _best_per_set(singles)
    best_single = ranked_singles[0] if ranked_singles else None
    # one noise model for the whole recording, every residual is judged against it: read from the residual of
    # the best-scoring single model, where a strong effect the generic structures draw only coarsely (three
    # slopes with sharp knees) no longer leaks its misfit into the noise estimate
    # ... but only a single that is itself evidence (delta BIC > 10): a flexible form that merely soaks up
    # part of a coloured wander would whiten the noise estimate and turn the rest of the wander into structure
    closest = best_single if best_single is not None and best_single.bic < base_fit.bic - BIC_THRESHOLD \
        else base_fit
    noise = reference_noise(ctx, ctx.y - closest.model)
    # that anything is missing at all must hold under the most generous noise model, each model's own profiled
    # filter (a misfit some plausible noise could have drawn is no evidence; a catalogue model is evidence
    # only with physically plausible parameters) ...
    plausible = [f for f in ranked_singles if not _implausible(ctx, f)]
    cat_gain = base_fit.bic - plausible[0].bic if plausible else 0.0
    if plausible:
        # ... and in units of the sensor's own slow power, which a filter fitted to the fine scales may draw
        # short (structure.slow_power_inflation: a steep low-pass sensor)
        extra_ln_n = (plausible[0].k - base_fit.k) * math.log(n)
        cat_gain = noise.deflate(cat_gain + extra_ln_n) - extra_ln_n
    # ... but models are ranked against each other under the recording's ONE noise model (fit.bic_fixed_noise):
    # a profiled filter would let a wrong loop law buy its misfit back as "noise"
    base_fit = rescored(base_fit, ctx, noise)
    singles = [rescored(f, ctx, noise) for f in singles]
    ranked_singles = _best_per_set(singles)
    best_single = ranked_singles[0] if ranked_singles else None
    gof_base = structure_test(ctx, ctx.y - base_fit.model, sigma, base_fit.prior_chi2, noise)
    # a channel stuck at its extreme while the other moves (channels.py) is a mismatch no physics explains
    stride = _stride(rec.n)

    def stuck_for(f: Fit) -> str:
        """The load-channel check judged on what ``f`` leaves of the response (channels.stuck_channel)."""
        return stuck_channel(rec.load, rec.response, sigma * ctx.Y, rec.load_name, rec.response_name,
                             residual=(ctx.y - f.model) * ctx.Y, stride=stride,
                             explained=lambda: _explained_rows(rec, base, ctx, f))

    stuck = stuck_for(closest)
    mismatch = bool(gof_base.structured or cat_gain > BIC_THRESHOLD or stuck)

    # pairs of the four best distinct singles; a pair is a candidate only if parsimonious (see module doc)
    pairs = []
    gofs: dict[int, StructureTest] = {}

    def gof(f: Fit) -> StructureTest:
        if id(f) not in gofs:
            gofs[id(f)] = structure_test(ctx, ctx.y - f.model, sigma, f.prior_chi2, noise)
        return gofs[id(f)]

    if mismatch and best_single is not None:
        # beside the best single effect, each effect enters a pair in its two best forms, the best of each law
        # class first (_pair_forms): the form that best fits the data ALONE need not be the one that fits beside
        # the other effect (a relay loop drawing part of a stiffening's misfit); pairs without the best single
        # keep one form each (speed: docs/decisions/019-diagnose-speed.md)
        # (a form that competes only alone, Effect.pairs, is left out of every pair)
        pairable = [f for f in singles if all(e.pairs for e in f.effects)]
        by_id: dict[str, list[Fit]] = {}
        for f in sorted(pairable, key=lambda f: f.bic):
            by_id.setdefault(f.id, []).append(f)
        tasks: list[FitTask] = []
        for a0, b0 in itertools.combinations(ranked_singles[:4], 2):
            if frozenset({a0.id, b0.id}) in _DEGENERATE:
                continue
            k = 2 if a0 is best_single else 1
            tasks += [FitTask(a.effects + b.effects, (np.concatenate([a.theta, b.theta]),), noise)
                      for a, b in itertools.product(_pair_forms(by_id[a0.id], k), _pair_forms(by_id[b0.id], k))]
        pairs = [with_loop_prior(ctx, f) for f in fit_all(ctx, tasks, sigma, u_rel, workers)]
        # the best pair in every other combination of model forms: a loop law that loses as a single
        # (its misfit of the stiffening costs more) may be the one that fits beside the other effect
        if pairs:
            top = min(pairs, key=lambda f: f.bic)
            forms = {e.id: [f for f in pairable if f.id == e.id] for e in top.effects}
            (ia, fa), (ib, fb) = forms.items()
            done = {tuple(e.label for e in p.effects) for p in pairs}
            pairs += [with_loop_prior(ctx, f) for f in fit_all(
                ctx, [FitTask(x.effects + y.effects, (np.concatenate([x.theta, y.theta]),), noise)
                      for x, y in itertools.product(fa, fb)
                      if (x.effects[0].label, y.effects[0].label) not in done], sigma, u_rel, workers)]
    candidates = list(ranked_singles)
    plausible_first = _best_plausible_per_effect(ctx, singles)
    if mismatch and best_single is not None:
        candidates += _offset_pairs(ctx, best_single, singles, gof, sigma, u_rel, noise)
    for p in pairs:
        first = plausible_first[p.effects[0].id]
        if p.at_bound:
            continue                         # an effect pinned at its bounds draws what its law cannot
        normal = rec.specimen in NORMAL_PAIRS and frozenset(e.id for e in p.effects) == NORMAL_PAIRS[rec.specimen]
        if first.bic - p.bic <= (0.0 if normal else BIC_THRESHOLD):
            continue                         # the second effect is not significant given the first
        if _unresolved(ctx, p, sigma):
            continue                         # one effect of the pair stays below the noise everywhere
        if normal:
            candidates.append(p)
            continue
        # it must explain a structure the first one cannot: some generic structure of the first's residual
        # loses more than 10 BIC units of evidence once the second effect is added
        before, after = gof(first), gof(p)
        # a structure the pair's residual no longer offers (no spectral line left) counts as fully taken
        if not any(s.delta_bic - (after.get(s.name).delta_bic if after.get(s.name) else min(s.delta_bic, 0.0))
                   > BIC_THRESHOLD for s in before.structures):
            continue
        candidates.append(p)
    candidates.sort(key=lambda f: f.bic)
    # one model reached twice (a pair and the series compliance beside the best single) is listed once
    candidates = [f for i, f in enumerate(candidates)
                  if not any(g.label == f.label and abs(g.bic - f.bic) < 1e-6 for g in candidates[:i])]
    best = candidates[0] if candidates else base_fit

    verdict = Verdict.AGREES
    named: tuple[str, ...] = ()
    note = ""                                # why a model that fits is still not an explanation
    gof_best = gof(best) if mismatch else gof_base
    if mismatch:
        # explained when some catalogue model (any of its model forms, best BIC first) beats the nuisance fit
        # by BIC (or, where the catalogue-free test found the mismatch, at least beats it), leaves a residual
        # consistent with the noise and has physically plausible parameters
        forms = sorted(singles + [p for p in candidates if len(p.effects) > 1], key=lambda f: f.bic)
        for f in forms[:MAX_GOF_TRIES]:
            gain = base_fit.bic - f.bic
            # where the catalogue-free test rejects the baseline, a model that leaves noise need not also win
            # on BIC by a margin: a stiffness 3 prior sigmas off costs the baseline about what one more
            # parameter costs the compliance offset that removes it (the two are one linear term), so BIC is
            # indifferent within AMBIGUOUS_BIC while the test has already decided (a specimen 15 % stiffer than
            # a 5 %-uncertain simulation read "unexplained" at a residual on the noise)
            if not (gain > BIC_THRESHOLD or (gof_base.structured and gain > -AMBIGUOUS_BIC)):
                break
            if not gof(f).structured and not _implausible(ctx, f) and not _unresolved(ctx, f, sigma) \
                    and not (stuck and stuck_for(f)):
                best, gof_best = f, gof(f)
                verdict = Verdict.EXPLAINED
                named = tuple(e.id for e in f.effects)
                candidates = [best] + [c for c in candidates if c is not best]
                break
        else:
            verdict = Verdict.UNEXPLAINED
        if verdict is Verdict.AGREES:
            verdict = Verdict.UNEXPLAINED
        if verdict is Verdict.UNEXPLAINED and stuck:
            note = stuck
    runner = next((f for f in candidates[1:] if frozenset(e.id for e in f.effects) != frozenset(best.id.split("+"))),
                  None)
    margin = float(runner.bic - best.bic) if runner is not None and mismatch else None
    ambiguous = bool(margin is not None and margin < AMBIGUOUS_BIC and verdict is Verdict.EXPLAINED)
    runner_label = runner.label if runner is not None and mismatch else None
    answer = _Answer(verdict, named, ambiguous, margin, runner_label, note)
    if verdict is Verdict.EXPLAINED and "hysteresis" in named:
        # the loop keeps time, not travel, across loading rates: out of the catalogue (friction is rate-independent);
        # at one loading rate a better-fitting rival is only a better SHAPE (creep may keep twisting after the
        # torque has turned, a passive friction law may not): no evidence of rate dependence
        rival_margin = _rate_rival_margin(ctx, best, sigma, u_rel, noise)
        several_rates = rate_loop.several_rates(ctx)
        answer = answer.judged_by_rival(
            rival_margin, several_rates,
            f"the loop is rate-dependent: {rate_loop.LABEL} draws it better than any friction law at the "
            f"recording's several loading rates (by {-rival_margin:.0f} BIC units), and friction does not depend on "
            f"the loading rate",
            rate_loop.LABEL + ("" if several_rates else ", at the recording's one loading rate") +
            "; a test at a second loading rate tells them apart")
    if answer.verdict is Verdict.EXPLAINED and "crack_closure" in answer.named:
        # the zero jumped where the compliance changed: no crack draws that, an exchanged specimen does; where each
        # load sign was visited before or after one instant only, a one-sided compliance is also one that changed
        # in time
        rival_margin, split = _exchange_rival_margin(ctx, best, sigma, u_rel, noise)
        row = split * _stride(rec.n) + 1
        answer = answer.judged_by_rival(
            rival_margin, True,
            f"the compliance and the zero change once, at row {row} while unloaded: {exchange.LABEL} draws the "
            f"one-sided compliance better than a breathing crack (by {-rival_margin:.0f} BIC units), and a crack "
            f"does not move the zero",
            f"{exchange.LABEL}, at row {row}; a test that visits both load signs before and after that row tells "
            f"them apart")
    verdict, named, ambiguous, margin, runner_label, note = dataclasses.astuple(answer)

    # samples the noise cannot have made (a spike, a frozen reading, a jump) under a verdict that says the
    # residual is noise (glitches.py): no smooth structure of the goodness-of-fit test draws them
    glitch_only = False
    if verdict in (Verdict.AGREES, Verdict.EXPLAINED):
        final = best if verdict is Verdict.EXPLAINED else base_fit
        if _stride(rec.n) == 1:
            glitch = find_glitch(ctx.y - final.model, noise, np.arange(rec.n), rec.response, rec.load,
                                 np.array([start for start, _, _ in ctx.segments[1:]], dtype=int))
        else:
            # a glitch on a row the fit skipped is a glitch all the same: the final model on every row, judged
            # against the noise model of that full-rate residual (the fitted rows' noise model is per stride)
            r_full = _full_residual(rec, base, ctx, final)
            glitch = find_glitch(r_full, fine_scale_noise(r_full), np.arange(rec.n), rec.response, rec.load,
                                 np.array([start * _stride(rec.n) + k for start, _, _ in ctx.segments[1:]
                                           for k in range(-_stride(rec.n), _stride(rec.n) + 1)], dtype=int))
        if glitch is not None:
            glitch_only = verdict is Verdict.AGREES
            verdict, named, ambiguous, mismatch = Verdict.UNEXPLAINED, (), False, True
            note = glitch.sentence(rec.response_name, rec.load_name) + \
                ("" if glitch_only else f"; without it {best.label} would explain the rest")
            if glitch_only:
                best, gof_best = base_fit, gof_base

    bics = np.array([f.bic for f in candidates]) if candidates else np.zeros(0)
    weights = np.exp(-0.5 * (bics - bics.min())) if len(bics) else bics
    weights = weights / weights.sum() if len(bics) else weights
    effects = tuple(_ranked(ctx, f, base_fit, n, float(w), detail=i < 3) for i, (f, w) in enumerate(zip(candidates, weights)))
    same_set = [f for f in singles + pairs if f is not best and f.id == best.id]
    quantities = _quantities(ctx, best, sigma, same_set) if mismatch and best is not base_fit else {}
    if "hysteresis_loss_arcmin" in quantities and effects:
        quantities = _with_loss_error(ctx, best, quantities, next((e for e in effects if e.model == best.label),
                                                                   effects[0]))
    located = _located(ctx, rec, best if verdict is Verdict.EXPLAINED else None, base_fit, sigma, mismatch,
                       gof_best)
    dt = None if rec.time_s is None else float(np.median(np.diff(fit_rec.time_s)))
    # an unexplained verdict whose best model leaves noise (its values are implausible or its effect is not
    # resolved) describes what that model was fitted to, the baseline's residual: "consistent with the noise"
    # beside "not explained" told a user nothing
    shown = gof_base if verdict is Verdict.UNEXPLAINED and not note and not gof_best.structured else gof_best
    structure = describe(shown, ctx, located.description, dt, stride) if mismatch else \
        describe(gof_base, ctx, "", dt, stride)
    if note:
        structure = f"{note}; {'apart from it, ' if glitch_only else ''}{structure}"
    after = best if verdict is not Verdict.AGREES else base_fit
    diag = Diagnosis(recording=rec.source, kind=rec.kind.value, specimen=rec.specimen, baseline=base,
                     mismatch=mismatch, noise_std=sigma * ctx.Y, located=located,
                     effects=effects if mismatch and not glitch_only else (), rms_before=base_fit.rms(n) * ctx.Y,
                     rms_after=after.rms(n) * ctx.Y, bic_before=base_fit.bic, bic_after=after.bic,
                     explanation="", n_samples=rec.n, verdict=verdict, named=named, ambiguous=ambiguous,
                     runner_up=runner_label, margin_bic=margin,
                     suggestion=effects[0] if verdict is Verdict.UNEXPLAINED and effects and not glitch_only else None,
                     structure=structure, gof_baseline=gof_base, gof_model=gof_best if mismatch else None,
                     quantities=quantities, fitted_rows=n, noise_model=noise.describe())
    diag = dataclasses.replace(diag, explanation=explain(diag))
    arrays = {"load": fit_rec.load, "response": fit_rec.response, "baseline": base_fit.model * ctx.Y,
              "augmented": after.model * ctx.Y, "model_label": after.label}
    return diag, arrays


def _offset_pairs(ctx, best_single: Fit, singles: list[Fit], gof, sigma: float, u_rel: float, noise) -> list[Fit]:
    """The best single effect beside a series compliance, where every form of it leaves noise but for a stiffness
    outside its prior (and the pair leaves noise).

    The compliance is then significant as a stiffness outside its prior is, by the prior's own test (the one
    that names it alone): one more linear term earns only chi2 - ln N of BIC, under the pairs' 10 at 3-4 prior
    sigmas, so a stiffening drawn to the noise on a specimen 3.5 sigmas softer read "unexplained" (heldout3's
    table with a 5 % stiffness error; a tanh stiffening 7-10 % off). Only where no form of the effect passes
    alone: one form's stiffness is biased by its misfit of the law's shape (family 2: a sinh stiffening on a
    specimen 1 prior sigma off came out 2.6 sigmas off in one form, inside the prior in another). The pair
    starts from the single's own fit with its stiffness departure moved into the compliance (the compliance
    fitted alone took the whole misfit's secant, far from the pair's optimum)."""
    offset = next((f for f in singles if f.id == OFFSET), None)
    forms = sorted((f for f in singles if f.id == best_single.id), key=lambda f: f.bic)
    if offset is None or best_single.id == OFFSET or not all(e.pairs for e in best_single.effects):
        return []
    firsts = [a for a in forms[:2] if _stiffness_only(gof(a))]
    if not firsts or any(not gof(f).structured and not _implausible(ctx, f) and not _unresolved(ctx, f, sigma)
                         for f in forms):
        return []
    out = []
    for a in firsts:
        p = with_loop_prior(ctx, fit_effects(ctx, a.effects + offset.effects, sigma, u_rel, noise=noise,
                                             starts=[np.concatenate([a.theta, [a.nuisance[2] - 1.0]]),
                                                     np.concatenate([a.theta, offset.theta])]))
        if a.bic - p.bic > -AMBIGUOUS_BIC and not gof(p).structured and not _unresolved(ctx, p, sigma):
            out.append(p)
    return out


def _stiffness_only(g: StructureTest) -> bool:
    """The residual is noise but for a stiffness outside its prior."""
    return g.structured and all(s.name == "stiffness" for s in g.significant)


def _rate_rival_margin(ctx, best: Fit, sigma: float, u_rel: float, noise) -> float:
    """BIC(rival) - BIC(best) where the rival replaces the named friction loop by linear viscoelastic creep
    (rate_loop.py), the other named effects kept: negative when a rate-dependent loop fits better."""
    keep = [(e, th) for e, th in zip(best.effects, best.split_theta()) if e.id != "hysteresis"]
    effects = tuple(e for e, _ in keep) + (rate_loop.RATE_LOOP,)
    head = [th for _, th in keep]
    starts = [np.concatenate([*head, np.array(x0)]) for x0 in ((0.05, -2.5), (0.05, -1.5))]
    rival = fit_effects(ctx, effects, sigma, u_rel, starts=starts, noise=noise)
    return float(rival.bic - best.bic)


@dataclass(frozen=True)
class _Answer:
    """The verdict as it stands while rivals of the named effect are heard."""
    verdict: Verdict
    named: tuple[str, ...]
    ambiguous: bool
    margin: float | None
    runner_up: str | None
    note: str

    def judged_by_rival(self, rival_margin: float, decisive: bool, unexplained_note: str,
                        rival_label: str) -> "_Answer":
        """A rival (a model outside the catalogue that draws the same data) fitting better by more than
        BIC_THRESHOLD, where the recording can decide between them, makes the answer unexplained; within
        AMBIGUOUS_BIC (or better) and closer than the runner-up, it makes the answer ambiguous with the rival."""
        if rival_margin < -BIC_THRESHOLD and decisive:
            return dataclasses.replace(self, verdict=Verdict.UNEXPLAINED, named=(), ambiguous=False,
                                       note=unexplained_note)
        if rival_margin < AMBIGUOUS_BIC and (self.margin is None or rival_margin < self.margin):
            return dataclasses.replace(self, ambiguous=True, margin=rival_margin, runner_up=rival_label)
        return self


def _exchange_rival_margin(ctx, best: Fit, sigma: float, u_rel: float, noise) -> tuple[float, int]:
    """(BIC(rival) - BIC(best), the rival's change row) where the rival replaces the named crack by a specimen
    exchanged once while unloaded (exchange.py), the other named effects kept: negative when it fits better."""
    keep = [(e, th) for e, th in zip(best.effects, best.split_theta()) if e.id != "crack_closure"]
    head = [th for _, th in keep]
    splits = exchange.candidate_splits(ctx)
    rivals = [(fit_effects(ctx, tuple(e for e, _ in keep) + (exchange.exchanged_at(k),), sigma, u_rel,
                           starts=[np.concatenate([*head, np.zeros(2)])], noise=noise), k) for k in splits]
    rival, split = min(rivals, key=lambda fk: fk[0].bic)
    # the change's row is chosen among len(splits) rows, each with prior 1/len(splits): -2 ln of that prior
    return float(rival.bic + 2.0 * math.log(len(splits)) - best.bic), split


def _unresolved(ctx, fit: Fit, sigma: float) -> list[str]:
    """Effects of ``fit`` whose defining part swings less than MIN_COMPONENT_SIGMAS white-noise sigmas over the
    record (its range, what a user sees: a backlash's jump 2b, the lost motion it reports; a crack's added twist
    at full load)."""
    return [e.id for e, th in zip(fit.effects, fit.split_theta())
            if float(np.ptp(e.signature_of(ctx, th))) < MIN_COMPONENT_SIGMAS * sigma]


def _implausible(ctx, fit: Fit) -> list[str]:
    """Physics bounds of the fitted effects (each effect's own plausibility check)."""
    return [w for e, th in zip(fit.effects, fit.split_theta()) if e.plausible is not None
            for w in e.plausible(ctx, th, fit.scale)]


def _loop_width(ctx, fit: Fit) -> tuple[float, float]:
    # only what the load history draws: a ripple in the input angle is no part of the loop (and the reference
    # cycle has no angle to run it on)
    return loop_quantities(ctx, lambda c: load_path_model(c, fit))


def _quantities(ctx, fit: Fit, sigma: float, other_forms: list[Fit] = ()) -> dict:
    """Shape-free loop quantities of the model's effects (hysteresis-type effects only). ``other_forms``: fits
    of the same effects in other model forms; those the data do not reject (within 2 x BIC_THRESHOLD) give the
    width's model-form spread, an uncertainty no Jacobian of one form can show."""
    if ctx.response_unit != "rad" or not any(e.id == "hysteresis" for e in fit.effects) or ctx.reversals < 1:
        return {}
    thetas = fit.split_theta()
    width, energy = _loop_width(ctx, fit)
    rivals = [_loop_width(ctx, f)[0] for f in other_forms if f.bic - fit.bic < 2.0 * BIC_THRESHOLD]
    spread = 0.5 * (max(rivals + [width]) - min(rivals + [width]))
    model_width, data = width, {}
    # the same width read from the data (zero_load_width.py): the residual without the model's hysteresis
    hyst = sum(e.contribution(ctx, th) for e, th in zip(fit.effects, thetas) if e.id == "hysteresis")
    r = ctx.y - fit.model
    # not beside a backlash: its band sits at zero torque, where the width is read, and the flanks' own
    # sliding friction would be counted as the loss (and its steep band is no quadratic)
    measured = None if any(e.id == "lost_motion" for e in fit.effects) else \
        zero_load_width(ctx, ctx.y - (fit.model - hyst), sigma, lag1(r), float(np.mean(r ** 2)))
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


def _with_loss_error(ctx, fit: Fit, quantities: dict, ranked: RankedEffect) -> dict:
    """The loop width's standard error as a user should read it: the fitted form's (Jacobian, GLS), its spread
    over the model forms the data do not reject, and the sensor's wander between the two moments the width is
    read. The width at zero torque is the difference of the unloading and the loading branch at two TIMES
    half a cycle apart, so whatever the sensor drifts in between enters it in full: 2 (gamma(L) - gamma(1)),
    gamma the residual's empirical semivariogram at the lag L between consecutive zero crossings, averaged over
    the K crossings (under a wandering sensor and one full-scale cycle this, not the fit, sets how well the loss
    is known: a width was reported 3.7 of its fit errors from the truth)."""
    key = next((k for k in ("hysteresis_loss_arcmin", "hysteresis.hysteresis_loss_arcmin") if k in ranked.errors),
               None)
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


def _located(ctx, rec, fit: Fit | None, base_fit: Fit, sigma: float, mismatch: bool, gof_best) -> Located:
    if not mismatch:
        return locate(ctx, ctx.y - base_fit.model, sigma, rec.load_name, False)
    binned = locate(ctx, ctx.y - base_fit.model, sigma, rec.load_name, True)
    if fit is None:
        # unexplained: where the residual the best model leaves is significant
        return locate(ctx, ctx.y - base_fit.model, sigma, rec.load_name, True)
    return locate_effect(ctx, fit.effects, fit.split_theta(), binned, rec.load_name)


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
    if multi and any(e.id == OFFSET for e in fit.effects):
        out[f"{OFFSET}.compliance_change_percent"] = out["secant_compliance_change_percent"]
        out[f"{OFFSET}.measured_stiffness"] = out["secant_stiffness"]
        # the offset's own parameter error is not the secant's: the secant is the whole loop's reading
        for k in (f"{OFFSET}.compliance_change_percent", f"{OFFSET}.measured_stiffness"):
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


def diagnose_file(path: Path, *, params_path=None, baseline: str = "analytic", json_out: Path | None = None,
                  plot_out: Path | None = None) -> Diagnosis:
    """CLI entry: parse, apply [params] overrides from the header, diagnose, write JSON/plot atomically."""
    from strainwave.params import load_params
    rec = parse_recording(path)
    params = load_params(params_path, overrides=rec.param_overrides or None)
    diag, arrays = diagnose(rec, params, baseline)
    if json_out is not None:
        atomic_write_text(Path(json_out), json.dumps(json_ready(diag.to_dict()), indent=2, allow_nan=False) + "\n")
    if plot_out is not None:
        from strainwave.compare.diagnose.plot import plot_diagnosis
        title = f"{diag.recording}: {diag.verdict.value}" + (f" - {' + '.join(diag.named)}" if diag.named else "")
        plot_diagnosis(Path(plot_out), load=arrays["load"], response=arrays["response"],
                       baseline=arrays["baseline"], augmented=arrays["augmented"],
                       load_label=f"{rec.load_name}", response_label=f"{rec.response_name}", title=title,
                       model_label=f"augmented: {arrays['model_label']}")
    return diag
