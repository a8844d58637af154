"""Steps 1-3 of the diagnosis: the noise, the candidate fits, and the selection of the models that earn a place.

1. noise: the white noise from the data's second differences; the nuisance fit and every applicable single
   effect form; the recording's ONE noise model, read beside the best single that is itself evidence; whether
   there is a mismatch at all (`Noise`);
2. candidate fits: pairs of the four best singles (each in its best forms), and the best single beside a
   series compliance where only its stiffness is off (`Candidates`);
3. selection: a pair joins only where its second effect is significant given the first and takes a structure
   the first leaves, or where the pair is the specimen's normal model (`Effect.normal_with`); a triple (fitted
   where no single or pair explains) where each effect is significant given the other two (`Selection`).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.effects import effects_for
from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.fit import NOISE_FLOOR, Fit, fit_effects, rescored
from strainwave.compare.diagnose.judge import (AMBIGUOUS_BIC, BIC_THRESHOLD, Judge, best_per_set, implausible,
                                               unresolved)
from strainwave.compare.diagnose.loop_stiffness import with_loop_prior
from strainwave.compare.diagnose.noise import noise_std
from strainwave.compare.diagnose.parallel import FitTask, fit_all
from strainwave.compare.diagnose.recording import Recording
from strainwave.compare.diagnose.structure import StructureTest, reference_noise

# a form that rereads the stated stiffness (Effect.rereads) is fitted where the other form's stiffness is more
# than this many prior sigmas off: closer, the prior costs that form under one BIC unit, about all another
# reading of the stiffness could win back (speed)
REREAD_PRIOR_SIGMAS = 1.0


@dataclass(frozen=True)
class Noise:
    """Step 1: the recording's noise, the single fits it was read beside, and whether anything is missing."""

    judge: Judge                 # white noise and the one noise model every residual is judged against
    base_fit: Fit                # the nuisance fit, scored under that noise model
    singles: tuple[Fit, ...]     # every applicable single effect form, scored under that noise model
    gof_base: StructureTest      # the nuisance fit's residual against the generic structures
    stuck: str                   # a channel stuck at its extreme while the other moves ("" if none)
    mismatch: bool

    @property
    def ranked_singles(self) -> list[Fit]:
        return best_per_set(list(self.singles))

    @property
    def best_single(self) -> Fit | None:
        ranked = self.ranked_singles
        return ranked[0] if ranked else None


@dataclass(frozen=True)
class Candidates:
    """Step 2: the pairs fitted beside the singles."""

    pairs: tuple[Fit, ...]           # pairs of the best singles, every form combination of the best pair
    offset_pairs: tuple[Fit, ...]    # the best single beside a series compliance
    triples: tuple[Fit, ...] = ()    # the best pairs beside a third effect (at most three effects at once)


@dataclass(frozen=True)
class Selection:
    """Step 3: the models that earned a place, best BIC first (each model once)."""

    candidates: tuple[Fit, ...]

    def best_or(self, base_fit: Fit) -> Fit:
        return self.candidates[0] if self.candidates else base_fit


def read_noise(rec: Recording, fit_rec: Recording, base: Baseline, ctx: Context, workers: int) -> Noise:
    """Step 1 (see the module doc)."""
    u_rel = base.uncertainty
    # noise from the residual of a free linear fit (any smooth trend is cancelled by second differences)
    sigma = max(noise_std(ctx.y - np.polyval(np.polyfit(ctx.u, ctx.y, 1), ctx.u)), NOISE_FLOOR)
    base_fit = fit_effects(ctx, (), sigma, u_rel)
    singles = _fit_singles(ctx, rec.kind.value, sigma, u_rel, workers)
    ranked = best_per_set(singles)
    # one noise model for the whole recording, every residual is judged against it: read from the residual of
    # the best-scoring single model, where a strong effect the generic structures draw only coarsely (three
    # slopes with sharp knees) no longer leaks its misfit into the noise estimate
    # ... but only a single that is itself evidence (delta BIC > 10): a flexible form that merely soaks up
    # part of a coloured wander would whiten the noise estimate and turn the rest of the wander into structure
    closest = ranked[0] if ranked and ranked[0].bic < base_fit.bic - BIC_THRESHOLD else base_fit
    noise = reference_noise(ctx, ctx.y - closest.model)
    cat_gain = _catalogue_gain(ctx, base_fit, ranked, noise)
    judge = Judge(rec, fit_rec, base, ctx, sigma, noise, workers)
    # ... but models are ranked against each other under the recording's ONE noise model (fit.bic_fixed_noise):
    # a profiled filter would let a wrong loop law buy its misfit back as "noise"
    base_fit = rescored(base_fit, ctx, noise)
    singles = [rescored(f, ctx, noise) for f in singles]
    gof_base = judge.gof(base_fit)
    # a channel stuck at its extreme while the other moves (channels.py) is a mismatch no physics explains
    stuck = judge.stuck_for(closest)
    mismatch = bool(gof_base.structured or cat_gain > BIC_THRESHOLD or stuck)
    return Noise(judge, base_fit, tuple(singles), gof_base, stuck, mismatch)


def _fit_singles(ctx: Context, kind: str, sigma: float, u_rel: float, workers: int) -> list[Fit]:
    """Every applicable effect in every model form, alone (a rereading form only where it may matter)."""
    forms = [e for e in effects_for(kind) if e.applicable(ctx)]
    singles = fit_all(ctx, [FitTask((e,)) for e in forms if e.rereads is None], sigma, u_rel, workers)
    reread = {f.effects[0].variant: f for f in singles}
    singles += fit_all(ctx, [FitTask((e,)) for e in forms if e.rereads is not None and e.rereads in reread
                             and reread[e.rereads].prior_chi2 > REREAD_PRIOR_SIGMAS ** 2], sigma, u_rel, workers)
    return [with_loop_prior(ctx, f) for f in singles]


def _catalogue_gain(ctx: Context, base_fit: Fit, ranked: list[Fit], noise) -> float:
    """BIC gain of the best plausible single under each model's own profiled filter, the most generous noise
    model (a misfit some plausible noise could have drawn is no evidence; a catalogue model is evidence only with
    physically plausible parameters), in units of the sensor's own slow power, which a filter fitted to the fine
    scales may draw short (structure.slow_power_inflation: a steep low-pass sensor; NoiseModel.flicker_inflation:
    flicker noise at the effect's own frequencies)."""
    plausible = [f for f in ranked if not implausible(ctx, f)]
    if not plausible:
        return 0.0
    extra_ln_n = (plausible[0].k - base_fit.k) * math.log(len(ctx.u))
    return noise.deflate(base_fit.bic - plausible[0].bic + extra_ln_n, base_fit.model - plausible[0].model) - extra_ln_n


def pair_forms(forms: list[Fit], k: int) -> list[Fit]:
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


def fit_candidates(noise: Noise, specimen: str = "") -> Candidates:
    """Step 2 (see the module doc); nothing beyond the singles where there is no mismatch."""
    best_single = noise.best_single
    if not noise.mismatch or best_single is None:
        return Candidates((), ())
    pairs = _pairs(noise)
    return Candidates(tuple(pairs), tuple(_offset_pairs(noise)),
                      tuple(_triples(noise, pairs, specimen)) if _needs_three(noise, pairs) else ())


def _needs_three(noise: Noise, pairs: list[Fit]) -> bool:
    """Three effects are fitted only where the best model of one or two does not already explain the recording
    (its residual is structured, or its values are implausible or unresolved): a third effect must take
    something the others leave, and this saves their fits on most recordings (speed)."""
    j = noise.judge
    best = min(list(noise.singles) + pairs, key=lambda f: f.bic)
    return bool(j.gof(best).structured or j.implausible(best) or j.unresolved(best))


# forms of each effect of a normal model of three (the best of each law class first, pair_forms)
TRIPLE_FORMS = 2
TRIPLE_LOOP_FORMS = 3    # a loop's law shapes the curve's ends as well (a Dahl exponent moved K3 by 3.5 %)


def _triples(noise: Noise, pairs: list[Fit], specimen: str) -> list[Fit]:
    """Models of three effects: the specimen's normal model (Effect.normal_model: a drive's stiffening, lost
    motion and loop, which no pair draws at once) in the two best forms of each effect that may stand in it, and
    the best pair beside a third effect of the four best singles in its best form. Started from each fitted
    pair of two of the three beside the third's single fit (alone, the third draws part of what the others draw)."""
    j = noise.judge
    pairable = sorted((f for f in noise.singles if all(e.pairs for e in f.effects)), key=lambda f: f.bic)
    by_id: dict[str, list[Fit]] = {}
    for f in pairable:
        by_id.setdefault(f.id, []).append(f)
    sets: list[tuple[Fit, ...]] = []
    for model in _normal_models(noise, specimen):
        if all(i in by_id for i in model):
            forms = [pair_forms([f for f in by_id[i] if f.effects[0].in_normal_model],
                                TRIPLE_LOOP_FORMS if by_id[i][0].effects[0].loop else TRIPLE_FORMS) for i in model]
            sets += list(itertools.product(*forms))
    top = next((p for p in sorted(pairs, key=lambda f: f.bic) if not p.at_bound), None)
    if top is not None:
        ids = {e.id for e in top.effects}
        for single in noise.ranked_singles[:4]:
            third = single.effects[0]
            # a series compliance is the partner of a stiffness off its prior (_offset_pairs), not a third effect
            if third.id in ids or single.id not in by_id or third.series_compliance \
                    or any(e.series_compliance or third.degenerate(e) for e in top.effects):
                continue
            sets.append((_single_of(top, 0, noise), _single_of(top, 1, noise), by_id[single.id][0]))
    tasks, done = [], set()
    for parts in sets:
        if any(p is None for p in parts):
            continue
        key = frozenset(p.effects[0].label for p in parts)
        if key not in done:
            done.add(key)
            tasks.append(FitTask(tuple(p.effects[0] for p in parts), _triple_starts(parts, pairs), j.noise))
    return fit_all(j.ctx, tasks, j.sigma, j.uncertainty, j.workers, then=with_loop_prior)


def _normal_models(noise: Noise, specimen: str) -> list[tuple[str, ...]]:
    """The three-effect normal models the catalogue declares for ``specimen`` (Effect.normal_model)."""
    out: list[tuple[str, ...]] = []
    for f in noise.singles:
        for sp, model in f.effects[0].normal_model:
            if sp == specimen and len(model) == 3 and tuple(model) not in out:
                out.append(tuple(model))
    return out


def _single_of(pair: Fit, k: int, noise: Noise) -> Fit | None:
    """The single fit of the form the pair's ``k``-th effect is in."""
    label = pair.effects[k].label
    return next((f for f in noise.singles if f.label == label), None)


def _triple_starts(parts: tuple[Fit, ...], pairs: list[Fit]) -> tuple[np.ndarray, ...]:
    """Starting points of a triple of the single fits ``parts``: every fitted pair of two of its forms beside the
    third's single fit, best pair first, then the three single fits side by side."""
    labels = [p.effects[0].label for p in parts]
    starts = []
    for q in sorted(pairs, key=lambda f: f.bic):
        ql = [e.label for e in q.effects]
        if len(ql) == 2 and all(x in labels for x in ql):
            thetas = dict(zip(ql, q.split_theta()))
            starts.append(np.concatenate([thetas.get(lab, p.theta) for lab, p in zip(labels, parts)]))
    starts.append(np.concatenate([p.theta for p in parts]))
    return tuple(starts[:3])


def _third_earns_place(j: Judge, t: Fit, pairs: tuple[Fit, ...], specimen: str) -> bool:
    """A triple is a candidate where EACH of its effects is significant given the other two (the pair of them, in
    its best fitted form, loses more than BIC_THRESHOLD against the triple: the pairs' own rule), no effect ends
    on a bound or stays below the noise; and, unless the three are the specimen's normal model
    (Effect.normal_model), the third takes a structure its best pair leaves."""
    if t.at_bound or j.unresolved(t):
        return False
    ids = [e.id for e in t.effects]
    best_pair = {}
    for p in pairs:
        key = frozenset(e.id for e in p.effects)
        if key not in best_pair or p.bic < best_pair[key].bic:
            best_pair[key] = p
    subs = [best_pair.get(frozenset(ids[:k] + ids[k + 1:])) for k in range(3)]
    if any(p is not None and p.bic - t.bic <= BIC_THRESHOLD for p in subs):
        return False
    known = [p for p in subs if p is not None]
    if not known:
        return False
    if t.effects[0].normal_among(t.effects[1:], specimen):
        return True
    before, after = j.gof(min(known, key=lambda f: f.bic)), j.gof(t)
    return any(s.delta_bic - (after.get(s.name).delta_bic if after.get(s.name) else min(s.delta_bic, 0.0))
               > BIC_THRESHOLD for s in before.structures)


def _pairs(noise: Noise) -> list[Fit]:
    """Beside the best single effect, each effect enters a pair in its two best forms, the best of each law class
    first (pair_forms): the form that best fits the data ALONE need not be the one that fits beside the other
    effect (a relay loop drawing part of a stiffening's misfit); pairs without the best single keep one form each
    (speed: docs/decisions/019-diagnose-speed.md). A form that competes only alone (Effect.pairs) is left out of
    every pair, and so is a pair of degenerate effects (Effect.degenerate_with)."""
    j, best_single = noise.judge, noise.best_single
    pairable = [f for f in noise.singles if all(e.pairs for e in f.effects)]
    by_id: dict[str, list[Fit]] = {}
    for f in sorted(pairable, key=lambda f: f.bic):
        by_id.setdefault(f.id, []).append(f)
    tasks: list[FitTask] = []
    for a0, b0 in itertools.combinations(noise.ranked_singles[:4], 2):
        if a0.effects[0].degenerate(b0.effects[0]):
            continue
        k = 2 if a0 is best_single else 1
        tasks += [FitTask(a.effects + b.effects, (np.concatenate([a.theta, b.theta]),), j.noise)
                  for a, b in itertools.product(pair_forms(by_id[a0.id], k), pair_forms(by_id[b0.id], k))]
    pairs = fit_all(j.ctx, tasks, j.sigma, j.uncertainty, j.workers, then=with_loop_prior)
    if not pairs:
        return pairs
    # the best pair in every other combination of model forms: a loop law that loses as a single
    # (its misfit of the stiffening costs more) may be the one that fits beside the other effect
    top = min(pairs, key=lambda f: f.bic)
    forms = {e.id: [f for f in pairable if f.id == e.id] for e in top.effects}
    (_, fa), (_, fb) = forms.items()
    done = {tuple(e.label for e in p.effects) for p in pairs}
    return pairs + fit_all(
        j.ctx, [FitTask(x.effects + y.effects, (np.concatenate([x.theta, y.theta]),), j.noise)
                for x, y in itertools.product(fa, fb)
                if (x.effects[0].label, y.effects[0].label) not in done], j.sigma, j.uncertainty, j.workers,
        then=with_loop_prior)


def _offset_pairs(noise: Noise) -> list[Fit]:
    """The best single effect beside a series compliance (Effect.series_compliance), where every form of it leaves
    noise but for a stiffness outside its prior (and the pair leaves noise).

    The compliance is then significant as a stiffness outside its prior is, by the prior's own test (the one
    that names it alone): one more linear term earns only chi2 - ln N of BIC, under the pairs' 10 at 3-4 prior
    sigmas, so a stiffening drawn to the noise on a specimen 3.5 sigmas softer read "unexplained" (heldout3's
    table with a 5 % stiffness error; a tanh stiffening 7-10 % off). Only where no form of the effect passes
    alone: one form's stiffness is biased by its misfit of the law's shape (family 2: a sinh stiffening on a
    specimen 1 prior sigma off came out 2.6 sigmas off in one form, inside the prior in another). The pair
    starts from the single's own fit with its stiffness departure moved into the compliance (the compliance
    fitted alone took the whole misfit's secant, far from the pair's optimum)."""
    j, best_single = noise.judge, noise.best_single
    offset = next((f for f in noise.singles if f.effects[0].series_compliance), None)
    forms = sorted((f for f in noise.singles if f.id == best_single.id), key=lambda f: f.bic)
    if offset is None or best_single.effects[0].series_compliance or not all(e.pairs for e in best_single.effects):
        return []
    firsts = [a for a in forms[:2] if _stiffness_only(j.gof(a))]
    if not firsts or any(not j.gof(f).structured and not j.implausible(f) and not j.unresolved(f) for f in forms):
        return []
    out = []
    for a in firsts:
        p = with_loop_prior(j.ctx, fit_effects(j.ctx, a.effects + offset.effects, j.sigma, j.uncertainty,
                                               noise=j.noise,
                                               starts=[np.concatenate([a.theta, [a.nuisance[2] - 1.0]]),
                                                       np.concatenate([a.theta, offset.theta])]))
        if a.bic - p.bic > -AMBIGUOUS_BIC and not j.gof(p).structured and not j.unresolved(p):
            out.append(p)
    return out


def _stiffness_only(g: StructureTest) -> bool:
    """The residual is noise but for a stiffness outside its prior."""
    return g.structured and all(s.name == "stiffness" for s in g.significant)


def best_plausible_per_effect(ctx: Context, singles: list[Fit]) -> dict[str, Fit]:
    """Per effect id, its best-scoring form among those with plausible values (the best form if none is).

    The first effect of a pair is judged in this form: a form that fits only with values its physics forbids
    explains nothing, so it cannot make a real second effect redundant (heldout5: an elastica form with an
    implausible second coefficient soaked up a ring's plasticity, and the plausible one-term form was named
    alone)."""
    best: dict[str, Fit] = {}
    for f in sorted(singles, key=lambda f: f.bic):
        if f.id not in best or (implausible(ctx, best[f.id]) and not implausible(ctx, f)):
            best[f.id] = f
    return best


def select(noise: Noise, cands: Candidates, specimen: str) -> Selection:
    """Step 3 (see the module doc)."""
    j = noise.judge
    candidates = list(noise.ranked_singles) + list(cands.offset_pairs)
    plausible_first = best_plausible_per_effect(j.ctx, list(noise.singles))
    candidates += [p for p in cands.pairs if _earns_place(j, p, plausible_first[p.effects[0].id], specimen)]
    candidates += [t for t in cands.triples if _third_earns_place(j, t, cands.pairs, specimen)]
    candidates.sort(key=lambda f: f.bic)
    # one model reached twice (a pair and the series compliance beside the best single) is listed once
    return Selection(tuple(f for i, f in enumerate(candidates)
                           if not any(g.label == f.label and abs(g.bic - f.bic) < 1e-6 for g in candidates[:i])))


def _earns_place(j: Judge, p: Fit, first: Fit, specimen: str) -> bool:
    """A pair is a candidate where its second effect is significant given the first (judged in its best plausible
    form) and takes a structure the first leaves; the specimen's normal pair only needs to fit better."""
    if p.at_bound:
        return False                     # an effect pinned at its bounds draws what its law cannot
    normal = p.effects[0].normal_beside(p.effects[1], specimen)
    if first.bic - p.bic <= (0.0 if normal else BIC_THRESHOLD):
        return False                     # the second effect is not significant given the first
    if j.unresolved(p):
        return False                     # one effect of the pair stays below the noise everywhere
    if normal:
        return True
    # it must explain a structure the first one cannot: some generic structure of the first's residual
    # loses more than 10 BIC units of evidence once the second effect is added
    before, after = j.gof(first), j.gof(p)
    # a structure the pair's residual no longer offers (no spectral line left) counts as fully taken
    return any(s.delta_bic - (after.get(s.name).delta_bic if after.get(s.name) else min(s.delta_bic, 0.0))
               > BIC_THRESHOLD for s in before.structures)


__all__ = ["Candidates", "Noise", "REREAD_PRIOR_SIGMAS", "Selection", "best_plausible_per_effect",
           "fit_candidates", "pair_forms", "read_noise", "select"]
