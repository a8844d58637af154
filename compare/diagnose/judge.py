"""What every step of the diagnosis judges a model by: the fitted rows, their white noise, the recording's one
noise model (structure.reference_noise), each effect's own physics bounds and the size a user can see."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.channels import stuck_channel
from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.fit import Fit
from strainwave.compare.diagnose.recording import Recording
from strainwave.compare.diagnose.rows import explained_rows, stride
from strainwave.compare.diagnose.structure import MIN_COMPONENT_SIGMAS, NoiseModel, StructureTest, structure_test

BIC_THRESHOLD = 10.0       # "very strong" on the Kass-Raftery scale
AMBIGUOUS_BIC = 6.0        # "strong": closer than this, the data cannot tell the two apart
# A named effect must be of a size a user can see: its defining part (Effect.signature: a backlash's clearance,
# not its flanks' stiffening) must swing by this many white-noise sigmas over the record. The benchmarks
# call an effect measurable from 3 sigma (the "signal >= 3x noise", after the nuisance fit, which can
# halve a one-sided effect); half of that leaves a factor two for a fitted contribution short of the true one.
# Below it, many samples make a sub-noise misfit of another model form "significant": a Preisach loop drew a
# crack of open/closed stiffness ratio 0.9994 beside it (peak 1.1 sigma, delta BIC 18; family 2, all three
# seeds), and a contact-spread stiffening a backlash of 0.05 arcmin clearance at 0.1 arcmin noise (heldout4).
# MIN_COMPONENT_SIGMAS (structure.py, 1.5) also floors a line in time the load does not share.


def unresolved(ctx: Context, fit: Fit, sigma: float) -> list[str]:
    """Effects of ``fit`` whose defining part swings less than MIN_COMPONENT_SIGMAS white-noise sigmas over the
    record (its range, what a user sees: a backlash's jump 2b, the lost motion it reports; a crack's added twist
    at full load)."""
    return [e.id for e, th in zip(fit.effects, fit.split_theta())
            if float(np.ptp(e.signature_of(ctx, th))) < MIN_COMPONENT_SIGMAS * sigma]


def implausible(ctx: Context, fit: Fit) -> list[str]:
    """Physics bounds of the fitted effects (each effect's own plausibility check)."""
    return [w for e, th in zip(fit.effects, fit.split_theta()) if e.plausible is not None
            for w in e.plausible(ctx, th, fit.scale)]


def best_per_set(fits: list[Fit]) -> list[Fit]:
    """The best-scoring model form of every distinct set of effect ids, ranked by BIC."""
    best: dict[frozenset, Fit] = {}
    for f in fits:
        key = frozenset(e.id for e in f.effects)
        if key not in best or f.bic < best[key].bic:
            best[key] = f
    return sorted(best.values(), key=lambda f: f.bic)


@dataclass(frozen=True)
class Judge:
    """The recording as the steps see it, and the tests every model's residual is put to."""

    rec: Recording             # every row
    fit_rec: Recording         # the rows the models are fitted to (rows.subsample)
    base: Baseline
    ctx: Context               # fit_rec normalised
    sigma: float               # white noise, normalised
    noise: NoiseModel          # the recording's one noise model
    workers: int
    _gofs: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def uncertainty(self) -> float:
        return self.base.uncertainty

    @property
    def stride(self) -> int:
        return stride(self.rec.n)

    @property
    def n(self) -> int:
        return len(self.ctx.u)

    def gof(self, f: Fit) -> StructureTest:
        """The goodness-of-fit test of ``f``'s residual under the one noise model (memoised per fit)."""
        if id(f) not in self._gofs:
            self._gofs[id(f)] = (f, structure_test(self.ctx, self.ctx.y - f.model, self.sigma, f.prior_chi2,
                                                   self.noise))
        return self._gofs[id(f)][1]

    def implausible(self, f: Fit) -> list[str]:
        return implausible(self.ctx, f)

    def unresolved(self, f: Fit) -> list[str]:
        return unresolved(self.ctx, f, self.sigma)

    def stuck_for(self, f: Fit) -> str:
        """The load-channel check judged on what ``f`` leaves of the response (channels.stuck_channel)."""
        rec, ctx = self.rec, self.ctx
        return stuck_channel(rec.load, rec.response, self.sigma * ctx.Y, rec.load_name, rec.response_name,
                             residual=(ctx.y - f.model) * ctx.Y, stride=self.stride,
                             explained=lambda: explained_rows(rec, self.base, ctx, f))


__all__ = ["AMBIGUOUS_BIC", "BIC_THRESHOLD", "MIN_COMPONENT_SIGMAS", "Judge", "best_per_set", "implausible",
           "unresolved"]
