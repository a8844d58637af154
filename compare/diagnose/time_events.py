"""Events in time that no catalogue effect draws: a one-way slip, creep under a hold, a thermal zero drift.

Read only where the catalogue leaves the recording unexplained (pipeline.diagnose): the events found are taken
out of the response and the recording diagnosed again without them; where the rest is then explained or agrees
they are named beside that verdict, else the first answer (unexplained) stands. The catalogue's effects are
never bent to an event, and a recording the catalogue explains is never touched (no event can be a false
alarm there).

Each is read against a load model that draws any single- or double-valued curve of the load (mains.load_basis:
a polynomial per loading direction, plus a line in time), so a loop or a stiffening is no event:

- a one-way slip: two or more steps of the response between neighbouring samples, each beyond SLIP_SIGMAS
  robust sigmas of the sample-to-sample differences, ALL in one direction (a clamp or flange that walks one way;
  steps both ways are a stick-slip joint, which stays unexplained; a single step is a jump, which glitches.py
  names: a splice or a re-clamp are single steps too). Each step is taken out;
- creep under a hold: where the load is held (within HOLD_BAND of the largest, at least HOLD_MIN_SAMPLES, at
  |load| >= HOLD_LOAD), the response moves in time as a + A (1 - exp(-(t - t0)/tau)), A of the held load's sign
  (the twist creeps further the way the torque holds it), better than a constant by BIC_THRESHOLD; named with
  its time constant tau; the creep is taken out in the hold and its end value after it;
- a thermal zero drift (find_thermal_drift, read also on explained and agreeing recordings, decision 069; an
  unexplained one keeps decision 067's find_drift: white noise, one exponential): the response drifts against
  TIME, not load: beside any function of the load per loading direction (load_states) and a line in time, a
  warm-up A (1 - exp(-t/tau)) (tau from DRIFT_TAU of the record) improves BIC by more than BIC_THRESHOLD under
  the recording's noise (a fine-scale filter of what is left, deflated by the sensor's slow power), departs
  from a line by at least MIN_COMPONENT_SIGMAS white sigmas, leaves a residual within DRIFT_LEAVES x the
  variance that noise implies and Gaussian innovations (DRIFT_TAILS). The first loading and the creep under any hold are left out. Found, its
  shape is taken out as two warm-ups and the line, from the end of the first loading.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from strainwave.compare.diagnose.judge import BIC_THRESHOLD
from strainwave.compare.diagnose.noise import _TRIM_FACTOR, KEEP
from strainwave.compare.diagnose.structure import (MIN_COMPONENT_SIGMAS, NoiseModel, fine_scale_noise,
                                                   flicker_noise, slow_power_inflation)

SLIP_SIGMAS = 30.0          # a step this many robust sigmas of the sample-to-sample differences is no noise
SLIP_SPAN = 3               # samples a slip may take
MAX_SLIPS = 20
HOLD_BAND = 0.005           # a hold: the load within this fraction of the largest load ...
HOLD_MIN_SAMPLES = 20       # ... for at least this many samples and HOLD_SHARE of the record (the top of a
HOLD_SHARE = 0.05           #     slow sine is no hold) ...
HOLD_LOAD = 0.2             # ... at a load at least this fraction of the largest
DRIFT_TAU = (0.03, 3.0)     # time constants tried for a drift, fractions of the record
N_TAU = 25
DRIFT_ROWS = 10_000
LOAD_KNOTS = 48             # knots per loading direction of the load model a drift is read against
DRIFT_LEAVES = 4.0          # a drift is the whole story beside the load: its residual's variance within this x
                            # the white noise's (else the load model misses something, e.g. a stick-slip stair,
                            # that a slow curve in time only partly follows)
DRIFT_TAILS = 2.0           # ... and the innovations its noise filter leaves Gaussian: their variance within this
                            # x their trimmed variance (a stair's steps, which a filter reads as red noise, are
                            # spikes in them; Gaussian innovations give 1.0-1.15)


@dataclass(frozen=True)
class TimeEvents:
    response: np.ndarray            # the response with the events taken out
    sentences: tuple[str, ...]


def _sigma(x: np.ndarray) -> float:
    """The white noise of ``x`` from its sample-to-sample differences (robust: median absolute deviation)."""
    d = np.diff(x)
    return 1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2.0)


def find_slips(load: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, str | None]:
    """One-way slips (see the module doc): (the response without them, a sentence) or (y, None)."""
    dl, dy = np.diff(load), np.diff(y)
    ok = np.abs(dl) > 0
    slope = float(np.median(dy[ok] / dl[ok])) if np.any(ok) else 0.0
    d = dy - slope * dl
    scale = 1.4826 * float(np.median(np.abs(d - np.median(d))))
    if not scale > 0.0:
        return y, None
    big = np.flatnonzero(np.abs(d) > SLIP_SIGMAS * scale)
    # a walk is two slips or more, a single step is a jump (glitches.py names it: a slip, a splice, a re-clamp)
    if len(big) < 2 or len(big) > MAX_SLIPS * SLIP_SPAN:
        return y, None
    signs = np.sign(d[big])
    if np.any(signs != signs[0]):
        return y, None                        # steps both ways: a stick-slip joint, not a one-way slip
    out, total = y.copy(), 0.0
    for k in big:
        out[k + 1:] -= d[k]
        total += float(d[k])
    at = float(np.median(np.abs(load[big + 1])) / (np.max(np.abs(load)) or 1.0))
    return out, (f"a one-way slip: the response steps {len(big)} time(s), all {'up' if total > 0 else 'down'}, "
                 f"{total:.4g} in all, at a median {100 * at:.0f} % of the largest load, and stays (a clamp or "
                 f"flange walking one way); taken out of the fit")


def _holds(load: np.ndarray) -> list[tuple[int, int]]:
    full = float(np.max(np.abs(load))) or 1.0
    out, start = [], 0
    for k in range(1, len(load) + 1):
        if k == len(load) or abs(load[k] - load[start]) > HOLD_BAND * full:
            if k - start >= max(HOLD_MIN_SAMPLES, HOLD_SHARE * len(load)) \
                    and abs(float(np.median(load[start:k]))) >= HOLD_LOAD * full:
                out.append((start, k))
            start = k
    return out


def _best_exponential(t: np.ndarray, r: np.ndarray, taus: np.ndarray, basis: np.ndarray, whiten=None):
    """(gain in RSS, tau, amplitude, curve) of A (1 - exp(-t/tau)) beside ``basis`` (orthonormal columns);
    ``whiten``: the noise filter ``r`` and ``basis`` were passed through."""
    best = (0.0, math.nan, 0.0, np.zeros_like(r))
    for tau in taus:
        g = 1.0 - np.exp(-t / tau)
        g = g if whiten is None else whiten(g)
        g = g - basis @ (basis.T @ g)
        gg = float(g @ g)
        if gg <= 0.0:
            continue
        a = float(g @ r) / gg
        if a * a * gg > best[0]:
            best = (a * a * gg, float(tau), a, a * g)
    return best


def find_hold_creep(load: np.ndarray, y: np.ndarray, t: np.ndarray, sigma: float,
                    unit: str) -> tuple[np.ndarray, list[str]]:
    """Creep under each hold (see the module doc): (the response without it, a sentence per hold)."""
    out, said = y.copy(), []
    for a, b in _holds(load):
        tt, r = t[a:b] - t[a], out[a:b]
        n, span = b - a, float(t[b - 1] - t[a])
        if not span > 0.0:
            continue
        # a constant and the load's own wander within the band (the response follows it, that is no creep)
        ones, _ = np.linalg.qr(np.column_stack([np.ones(n), load[a:b] - float(np.mean(load[a:b]))]))
        rc = r - ones @ (ones.T @ r)
        dt = span / (n - 1)
        gain, tau, amp, curve = _best_exponential(tt, rc, np.geomspace(dt, 3.0 * span, N_TAU), ones)
        rss0 = float(rc @ rc)
        if not rss0 > gain or n * math.log(rss0 / (rss0 - gain)) - 2.0 * math.log(n) <= BIC_THRESHOLD:
            continue
        held = float(np.median(load[a:b]))
        swing = abs(amp) * (1.0 - math.exp(-span / tau))
        if np.sign(amp) != np.sign(held) or swing < MIN_COMPONENT_SIGMAS * sigma:
            continue
        creep = amp * (1.0 - np.exp(-tt / tau))
        out[a:b] -= creep
        out[b:] -= creep[-1]
        said.append(f"creep under a hold: at load {held:.4g} (rows {a + 1}-{b}) the response creeps {swing:.3g} "
                    f"{unit} the way the load holds it, time constant {tau:.3g} s; taken out of the fit")
    return out, said


def load_states(load: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Any function of the load per loading direction (piecewise linear on LOAD_KNOTS knots: a loop, a band,
    a staircase repeated each cycle), plus a line in time: what a drift against time must stand out from."""
    u = load / (float(np.max(np.abs(load))) or 1.0)
    d = np.sign(np.gradient(u))
    up = d >= 0
    knots = np.linspace(-1.0, 1.0, LOAD_KNOTS)
    h = knots[1] - knots[0]
    hats = np.maximum(0.0, 1.0 - np.abs(u[:, None] - knots[None, :]) / h)
    cols = np.hstack([hats * up[:, None], hats * ~up[:, None]])
    cols = cols[:, cols.any(axis=0)]
    return np.column_stack([cols, (t - t[0]) / (t[-1] - t[0])])


@dataclass(frozen=True)
class Drift:
    """A thermal zero drift found beside the load (see the module doc)."""

    curve: np.ndarray           # the drift (warm-ups and line) from the end of the first loading, 0 before it
    total: np.ndarray           # the whole drift in time (warm-up plus line), every row, zero where the fit starts
    departure: float            # its departure from a straight line over the rows read (peak to peak)
    tau: float                  # time constant of the warm-up fitted (s, or samples without a time column)
    evidence: float             # delta BIC under the recording's noise, deflated by its slow power
    noise: str                  # the noise filter it was judged under
    start_s: float              # where the fit starts: the end of the first loading (s)

    def sentence(self, t: np.ndarray, unit: str) -> str:
        span = float(t[-1] - self.start_s)
        change = float(self.total[-1])

        def shown(x: float) -> str:
            return f"{x:.3g} {unit}" + (f" ({x * _ARCMIN_PER_RAD:.3g} arcmin)" if unit == "rad" else "")
        return (f"a thermal zero drift: the response drifts against time, not load, by {shown(change)} from "
                f"{self.start_s:.4g} s to {float(t[-1]):.4g} s (mean rate {shown(change / span)}/s; time constant "
                f"{self.tau:.3g} s), "
                f"departing from a straight line by {shown(self.departure)} "
                f"(delta BIC {self.evidence:.3g} beside any function of the load per loading direction, "
                f"{self.noise} noise); taken out, the rows from {self.start_s:.4g} s diagnosed without it")


_ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi


def _noise_of(rest: np.ndarray) -> tuple[NoiseModel, float]:
    """The recording's noise read from the fine scales of what the drift and the load leave (as
    structure.reference_noise reads it), with its slow power; and the variance that filter implies."""
    model = fine_scale_noise(rest)
    model = dataclasses.replace(model, slow_inflation=slow_power_inflation(rest, model),
                                flicker=flicker_noise(rest, model))
    impulse = np.zeros(min(len(rest), 4000))
    impulse[0] = 1.0
    h = lfilter(model.a, model.b, impulse)          # r = lfilter(a, b, e): the filter's response to one innovation
    return model, model.innovation_var * float(h @ h)


def _trimmed_var(x: np.ndarray) -> float:
    """Gaussian variance from the central KEEP of |x - median| (noise.py's trimming): spikes left out."""
    a = np.abs(x - np.median(x))
    kept = x[a <= np.quantile(a, KEEP)] - np.median(x)
    return float(np.mean(kept ** 2)) / _TRIM_FACTOR


def _judged(tt: np.ndarray, keep: np.ndarray, X: np.ndarray, y: np.ndarray, taus: np.ndarray, model: NoiseModel):
    """(delta BIC deflated by the sensor's slow power, tau, amplitude) of the best warm-up beside the load X,
    both scored on the rows whitened by ``model``."""
    qw, _ = np.linalg.qr(model.whiten(X))
    yw = model.whiten(y)
    rw = yw - qw @ (qw.T @ yw)
    gain, tau, amp, _ = _best_exponential(tt[keep], rw, taus, qw, whiten=model.whiten)
    n, rss0 = len(rw), float(rw @ rw)
    if not (rss0 > gain and math.isfinite(tau)):
        return -math.inf, tau, amp
    warm = amp * (1.0 - np.exp(-tt[keep] / tau))
    beyond = warm - np.polyval(np.polyfit(tt[keep], warm, 1), tt[keep])
    return model.deflate(n * math.log(rss0 / (rss0 - gain)), beyond) - 2.0 * math.log(n), tau, amp


def drift_test(load: np.ndarray, y: np.ndarray, t: np.ndarray, sigma: float, first: int) -> Drift | None:
    """A warm-up in time beside any function of the load, judged as the effects are (decision 069)."""
    rows = np.arange(len(y))
    keep = (rows >= first) & (rows % max(1, len(y) // DRIFT_ROWS) == 0)
    tt = t - t[0]
    span = float(tt[-1])
    if keep.sum() < 50 or not span > 0.0:
        return None
    X = load_states(load[keep], t[keep])
    q, _ = np.linalg.qr(X)
    r = y[keep] - q @ (q.T @ y[keep])
    taus = span * np.geomspace(DRIFT_TAU[0], DRIFT_TAU[1], N_TAU)
    gain, tau, _, curve = _best_exponential(tt[keep], r, taus, q)
    n, rss0 = int(keep.sum()), float(r @ r)
    # not significant under white noise, it is not under a redder one (more slow power): the noise is not read
    if not (math.isfinite(tau) and rss0 > gain) or n * math.log(rss0 / (rss0 - gain)) - 2.0 * math.log(n) \
            <= BIC_THRESHOLD:
        return None
    model, variance = _noise_of(r - curve)
    evidence, tau, amp = _judged(tt, keep, X, y[keep], taus, model)
    yw = model.whiten(y[keep])
    warm = amp * (1.0 - np.exp(-tt / tau))
    fit_all = np.column_stack([X, warm[keep]])
    coef = np.linalg.lstsq(model.whiten(fit_all), yw, rcond=None)[0]
    beyond = warm - np.polyval(np.polyfit(tt[keep], warm[keep], 1), tt)
    a = int(np.flatnonzero(keep)[0])
    # held over the first loading, not extrapolated: the fitted shape says nothing of the drift before it
    beyond[:a] = beyond[a]
    rest = y[keep] - fit_all @ coef
    innovations = model.whiten(rest)
    if evidence <= BIC_THRESHOLD or float(np.var(rest)) > DRIFT_LEAVES * variance \
            or float(np.var(innovations)) > DRIFT_TAILS * _trimmed_var(innovations):
        return None
    if float(np.ptp(beyond[keep])) < MIN_COMPONENT_SIGMAS * sigma:
        return None
    # found, its shape is taken out as two warm-ups (a heater's t^2 start is no one exponential) and the line
    slope, drift = _two_warm_ups(tt, keep, X, model.whiten, yw, taus)
    slope = slope / (t[keep][-1] - t[keep][0])                          # load_states' line in time
    whole = drift + slope * tt
    whole = whole - whole[a]
    departure = float(np.ptp((drift - np.polyval(np.polyfit(tt[keep], drift[keep], 1), tt))[keep]))
    # reported over the rows it was fitted on (no extrapolation over the first loading): taken out whole
    # (its rate at the window's start is not said: the pair's slope there was off by 33-89 % on the tests)
    return Drift(np.where(rows < a, 0.0, whole), whole, departure, tau, evidence, model.describe(), float(t[a]))


def _two_warm_ups(tt: np.ndarray, keep: np.ndarray, X: np.ndarray, whiten, yw: np.ndarray, taus: np.ndarray):
    """(coefficient of X's line in time, the drift on every row): the pair of warm-ups A_i (1 - exp(-t/tau_i))
    fitted beside the load (X) on the whitened rows that leaves least."""
    G = 1.0 - np.exp(-tt[:, None] / taus[None, :])
    Xw = whiten(X)
    qw, _ = np.linalg.qr(Xw)
    P = whiten(G[keep])
    P = P - qw @ (qw.T @ P)
    rw = yw - qw @ (qw.T @ yw)
    M, b = P.T @ P, P.T @ rw
    best, pair = -math.inf, (0, 1)
    for i in range(len(taus)):
        for j in range(i + 1, len(taus)):
            m = M[np.ix_([i, j], [i, j])]
            if abs(np.linalg.det(m)) <= 1e-12 * m[0, 0] * m[1, 1]:
                continue
            c = np.linalg.solve(m, b[[i, j]])
            if float(c @ b[[i, j]]) > best:                  # the gain in RSS of the pair
                best, pair = float(c @ b[[i, j]]), (i, j)
    cols = G[:, list(pair)]
    coef = np.linalg.lstsq(np.column_stack([Xw, whiten(cols[keep])]), yw, rcond=None)[0]
    return float(coef[X.shape[1] - 1]), cols @ coef[-2:]


def find_drift(load: np.ndarray, y: np.ndarray, t: np.ndarray, sigma: float, first: int,
               unit: str) -> tuple[np.ndarray, str | None]:
    """Decision 067's thermal drift, read where the catalogue left the recording unexplained (white noise, the
    one exponential beyond a line taken out of every row): (the response without it, a sentence) or (y, None)."""
    # fitted on at most DRIFT_ROWS rows (a slow curve needs no more), taken out of every row
    rows = np.arange(len(y))
    keep = (rows >= first) & (rows % max(1, len(y) // DRIFT_ROWS) == 0)
    tt = t - t[0]
    span = float(tt[-1])
    if keep.sum() < 50 or not span > 0.0:
        return y, None
    q, _ = np.linalg.qr(load_states(load[keep], t[keep]))
    r = y[keep] - q @ (q.T @ y[keep])
    taus = span * np.geomspace(DRIFT_TAU[0], DRIFT_TAU[1], N_TAU)
    gain, tau, amp, _ = _best_exponential(tt[keep], r, taus, q)
    n, rss0 = int(keep.sum()), float(r @ r)
    if not rss0 > gain or n * math.log(rss0 / (rss0 - gain)) - 2.0 * math.log(n) <= BIC_THRESHOLD:
        return y, None
    if (rss0 - gain) / n > DRIFT_LEAVES * sigma ** 2:
        return y, None
    drift = amp * (1.0 - np.exp(-tt / tau))
    # the nuisance fit takes a line in time: what is left of the drift beyond it
    drift = drift - np.polyval(np.polyfit(tt[keep], drift[keep], 1), tt)
    swing = float(np.ptp(drift[keep]))
    if swing < MIN_COMPONENT_SIGMAS * sigma:
        return y, None
    return y - drift, (f"a thermal zero drift: the response drifts against time, not load, departing from a "
                       f"straight line by {swing:.3g} {unit} (time constant {tau:.3g} s); taken out of the fit")


@dataclass(frozen=True)
class FoundDrift:
    curve: np.ndarray           # what to take out of the response (every row)
    said: str
    start_row: int              # the first row it was read on (the end of the first loading)


def find_thermal_drift(load: np.ndarray, y: np.ndarray, t: np.ndarray | None, first: int,
                       unit: str = "rad") -> FoundDrift | None:
    """A thermal zero drift alone (decision 069: read on every verdict); without a time column the sample index
    is the clock (times then in samples)."""
    if len(y) < 50:
        return None
    clock = np.arange(len(y), dtype=float) if t is None or not t[-1] > t[0] else t
    from threadpoolctl import threadpool_limits
    sigma = _sigma(y)
    with threadpool_limits(limits=1):       # a (rows x 97) QR: BLAS threads only contend (decision 019)
        # read beside the creep under any hold (a hold's creep runs in time at a constant load, and is no drift)
        drift = drift_test(load, find_hold_creep(load, y, clock, sigma, unit)[0], clock, sigma, first)
    if drift is None:
        return None
    said = drift.sentence(clock, unit)
    start = int(np.searchsorted(clock, drift.start_s))
    return FoundDrift(drift.curve, said if t is not None else _in_samples(said), start)


def _in_samples(said: str) -> str:
    for a, b in ((" s ", " samples "), (" s;", " samples;"), (" s)", " samples)"), ("/s", "/sample")):
        said = said.replace(a, b)
    return said


def find_time_events(load: np.ndarray, y: np.ndarray, t: np.ndarray | None, first: int,
                     unit: str = "rad") -> TimeEvents | None:
    """Slips, creep under holds and a thermal drift (see the module doc), in that order; None if none. Without
    a time column the sample index is the time (time constants then in samples)."""
    y1, slip = find_slips(load, y)
    said = [slip] if slip else []
    if len(y) >= 50:
        clock = np.arange(len(y), dtype=float) if t is None or not t[-1] > t[0] else t
        sigma = _sigma(y1)
        y1, creep = find_hold_creep(load, y1, clock, sigma, unit)
        said += creep
        y1, drift = find_drift(load, y1, clock, sigma, first, unit)
        said += [drift] if drift else []
    if t is None:
        said = [_in_samples(s) for s in said]
    return TimeEvents(y1, tuple(said)) if said else None


__all__ = ["Drift", "FoundDrift", "TimeEvents", "drift_test", "find_drift", "find_hold_creep", "find_slips",
           "find_thermal_drift", "find_time_events"]
