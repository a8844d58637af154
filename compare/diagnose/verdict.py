"""Step 4 of the diagnosis: the verdict.

Explained where some catalogue model (best BIC first, at most MAX_GOF_TRIES forms) beats the nuisance fit, leaves
a residual the goodness-of-fit test calls noise, has physically plausible values and resolved effects; else
unexplained where there is a mismatch, agrees where there is none. Then each named effect's rival (Effect.rival,
a model outside the catalogue that draws the same data) is heard: better by more than BIC_THRESHOLD, the answer
is unexplained (docs/recordings.md); within AMBIGUOUS_BIC, ambiguous. Last, samples the
noise cannot have made (glitches.py) under a verdict that says the residual is noise make it unexplained.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.candidates import Noise, Selection
from strainwave.compare.diagnose.diagnosis import Verdict
from strainwave.compare.diagnose.effects import CATALOGUE
from strainwave.compare.diagnose.effects.base import RivalReading
from strainwave.compare.diagnose.fit import Fit
from strainwave.compare.diagnose.glitches import find_glitch
from strainwave.compare.diagnose.judge import AMBIGUOUS_BIC, BIC_THRESHOLD
from strainwave.compare.diagnose.rows import full_residual
from strainwave.compare.diagnose.structure import StructureTest, fine_scale_noise

MAX_GOF_TRIES = 16         # model forms offered the goodness-of-fit test, best BIC first (3-6 forms per effect)


@dataclass(frozen=True)
class Answer:
    """The verdict and the model it rests on."""

    verdict: Verdict
    named: tuple[str, ...]
    ambiguous: bool
    margin: float | None              # BIC(runner-up) - BIC(best)
    runner_up: str | None
    note: str                         # why a model that fits is still not an explanation
    best: Fit                         # the named model (explained), the best partial one, or the nuisance fit
    gof_best: StructureTest
    ranked: tuple[Fit, ...]           # the candidates, the named model first
    mismatch: bool
    glitch_only: bool = False         # a glitch is all that departs from the baseline

    def judged_by_rival(self, rival: RivalReading) -> "Answer":
        """A rival fitting better by more than BIC_THRESHOLD makes the answer unexplained (docs/recordings.md);
        where the recording cannot tell the two apart (one loading rate) the note says what would. Within
        AMBIGUOUS_BIC and closer than the runner-up, ambiguous."""
        if rival.margin_bic < -BIC_THRESHOLD:
            note = rival.unexplained_note if rival.decisive else \
                f"{rival.label}: it fits better than the named model by {-rival.margin_bic:.0f} BIC units"
            return dataclasses.replace(self, verdict=Verdict.UNEXPLAINED, named=(), ambiguous=False,
                                       margin=rival.margin_bic, runner_up=rival.label, note=note)
        if rival.margin_bic < AMBIGUOUS_BIC and (self.margin is None or rival.margin_bic < self.margin):
            return dataclasses.replace(self, ambiguous=True, margin=rival.margin_bic, runner_up=rival.label)
        return self


def decide(noise: Noise, selection: Selection) -> Answer:
    """Step 4 (see the module doc)."""
    answer = _with_runner_up(_first_explaining(noise, selection))
    for effect in CATALOGUE.values():
        if effect.rival is not None and answer.verdict is Verdict.EXPLAINED and effect.id in answer.named:
            answer = answer.judged_by_rival(_hear(noise, answer.best, effect))
    return _with_glitch(noise, answer)


def _first_explaining(noise: Noise, selection: Selection) -> Answer:
    """The first model (best BIC first) that explains the mismatch, if any."""
    j, base_fit, gof_base = noise.judge, noise.base_fit, noise.gof_base
    candidates = selection.candidates
    best = selection.best_or(base_fit)
    if not noise.mismatch:
        return Answer(Verdict.AGREES, (), False, None, None, "", best, gof_base, candidates, False)
    forms = sorted(list(noise.singles) + [p for p in candidates if len(p.effects) > 1], key=lambda f: f.bic)
    for f in forms[:MAX_GOF_TRIES]:
        gain = base_fit.bic - f.bic
        # where the catalogue-free test rejects the baseline, a model that leaves noise need not also win
        # on BIC by a margin: a stiffness 3 prior sigmas off costs the baseline about what one more
        # parameter costs the compliance offset that removes it (the two are one linear term), so BIC is
        # indifferent within AMBIGUOUS_BIC while the test has already decided (a specimen 15 % stiffer than
        # a 5 %-uncertain simulation read "unexplained" at a residual on the noise)
        if not (gain > BIC_THRESHOLD or (gof_base.structured and gain > -AMBIGUOUS_BIC)):
            break
        if not j.gof(f).structured and not j.implausible(f) and not j.unresolved(f) \
                and not (noise.stuck and j.stuck_for(f)):
            return Answer(Verdict.EXPLAINED, tuple(e.id for e in f.effects), False, None, None, "", f, j.gof(f),
                          (f,) + tuple(c for c in candidates if c is not f), True)
    return Answer(Verdict.UNEXPLAINED, (), False, None, None, noise.stuck, best, j.gof(best), candidates, True)


def _with_runner_up(answer: Answer) -> Answer:
    """The best model of another set of effects, and how far behind it is (ambiguous within AMBIGUOUS_BIC)."""
    ids = frozenset(answer.best.id.split("+"))
    runner = next((f for f in answer.ranked[1:] if frozenset(e.id for e in f.effects) != ids), None)
    if runner is None or not answer.mismatch:
        return answer
    margin = float(runner.bic - answer.best.bic)
    return dataclasses.replace(answer, margin=margin, runner_up=runner.label,
                               ambiguous=bool(margin < AMBIGUOUS_BIC and answer.verdict is Verdict.EXPLAINED))


def _hear(noise: Noise, best: Fit, effect) -> RivalReading:
    """``effect``'s rival in place of it, the other named effects kept."""
    j = noise.judge
    keep = [(e, th) for e, th in zip(best.effects, best.split_theta()) if e.id != effect.id]
    return effect.rival(j.ctx, tuple(e for e, _ in keep), [th for _, th in keep], best.bic, j.sigma,
                        j.uncertainty, j.noise, j.stride)


def _with_glitch(noise: Noise, answer: Answer) -> Answer:
    """Samples the noise cannot have made (a spike, a frozen reading, a jump) under a verdict that says the
    residual is noise (glitches.py): no smooth structure of the goodness-of-fit test draws them."""
    if answer.verdict not in (Verdict.AGREES, Verdict.EXPLAINED):
        return answer
    j, rec, ctx = noise.judge, noise.judge.rec, noise.judge.ctx
    final = answer.best if answer.verdict is Verdict.EXPLAINED else noise.base_fit
    k = j.stride
    if k == 1:
        glitch = find_glitch(ctx.y - final.model, j.noise, np.arange(rec.n), rec.response, rec.load,
                             np.array([start for start, _, _ in ctx.segments[1:]], dtype=int))
    else:
        # a glitch on a row the fit skipped is a glitch all the same: the final model on every row, judged
        # against the noise model of that full-rate residual (the fitted rows' noise model is per stride)
        r_full = full_residual(rec, j.base, ctx, final)
        glitch = find_glitch(r_full, fine_scale_noise(r_full), np.arange(rec.n), rec.response, rec.load,
                             np.array([start * k + i for start, _, _ in ctx.segments[1:]
                                       for i in range(-k, k + 1)], dtype=int))
    if glitch is None:
        return answer
    glitch_only = answer.verdict is Verdict.AGREES
    note = glitch.sentence(rec.response_name, rec.load_name) + \
        ("" if glitch_only else f"; without it {answer.best.label} would explain the rest")
    out = dataclasses.replace(answer, verdict=Verdict.UNEXPLAINED, named=(), ambiguous=False, mismatch=True,
                              note=note, glitch_only=glitch_only)
    return dataclasses.replace(out, best=noise.base_fit, gof_best=noise.gof_base) if glitch_only else out


__all__ = ["Answer", "MAX_GOF_TRIES", "decide"]
