"""The rival of a one-sided compliance: the specimen (or its clamping) changed once, mid-test, while unloaded.

Not a catalogue effect (it is never named): it is what a breathing crack could be instead. A crack open under
one load sign adds compliance on that side of zero load only. A specimen exchanged for another, or re-clamped,
changes its compliance and its zero once, between two stretches of the test. Where each load sign is visited in
one stretch of time only (a single cycle: up to +T, then down to -T), the two are the same curve: a compliance
that differs between the two halves of the load range is also one that differs between the two halves of the
record. A test that visits both load signs before and after the change tells them apart; one that does not
cannot, and the diagnosis must say so (family 2 seed 2: two spliced recordings of one cycle each, named
crack_closure without doubt).

Model: y += (d u + j) [k >= k0], the compliance change d (normalised) and the zero's jump j, fitted by least
squares at each candidate k0. The change happens while the specimen is unloaded, so k0 runs over the interior
load-zero crossings (and the record's middle where the load never crosses zero).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param, RivalReading

LABEL = "a specimen exchanged or re-clamped mid-test (its compliance and zero changed once, while unloaded)"
# a change in the first or last tenth of the record is an end effect (run-in, unloading), not an exchange
EDGE = 0.1
MAX_CROSSINGS = 6
NEAR = 5
UNLOADED = 0.05


def candidate_splits(ctx: Context) -> list[int]:
    """First rows after the change: around each interior load-zero crossing (EDGE..1-EDGE of the record, nearest
    the middle first), every row within NEAR rows whose load is within UNLOADED of full scale (a rig is unloaded
    for a moment, not for one sample: the change may fall a few rows either side of the crossing)."""
    n = len(ctx.u)
    lo, hi = int(EDGE * n), int((1.0 - EDGE) * n)
    sign = np.sign(ctx.u)
    cross = [k + 1 for k in range(max(lo - 1, 0), min(hi, n - 1)) if sign[k] != sign[k + 1] and sign[k] != 0]
    if not cross:
        cross = [n // 2]
    cross.sort(key=lambda k: abs(k - n // 2))
    quiet = np.abs(ctx.u) <= UNLOADED * float(np.max(np.abs(ctx.u)) or 1.0)
    out: list[int] = []
    for c in cross[:MAX_CROSSINGS]:
        near = [k for k in range(max(c - NEAR, 1), min(c + NEAR + 1, n)) if quiet[k] or quiet[k - 1]]
        out += [k for k in (near or [c]) if k not in out]
    return out


def _contribution(split: int):
    def contribution(ctx: Context, theta) -> np.ndarray:
        after = np.arange(len(ctx.u)) >= split
        return after * (theta[0] * ctx.u + theta[1])
    return contribution


def _report(ctx: Context, theta, s: float) -> dict:
    return {"compliance_change_fraction": (float(theta[0]), "1"), "zero_jump": (float(theta[1]) * ctx.Y,
                                                                              ctx.response_unit)}


_EXCHANGE = Effect(
    id="specimen_exchange",
    kinds=("torsion", "ring_compression"),
    params=(Param("d", -0.9, 10.0, (0.0,)), Param("j", -1.0, 1.0, (0.0,))),
    contribution=_contribution(0),
    report=_report,
    explanation=LABEL,
)


def exchanged_at(split: int) -> Effect:
    """The exchange rival with its change at sample ``split`` (of the fitted rows)."""
    return dataclasses.replace(_EXCHANGE, contribution=_contribution(split), variant=f"at {split}")


def rival(ctx: Context, kept: tuple[Effect, ...], heads: list, best_bic: float, sigma: float, uncertainty: float,
          noise, stride: int) -> RivalReading:
    """The named crack replaced by a specimen exchanged once while unloaded, the other named effects ``kept``:
    the zero jumped where the compliance changed, which no crack draws; where each load sign was visited before
    or after one instant only, a one-sided compliance is also one that changed in time."""
    from strainwave.compare.diagnose.fit import fit_effects       # fit imports the catalogue, which names this
    splits = candidate_splits(ctx)
    fits = [(fit_effects(ctx, kept + (exchanged_at(k),), sigma, uncertainty,
                         starts=[np.concatenate([*heads, np.zeros(2)])], noise=noise), k) for k in splits]
    fitted, split = min(fits, key=lambda fk: fk[0].bic)
    # the change's row is chosen among len(splits) rows, each with prior 1/len(splits): -2 ln of that prior
    margin = float(fitted.bic + 2.0 * math.log(len(splits)) - best_bic)
    row = split * stride + 1
    return RivalReading(
        margin, True,
        f"the compliance and the zero change once, at row {row} while unloaded: {LABEL} draws the one-sided "
        f"compliance better than a breathing crack (by {-margin:.0f} BIC units), and a crack does not move the zero",
        f"{LABEL}, at row {row}; a test that visits both load signs before and after that row tells them apart")


__all__ = ["EDGE", "LABEL", "MAX_CROSSINGS", "NEAR", "UNLOADED", "candidate_splits", "exchanged_at", "rival"]
