"""A rig check after the fit: samples the recording's noise cannot have made.

Every structure the goodness-of-fit test looks for is smooth (a function of the load, of the branch, of
time, a ripple); one sample 30 noise sigmas off, or a reading that froze for 20 samples and then caught up,
changes the residual's variance by a few tens of percent and no smooth structure draws it, so the test
passed both as "consistent with the noise" (the most dangerous answer, on a rig's everyday faults).

The check is on the innovations of the final residual: the residual whitened by the recording's ONE noise
model (structure.NoiseModel), in units of its innovation standard deviation. Gaussian noise of any colour the
model describes leaves standard-normal innovations, so the largest of m exceeds the Bonferroni point
z = Phi^-1(1 - ALPHA / 2m) with probability ALPHA per recording (z = 5.0 at m = 2,000, 5.6 at 20,000).
But the model is right only up to its form: at a sharp feature of the data (a backlash edge, the knee where
a stiff slip element starts to slide) a model of the right physics and a slightly different form leaves a
departure of a few samples, and at high signal-to-noise a large one (measured: 6.0 innovation sigmas at a
backlash edge at signal 30, 5.0 at a Maxwell-slip knee at signal 25, both read as glitches at the Bonferroni
point). A glitch worth stopping a test for is gross, so the threshold is the larger of the Bonferroni point
and GROSS_SIGMAS; smaller departures are left to the goodness-of-fit test.
What exceeds it is named from the raw readings, not guessed from the physics:

- a frozen reading: the response repeats one value exactly for MIN_FROZEN or more samples (a noisy,
  unquantised channel never does) while the load moves, and the sample flagged lies in or just after that run;
- a spike: the flagged sample is off its neighbours on both sides, which agree with each other;
- otherwise a jump: the level changes between two samples and stays (a slip in the clamp, a stick-slip step,
  a sensor glitch that offsets the channel), located where the mean levels of the STEP_SPAN samples either
  side differ most.

With more than rows.MAX_FIT_ROWS rows the fit sees every k-th row; the check sees every row (the final
model evaluated on all of them, the noise model read from that full-rate residual's fine scales).
"""
from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from scipy.stats import norm

ALPHA = 1e-3          # family-wise false-alarm probability per recording (Gaussian innovations)
GROSS_SIGMAS = 10.0   # innovation sigmas: beyond the form misfit of a right model at a sharp feature (<= 6)
MIN_FROZEN = 5        # identical consecutive readings that count as a frozen channel
NEIGHBOURS = 3        # samples each side that a spike's neighbours are read from
STEP_SPAN = 10        # samples each side whose mean levels locate a jump
_IMPULSE = 4000       # samples of the noise filter's impulse response (a pole at 0.998 decays to 3e-4)


class GlitchKind(str, enum.Enum):
    FROZEN = "frozen reading"
    SPIKE = "spike"
    JUMP = "jump"


@dataclass(frozen=True)
class Glitch:
    kind: GlitchKind
    sample: int              # 1-based sample number in the recording
    sigmas: float            # the largest innovation, in innovation standard deviations
    threshold: float         # the Bonferroni point it exceeds
    count: int               # innovations beyond the threshold
    run: tuple[int, int] | None = None   # 1-based first and last sample of a frozen run

    def sentence(self, response_name: str, load_name: str) -> str:
        where = f"sample {self.sample}"
        size = (f"{self.sigmas:.0f} noise sigmas (beyond {self.threshold:.0f}: more than the noise model's "
                f"largest innovation at 99.9 % probability and than a right model of another form leaves at a "
                f"sharp feature)")
        if self.kind is GlitchKind.FROZEN:
            a, b = self.run
            what = (f"the {response_name} reading repeats one value for {b - a + 1} samples ({a}-{b}) while "
                    f"{load_name} moves, then catches up: a frozen reading (a dropped sensor or acquisition "
                    f"channel), not the specimen")
        elif self.kind is GlitchKind.SPIKE:
            what = (f"one reading off its neighbours, which agree with each other: a spike (electrical "
                    f"interference, a corrupted sample), not the specimen")
        else:
            what = (f"the {response_name} level changes between two samples and stays: a jump (a slip in the "
                    f"clamp or joint, a stick-slip step, a sensor offset)")
        more = f"; {self.count} samples in all beyond that point" if self.count > 1 else ""
        return f"{where} departs from the model by {size}: {what}{more}"


def _frozen_runs(response: np.ndarray, load: np.ndarray, load_step: float) -> list[tuple[int, int]]:
    """0-based (first, last) of runs of >= MIN_FROZEN identical readings during which the load moves by more
    than MIN_FROZEN typical load steps (a hold at constant load legitimately repeats a quantised reading)."""
    same = np.concatenate([[False], np.diff(response) == 0.0])
    out, k, n = [], 1, len(response)
    while k < n:
        if same[k]:
            a = k - 1
            while k < n and same[k]:
                k += 1
            b = k - 1
            if b - a + 1 >= MIN_FROZEN and float(np.ptp(load[a:b + 1])) > MIN_FROZEN * load_step:
                out.append((a, b))
        k += 1
    return out


def _side_lines(residual: np.ndarray, k: int) -> tuple[float, float] | None:
    """The residual at sample k extrapolated by straight lines through the STEP_SPAN samples before it and the
    STEP_SPAN after it (None where either side is short)."""
    a, b = residual[max(k - STEP_SPAN, 0):k], residual[k + 1:k + 1 + STEP_SPAN]
    if len(a) < 3 or len(b) < 3:
        return None
    left = np.polyval(np.polyfit(np.arange(k - len(a), k), a, 1), k)
    right = np.polyval(np.polyfit(np.arange(k + 1, k + 1 + len(b)), b, 1), k)
    return float(left), float(right)


def _off_both_sides(residual: np.ndarray, k: int) -> float:
    """How far sample k is off BOTH sides' lines (a spike is; a corner lies on both)."""
    lines = _side_lines(residual, k)
    return math.inf if lines is None else min(abs(residual[k] - lines[0]), abs(residual[k] - lines[1]))


def _step_across(residual: np.ndarray, k: int) -> float:
    """The level step between the two sides' lines at sample k (a jump has one; a corner has none)."""
    lines = _side_lines(residual, k)
    return math.inf if lines is None else abs(lines[1] - lines[0])


def _step_weights() -> np.ndarray:
    """w with w @ residual[k - STEP_SPAN:k + STEP_SPAN + 1] = right line - left line at k (_side_lines, full
    sides): zero on a constant and on a straight line, so a random walk's step has a finite variance too."""
    def extrapolation(x: np.ndarray, x0: float) -> np.ndarray:
        # least-squares line through (x, r) evaluated at x0, as weights on r
        d = x - x.mean()
        return 1.0 / len(x) + (x0 - x.mean()) * d / float(d @ d)
    left = extrapolation(np.arange(-STEP_SPAN, 0, dtype=float), 0.0)
    right = extrapolation(np.arange(1, STEP_SPAN + 1, dtype=float), 0.0)
    return np.concatenate([-left, [0.0], right])


def step_noise_std(noise) -> float:
    """Standard deviation of ``_step_across``'s signed step on noise alone, under the recording's noise model:
    sqrt(innovation_var * sum((w * h)^2)), h the noise filter's impulse response. White noise gives 0.97
    sigma; a resonant or low-pass sensor swings one side's line against the other's by many white sigmas
    (heldout6: AR(2) 1.65, -0.76 behind a Bouc-Wen loop at 50x read "a jump")."""
    from scipy.signal import lfilter
    impulse = np.zeros(_IMPULSE)
    impulse[0] = 1.0
    h = lfilter(noise.a, noise.b, impulse)
    return math.sqrt(noise.innovation_var * float(np.sum(np.convolve(_step_weights(), h) ** 2)))


def find_glitch(residual: np.ndarray, noise, rows: np.ndarray, response: np.ndarray,
                load: np.ndarray, reversals: np.ndarray | None = None) -> Glitch | None:
    """The worst sample the noise model cannot explain, or None.

    ``residual``: data minus the final model on the fitted rows; ``noise``: the recording's noise model;
    ``rows``: the fitted rows' 0-based indices in the recording; ``response``, ``load``: the raw channels
    (all rows, for naming what was found); ``reversals``: indices into the residual of the load reversals,
    where the sample on each side is not judged: the load's true extreme may lie between two samples, so the
    model there misses the travel nobody recorded (heldout6: a triangle wave turning between samples 440 and
    441 read "a spike at sample 441" at 120x the noise)."""
    std = math.sqrt(noise.innovation_var)
    if not std > 0.0 or len(residual) < 3 * NEIGHBOURS:
        return None
    e = noise.whiten(residual) / std
    lag = len(residual) - len(e)              # the whitening filter drops its start-up samples
    threshold = max(float(norm.isf(ALPHA / (2.0 * len(e)))), GROSS_SIGMAS)
    judged = np.abs(e)
    if reversals is not None and len(reversals):
        near = (np.asarray(reversals)[:, None] + np.arange(-1, 2)[None, :]).ravel() - lag
        judged = judged.copy()
        judged[near[(near >= 0) & (near < len(judged))]] = 0.0
    beyond = np.flatnonzero(judged > threshold)
    if not len(beyond):
        return None
    worst = int(beyond[np.argmax(judged[beyond])]) + lag         # index into the fitted rows
    row = int(rows[worst])
    sigmas = float(abs(e[worst - lag]))
    load_step = float(np.median(np.abs(np.diff(load)))) if len(load) > 1 else 0.0
    for a, b in _frozen_runs(response, load, load_step):
        if a <= row <= b + max(1, int(np.max(np.diff(rows))) if len(rows) > 1 else 1):
            return Glitch(GlitchKind.FROZEN, row + 1, sigmas, threshold, len(beyond), (a + 1, b + 1))
    lo, hi = max(worst - NEIGHBOURS, 0), min(worst + NEIGHBOURS + 1, len(residual))
    before, after = residual[lo:worst], residual[worst + 1:hi]
    # the residual's sample-to-sample scale (robust: the glitch itself does not set it)
    scale = 1.4826 * float(np.median(np.abs(np.diff(residual)))) / math.sqrt(2.0)
    if len(before) and len(after) and scale > 0.0:
        level = abs(float(np.median(after)) - float(np.median(before)))
        off = abs(float(residual[worst]) - 0.5 * (float(np.median(after)) + float(np.median(before))))
        if off > 2.0 * level and off > threshold * scale and _off_both_sides(residual, worst) > threshold * scale:
            return Glitch(GlitchKind.SPIKE, row + 1, sigmas, threshold, len(beyond))
    # a jump: where the mean level of STEP_SPAN samples after differs most from that of the STEP_SPAN before
    c = np.concatenate([[0.0], np.cumsum(residual)])
    k = np.arange(STEP_SPAN, len(residual) - STEP_SPAN + 1)
    if len(k):
        step = (c[k + STEP_SPAN] - c[k]) - (c[k] - c[k - STEP_SPAN])
        at = int(k[np.argmax(np.abs(step))])
        # no step between the two sides' lines where the levels differ most: the residual runs on continuously,
        # a corner the model draws with another shape (a stick-slip knee, a reversal) that the whitening of a
        # smooth (low-pass) sensor turns into one large innovation; left to the goodness-of-fit test
        # (heldout6: Bouc-Wen and bristle loops at 80-260x behind a Butterworth sensor read "a jump")
        # ... judged against the larger of the white scale and what the noise model's own wander makes between
        # the two lines (the same multiple of each)
        allowed = 0.5 * threshold * max(scale, step_noise_std(noise))
        if scale > 0.0 and max(_step_across(residual, at), _step_across(residual, worst)) < allowed:
            return None
        return Glitch(GlitchKind.JUMP, int(rows[at]) + 1, sigmas, threshold, len(beyond))
    return Glitch(GlitchKind.JUMP, row + 1, sigmas, threshold, len(beyond))

__all__ = ["ALPHA", "GROSS_SIGMAS", "Glitch", "GlitchKind", "MIN_FROZEN", "find_glitch", "step_noise_std"]
