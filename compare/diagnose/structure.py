"""Is a residual consistent with the noise? A goodness-of-fit test that does not know the catalogue.

The residual r of a model is offered a few generic, catalogue-free structures, each a small linear basis
(binned means in disguise: piecewise-linear hats):
- ``odd`` / ``even`` (two-sided loads) or ``load`` (one-sided): a smooth function of the load;
- ``branch``: a function of the load that differs between loading and unloading (hysteretic);
- ``rate``: proportional to the loading rate du/dt (viscous, viscoelastic, a channel lagging in time);
- ``creep``: the load through first-order lags of a few time constants (creep; only where the load is held);
- ``time``: a slow function of time at any load (drift that is not linear);
- ``time_load``: a compliance that changes during the test (u times hats in time: re-clamping, a second
  specimen, warm-up of the gain);
- ``periodic_time``: a sinusoid at the residual's strongest spectral line (period reported);
- ``periodic_angle``: a sinusoid in the wave generator's input angle (when recorded), k per revolution;
- ``angle_load``: harmonics 1-4 of the input angle times the load (a stiffness rippling with the angle);
- ``periodic_response``: two harmonics of the strongest line against the measured response (an encoder's
  interpolation error, periodic in the reading itself).
Each is scored under the same coloured-noise likelihood as the catalogue (fit.bic_ar, fit.noise_filter): delta BIC =
N ln(RSS_e(r) / RSS_e(r - G c)) - rank(G) ln N (and + ln N for a searched frequency). A structure is
significant when delta BIC > 10 ("very strong"); its unique share is its drop from the joint fit of all
structures. Coloured noise is no structure: its wander costs what an AR process of that size costs.
"""
from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.fit import _PHIS, _THETAS, NOISE_FLOOR, ar_profile, lag1
from strainwave.compare.diagnose.noise import KEEP, noise_std
from strainwave.compare.diagnose.periodic import angle_load_columns, recorded_line, response_columns

THRESHOLD = 10.0
# the least swing, in white-noise sigmas, a user can see (judge.MIN_COMPONENT_SIGMAS says why)
MIN_COMPONENT_SIGMAS = 1.5
# A line in time that the load does not share (mains pick-up, a pump) averages out over the load's cycles and
# shifts no specimen quantity: it is a rig fault to report only where a user can see it, MIN_COMPONENT_SIGMAS
# of swing, the floor a named effect must reach; below it, thousands of samples still make it "significant"
UNTIED_TO_LOAD = ("periodic_time",)
STIFFNESS_CHI2 = 6.63     # chi-square(1) at 99 %: 2.58 prior sigmas
# A structure must beat a random-walk wander of WANDER_SIGMAS at its frequencies (docs/decisions/023-diagnose-noise-model.md).
WANDER_SIGMAS = 2.0
_TWO_SIDED_KNOTS = (0.0, 0.1, 0.3, 0.55, 0.8, 1.0)
_ONE_SIDED_KNOTS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)


@dataclass(frozen=True)
class Structure:
    name: str
    delta_bic: float           # added alone to the model
    unique_delta_bic: float    # dropped from the joint fit of all structures
    detail: str = ""           # e.g. the period
    threshold: float = THRESHOLD
    size: float = math.inf     # RMS of the fitted structure in white-noise sigmas (inf: not a residual shape)
    wander: float = 0.0        # RMS a random walk of WANDER_SIGMAS puts at the structure's frequencies
    visible: bool = True       # swings by MIN_COMPONENT_SIGMAS or more (judged only where UNTIED_TO_LOAD)

    @property
    def significant(self) -> bool:
        return self.delta_bic > self.threshold and self.size >= self.wander and self.visible

    def to_dict(self) -> dict:
        return {"name": self.name, "delta_bic": self.delta_bic, "unique_delta_bic": self.unique_delta_bic,
                "detail": self.detail, "size_noise_sigmas": self.size if math.isfinite(self.size) else None,
                "wander_noise_sigmas": self.wander, "visible": self.visible}


@dataclass(frozen=True)
class StructureTest:
    structures: tuple[Structure, ...]
    chi2_per_sample: float     # RMS(residual)^2 / white-noise variance (1 for white noise)
    lag1: float                # lag-1 autocorrelation of the residual
    rss_innovation: float

    @property
    def structured(self) -> bool:
        return any(s.significant for s in self.structures)

    @property
    def significant(self) -> tuple[Structure, ...]:
        return tuple(sorted((s for s in self.structures if s.significant), key=lambda s: -s.delta_bic))

    def get(self, name: str) -> Structure | None:
        return next((s for s in self.structures if s.name == name), None)

    def to_dict(self) -> dict:
        return {"structured": self.structured, "chi2_per_sample": self.chi2_per_sample, "lag1": self.lag1,
                "structures": [s.to_dict() for s in self.structures]}


def _hats(x: np.ndarray, knots) -> np.ndarray:
    """Piecewise-linear hat functions on ``knots`` evaluated at x (columns)."""
    eye = np.eye(len(knots))
    return np.column_stack([np.interp(x, knots, eye[i]) for i in range(len(knots))])


# A periodic disturbance is a spectral LINE: its peak stands far above the neighbouring bins, where coloured
# noise (a random walk, a filtered sensor) is a continuum whose bins scatter as exponential variates about a
# smooth level; the largest of ~n/2 such bins exceeds the local median by ~ln(n) (< 10 for n <= 2,500), so a
# peak LINE_CONTRAST times the local median is not the noise's own scatter.
LINE_CONTRAST = 30.0


def _spectral_line(r: np.ndarray) -> tuple[float, float]:
    """(frequency in cycles per sample, refined; peak power) of the largest periodogram peak above the slowest
    3 bins, or (0, 0) when it is not a line (not LINE_CONTRAST x the median of the bins 3 to 12 away)."""
    n = len(r)
    spec = np.abs(np.fft.rfft((r - r.mean()) * np.hanning(n))) ** 2
    if len(spec) < 8:
        return 0.0, 0.0
    spec[:4] = 0.0
    k = int(np.argmax(spec))
    around = np.concatenate([spec[max(k - 12, 4):max(k - 2, 4)], spec[k + 3:k + 13]])
    if len(around) < 4 or spec[k] < LINE_CONTRAST * float(np.median(around)):
        return 0.0, 0.0
    peak = float(spec[k])
    if 0 < k < len(spec) - 1:
        a, b, c = np.log(spec[k - 1:k + 2] + 1e-300)
        den = a - 2 * b + c
        k = k + (0.5 * (a - c) / den if den < 0 else 0.0)
    return k / n, peak


def _groups(ctx: Context, r: np.ndarray) -> dict[str, tuple[np.ndarray, int, str]]:
    """name -> (columns, extra searched parameters, detail)."""
    u, t, d = ctx.u, ctx.t, ctx.direction
    out: dict[str, tuple[np.ndarray, int, str]] = {}
    if ctx.two_sided:
        m = np.abs(u)
        h = _hats(m, _TWO_SIDED_KNOTS)
        out["odd"] = (np.sign(u)[:, None] * h[:, 1:], 0, "")
        out["even"] = (h, 0, "")
        out["branch"] = (np.column_stack([d * np.interp(m, (0, 0.5, 1), (1, 0, 0)), d * np.interp(m, (0, 0.5, 1), (0, 1, 0)),
                                          d * np.interp(m, (0, 0.5, 1), (0, 0, 1)), d * u]), 0, "")
    else:
        lo, hi = float(u.min()), float(u.max())
        out["load"] = (_hats(u, np.linspace(lo, hi, 6)), 0, "")
        out["branch"] = (d[:, None] * _hats(u, np.linspace(lo, hi, 3)), 0, "")
    if ctx.reversals < 1:
        out.pop("branch")
    else:
        # the signed loading rate: a viscous or viscoelastic part, or a channel recorded L samples late
        # (y(k - L) = y(k) - L dy/dk), is proportional to it; rate-independent friction is not
        rate = _load_rate(u, t)
        scale = float(np.max(np.abs(rate))) or 1.0
        out["rate"] = (np.column_stack([rate, rate * (np.abs(u) if ctx.two_sided else u)]) / scale, 0, "")
        if _load_held(ctx):
            out["creep"] = (_creep_basis(ctx), 0, "")
    out["time"] = (_hats(t, np.linspace(0.0, 1.0, 6)), 0, "")
    out["time_load"] = (u[:, None] * _hats(t, np.linspace(0.0, 1.0, 4)), 0, "")
    f, _ = _spectral_line(r)
    if f > 0:
        k = np.arange(len(r))
        out["periodic_time"] = (np.column_stack([np.cos(2 * np.pi * f * k), np.sin(2 * np.pi * f * k)]), 1, f"{f:.6g}")
    if ctx.angle is not None:
        best, cols = None, None
        for order in range(1, 9):
            c = np.column_stack([np.cos(order * ctx.angle), np.sin(order * ctx.angle)])
            coef, *_ = np.linalg.lstsq(c, r - r.mean(), rcond=None)
            gain = float(np.sum((c @ coef) ** 2))
            if best is None or gain > best[0]:
                best, cols = (gain, order), c
        out["periodic_angle"] = (cols, 1, f"{best[1]}")
        # a ripple in the input angle that grows with the load: a stiffness that varies with the angle
        out["angle_load"] = (angle_load_columns(ctx), 0, "")
    f = recorded_line(ctx)[0]
    if f > 0:
        # periodic in the measured response itself (an encoder's line pitch), at the recording's strongest line
        # (searched once per recording, on the residual of a straight line in the load: what repeats with the
        # reading is there whatever else the residual holds); the search costs two parameters
        out["periodic_response"] = (response_columns(ctx, f), 2, f"{f:.6g}")
    return out


# Creep under held loads needs first-order lag columns; taus 4x apart (docs/decisions/023-diagnose-noise-model.md).
CREEP_TAUS = (0.01, 0.04, 0.16)


# The creep columns are offered only where the load is held: there creep shows as itself, a response moving at
# constant load. Under a load that keeps moving the lags draw rate-dependent shapes that the rate and branch
# structures already offer and, being more flexible, also one loop law's misfit of another law's loop (family 2:
# a CHA gear with a Bouc-Wen loop, explained by the catalogue's loops, read "it creeps" under a random-walk
# noise model). A hold: HOLD_FRACTION of the record (at least HOLD_SAMPLES) consecutive samples of the load
# within HOLD_SIGMAS of its own noise (second differences; exactly equal where the load channel carries no
# noise) of their median. A sine's peak stays within d of its top for a share sqrt(2 d)/pi of a cycle: 1-2 % of
# a record of 1.5 cycles for a load noise of 1e-4 to 1e-3 of full scale (that CHA loop, sampled 700 times a
# cycle, passed a bound of ten samples alone).
HOLD_SAMPLES = 10
HOLD_FRACTION = 0.05
HOLD_SIGMAS = 3.0


def _load_held(ctx: Context) -> bool:
    """Whether the load stands still anywhere in the record (see HOLD_SAMPLES)."""
    if "load_held" not in ctx.cache:
        u = ctx.u
        held = False
        run = max(HOLD_SAMPLES, math.ceil(HOLD_FRACTION * len(u)))
        if len(u) >= max(run, 3):
            # noise_std falls back on the first differences where the trimmed second differences are all zero:
            # a noise-free load, whose holds are exact
            noisy = float(np.quantile(np.abs(np.diff(u, 2)), KEEP)) > 0.0
            windows = np.lib.stride_tricks.sliding_window_view(u, run)
            spread = np.max(np.abs(windows - np.median(windows, axis=1)[:, None]), axis=1)
            held = bool(np.any(spread <= (HOLD_SIGMAS * noise_std(u) if noisy else 0.0)))
        ctx.cache["load_held"] = held
    return ctx.cache["load_held"]


def _creep_basis(ctx: Context) -> np.ndarray:
    """Columns lag_tau(u) - u for tau in CREEP_TAUS (time scaled to [0, 1]), the lag exact for a load held
    between samples; memoised on the context."""
    if "creep" not in ctx.cache:
        u = ctx.u
        cols = np.empty((len(u), len(CREEP_TAUS)))
        for j, tau in enumerate(CREEP_TAUS):
            keep = np.exp(-np.maximum(np.diff(ctx.t), 0.0) / tau).tolist()
            x = float(u[0])
            col = [x]
            for uk, kk in zip(u[1:].tolist(), keep):
                x = uk + kk * (x - uk)
                col.append(x)
            cols[:, j] = col
        ctx.cache["creep"] = cols - u[:, None]
    return ctx.cache["creep"]


def _load_rate(u: np.ndarray, t: np.ndarray) -> np.ndarray:
    """du/dt, with u first averaged over 1 % of the record (at least 5 samples) so the load channel's own
    sample-to-sample noise does not dominate the derivative."""
    k = max(5, len(u) // 100) | 1
    pad = np.pad(u, k // 2, mode="edge")
    smooth = np.convolve(pad, np.ones(k) / k, mode="valid")
    return np.gradient(smooth, t) if np.all(np.diff(t) > 0) else np.gradient(smooth)


def _nuisance(ctx: Context) -> np.ndarray:
    return np.column_stack([np.ones_like(ctx.u), ctx.t, ctx.u])


def _project_out(G: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, int]:
    """Columns of G orthogonal to span(Q), reduced to an orthonormal basis; (basis, rank).

    Directions that lose more than 95 % of their length to the projection are dropped: they are (nearly)
    the nuisance itself, e.g. hats in time that can draw the triangular load path u(t), and what is left of
    them is the load channel's own noise, which the response does correlate with (errors in variables)."""
    scale = np.linalg.svd(G, compute_uv=False).max() if G.size else 0.0
    G = G - Q @ (Q.T @ G)
    U, sv, _ = np.linalg.svd(G, full_matrices=False)
    rank = int(np.sum(sv > 0.05 * max(scale, 1e-300))) if len(sv) else 0
    return U[:, :rank], rank


@dataclass(frozen=True)
class NoiseModel:
    """The recording's noise filter e = lfilter(b, a, r), estimated ONCE per recording (see ``reference_noise``)
    and then held fixed for every residual it scores."""
    b: np.ndarray
    a: np.ndarray
    innovation_var: float      # per-sample innovation variance of the reference residual (normalised units)
    # how many times more power the sensor has at the slow structures' frequencies than the filter draws there
    # (``slow_power_inflation``); 1 where the filter is not shown to fall short
    slow_inflation: float = 1.0
    # flicker (1/f) noise read at the fine scales (``flicker_noise``): (white level, flicker amplitude c) of the
    # spectrum white + pi c / omega; (0, 0) where the fine scales show none
    flicker: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self):
        if self.b.ndim != 1 or self.a.ndim != 1 or self.b[0] != 1.0 or self.a[0] != 1.0:
            raise ValueError("noise filter polynomials must be 1-D and monic")
        if not (self.innovation_var >= 0.0):
            raise ValueError(f"innovation variance must be >= 0, got {self.innovation_var!r}")
        if not (self.slow_inflation >= 1.0):
            raise ValueError(f"slow-power inflation must be >= 1, got {self.slow_inflation!r}")

    def psd(self, omega: np.ndarray) -> np.ndarray:
        """Power spectral density of the noise the filter describes (per sample, normalised units) at the
        angular frequencies ``omega`` (rad per sample): innovation var * |a(e^iw) / b(e^iw)|^2."""
        z = np.exp(-1j * np.asarray(omega, dtype=float))
        num = np.polyval(self.a[::-1], z)
        den = np.polyval(self.b[::-1], z)
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.innovation_var * np.abs(num) ** 2 / np.abs(den) ** 2

    def deflate(self, evidence: float, drawn: np.ndarray | None = None) -> float:
        """A likelihood-ratio statistic of slow structure measured under this filter, in units of the sensor's
        own slow power (see ``slow_power_inflation``); with flicker noise, at the frequencies of the structure
        ``drawn`` (``flicker_inflation``)."""
        return evidence / max(self.slow_inflation, self.flicker_inflation(drawn))

    def flicker_inflation(self, drawn: np.ndarray | None) -> float:
        """How many times more power the flicker puts at ``drawn``'s frequencies than the filter: the mean of
        the ratio weighted as the evidence is, by drawn's power over the filter's (a GLS statistic sums
        |drawn_k|^2 / S(k)); 1 without flicker or without ``drawn``."""
        white, c = self.flicker
        if c <= 0.0 or drawn is None:
            return 1.0
        power = np.abs(np.fft.rfft(drawn - drawn.mean()))[1:] ** 2
        omega = 2.0 * np.pi * np.arange(1, len(power) + 1) / len(drawn)
        model = self.psd(omega)
        ratio = np.maximum(1.0, (white + np.pi * c / omega) / model)
        weight = power / model
        total = float(weight.sum())
        return float(np.sum(weight * ratio) / total) if total > 0.0 else 1.0

    def whiten(self, x: np.ndarray) -> np.ndarray:
        """Innovations of x (vector or column stack), start-up samples dropped."""
        from scipy.signal import lfilter
        return lfilter(self.b, self.a, x, axis=0)[len(self.b) - 1:]

    def describe(self) -> str:
        slow = f"; {self.slow_inflation:.3g} x its power at the slowest scales" if self.slow_inflation > 1.0 else ""
        flicker = "; flicker (1/f) noise at the slow scales" if self.flicker[1] > 0.0 else ""
        return self._filter_text() + slow + flicker

    def _filter_text(self) -> str:
        if len(self.b) == 1:
            return "white"
        if len(self.b) == 2:
            if -self.b[1] == 1.0:
                return f"random walk + white, theta {-self.a[1]:.3g}"
            return f"ARMA(1,1) phi {-self.b[1]:.3g}, theta {-self.a[1]:.3g}"
        if len(self.b) == 3 and abs(self.b[1] ** 2 - 4.0 * self.b[2]) < 1e-12:
            return f"second-order low-pass, pole {-self.b[1] / 2.0:.3g}, theta {-self.a[-1]:.3g}"
        return "AR(2) " + ", ".join(f"{-c:.3g}" for c in self.b[1:])


# Lags (samples) over which the noise's colour is read: short against the structures' scales (the hats are
# a fifth of the record apart), long enough to see a filter's or a wander's correlation build up.
FINE_LAGS = 16
# the double pole is one more shape, not one more parameter (both families have two): it is preferred to the
# first-order shapes only where it fits the fine-scale variogram better by the 95 % point of chi-square(1) (to
# the least-squares AR(2), also second order, on equal terms). A smooth sensor's variogram
# misses every first-order shape by 7 to 1000 (quantised and plain Butterworth, 5 % of Nyquist); an AR(1)'s
# residual with its slow structures fitted away is followed by the double pole's extra curvature by ~0.1
# (a clean AR(1) 0.95 recording alarmed without the margin)
DOUBLE_POLE_CHI2 = 3.84
REDDEST_TOLERANCE = 4.0
_IMPULSE = 4000


def _variogram(b: np.ndarray, a: np.ndarray, lags: np.ndarray) -> np.ndarray:
    """Semivariogram v(k) = Var(r_(t+k) - r_t)/2 of r = lfilter(a, b, e), unit innovations (also for a
    random walk, b = [1, -1], whose increments are stationary)."""
    # memoised: the candidate grid's filters are the same for every recording (~80 x 16 impulse responses)
    return np.array(_variogram_of(tuple(map(float, b)), tuple(map(float, a)), tuple(map(int, lags))))


@functools.lru_cache(maxsize=1024)
def _variogram_of(b: tuple[float, ...], a: tuple[float, ...], lags: tuple[int, ...]) -> tuple[float, ...]:
    from scipy.signal import lfilter
    b, a = np.array(b), np.array(a)
    out = np.empty(len(lags))
    for i, k in enumerate(lags):
        x = np.zeros(_IMPULSE)
        x[0], x[k] = 1.0, -1.0
        g = lfilter(a, b, x)
        out[i] = 0.5 * float(g @ g)
    return tuple(out)


def _fine_variogram(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lags, empirical semivariogram, weights) of x over its first FINE_LAGS lags; lag k rests on ~n/k
    independent differences, so ln v(k) is weighted by n/(2 k)."""
    n = len(x)
    lags = np.arange(1, min(FINE_LAGS, max(n // 8, 2)) + 1)
    emp = np.array([0.5 * float(np.mean((x[k:] - x[:-k]) ** 2)) for k in lags])
    return lags, emp, n / (2.0 * lags)


def _shape_misfit(emp: np.ndarray, w: np.ndarray, model: np.ndarray) -> tuple[float, float]:
    """(weighted chi-square of ln emp - ln model about their best common offset, that offset): how well a
    variogram SHAPE follows the empirical one, its scale free."""
    d = np.log(emp) - np.log(model)
    c = float(np.sum(w * d) / np.sum(w))
    return float(np.sum(w * (d - c) ** 2)), c


def fine_scale_noise(x: np.ndarray) -> NoiseModel:
    """The noise filter whose semivariogram over the first FINE_LAGS lags has the shape of x's.

    A least-squares filter (AR, ARMA conditional sum of squares) is set by the whole record, so it also sees
    the slowest scales; there, a residual with its slow structures fitted away has lost a random walk's own
    wander and mean-reverts, and the filter comes out less red than the sensor. Over a few samples the
    random walk, the AR(1), the low-pass filter and white noise have distinct variogram shapes (linear,
    saturating, flat) that the few smooth structures barely touch. Candidates: white, AR(2) (least squares,
    if red), ARMA(1,1) on the grid of fit.noise_filter with theta <= phi (red), including phi = 1 (a random
    walk plus white). Lag k rests on ~n/k independent differences, so ln v(k) is weighted by n/(2 k)."""
    lags, emp, w = _fine_variogram(x)
    if not np.all(emp > 0):
        return NoiseModel(np.array([1.0]), np.array([1.0]), float(np.mean(x ** 2)))
    candidates = [(np.array([1.0]), np.array([1.0]))]
    _, coef = ar_profile(x)
    if abs(1.0 - coef.sum()) <= abs(1.0 + coef[0] - coef[1:].sum()):
        candidates.append((np.concatenate([[1.0], -coef]), np.array([1.0])))
    candidates += [(np.array([1.0, -phi]), np.array([1.0, -th])) for phi in _PHIS for th in _THETAS if th <= phi]
    # a second-order low-pass sensor (an anti-aliasing filter) is smooth sample to sample: its variogram rises
    # quadratically over the first lags and then saturates, which no first-order model draws (a random walk
    # rises linearly for ever; an AR(1) plus white rises linearly and saturates): taken as a random walk, its
    # correlated steps read as a drift in time (a clean quantised low-pass recording read "varies in time at
    # constant load"). A double pole plus the white part: (1 - phi z)^2 / (1 - theta z), theta < phi
    # (theta = phi cancels to an AR(1)); it must beat the first-order shapes by DOUBLE_POLE_CHI2
    first_order = len(candidates)
    candidates += [(np.array([1.0, -2.0 * phi, phi * phi]), np.array([1.0, -th]))
                   for phi in _PHIS[:-1] for th in _THETAS if th < phi]
    best, first_best = None, math.inf
    for i, (bb, aa) in enumerate(candidates):
        model = _variogram(bb, aa, lags)
        if not np.all(np.isfinite(model)) or np.any(model <= 0):
            continue
        chi2, c = _shape_misfit(emp, w, model)
        if i < first_order and len(bb) <= 2:
            first_best = min(first_best, chi2)
        if i >= first_order and chi2 + DOUBLE_POLE_CHI2 >= first_best:
            continue
        if best is None or chi2 < best[0]:
            best = (chi2, bb, aa, math.exp(c))
    _, bb, aa, var = best
    return NoiseModel(bb, aa, var)


# Noise above the structures' band bounds the noise within it (docs/decisions/023-diagnose-noise-model.md).
SLOW_BINS = 8
SPECTRAL_BANDS = (16, 32)
SLOW_ALPHA = 0.01


def slow_power_inflation(x: np.ndarray, model: NoiseModel) -> float:
    """Lower bound (>= 1) on the ratio of x's noise power at the slow structures' frequencies to ``model``'s:
    the largest noise level x shows above SLOW_BINS cycles per record over the model's smallest level below."""
    from scipy.stats import norm
    n = len(x)
    power = np.abs(np.fft.rfft(x - x.mean())) ** 2 / n
    bands = [(lo, lo + width) for width in SPECTRAL_BANDS for lo in range(SLOW_BINS, n // 2 - width + 1, width)]
    if not bands:
        return 1.0
    floor = float(np.min(model.psd(2.0 * np.pi * np.arange(1, SLOW_BINS + 1) / n)))
    if not (floor > 0.0 and math.isfinite(floor)):
        return 1.0
    z = float(norm.isf(SLOW_ALPHA / len(bands)))
    bound = max(float(np.median(power[lo:hi])) / math.log(2.0) / (1.0 + z / (math.log(2.0) * math.sqrt(hi - lo)))
                for lo, hi in bands)
    return max(1.0, bound / floor)


# Flicker (1/f) noise, common in bridge amplifiers and encoders' electronics, has equal power per octave down to the
# slowest frequency: its semivariogram grows as the log of the lag, which no filter of the model draws (a random
# walk grows linearly, an AR(1) or a low-pass saturates). Fitted at the fine scales, a filter follows it there and
# draws its slow power several times short, so the flicker's own slow power is taken where its log-growing
# shape beats the filter's by the 95 % point of chi-square(1) (as the double pole must, DOUBLE_POLE_CHI2)
FLICKER_WHITE_SHARES = np.linspace(0.0, 1.0, 41)


def flicker_noise(x: np.ndarray, model: NoiseModel) -> tuple[float, float]:
    """(white level, flicker amplitude c) of the spectrum white + pi c / omega whose semivariogram follows x's
    over the fine lags better than ``model``'s filter does (by DOUBLE_POLE_CHI2); (0, 0) where none does.

    Flicker noise of power c/j in the record's Fourier bin j (j = 1 .. n/2) has the semivariogram
    v(k) = sum_j (c/j) (1 - cos(2 pi j k / n)) and the periodogram level n c / (2 j) = pi c / omega; white noise
    adds its variance to both."""
    n = len(x)
    lags, emp, w = _fine_variogram(x)
    if n < 4 * SLOW_BINS or not np.all(emp > 0):
        return 0.0, 0.0
    j = np.arange(1, n // 2 + 1)
    g = np.array([float(np.sum((1.0 - np.cos(2.0 * np.pi * j * k / n)) / j)) for k in lags])
    own, _ = _shape_misfit(emp, w, _variogram(model.b, model.a, lags))
    fits = [(*_shape_misfit(emp, w, share * g[0] + (1.0 - share) * g), share) for share in FLICKER_WHITE_SHARES]
    chi2, c, share = min(fits, key=lambda f: f[0])
    if share >= 1.0 or chi2 + DOUBLE_POLE_CHI2 >= own:
        return 0.0, 0.0
    # the fitted variogram is exp(c) (share g(1) + (1 - share) g(k)): the white part and the flicker's amplitude
    return float(math.exp(c) * share * g[0]), float(math.exp(c) * (1.0 - share))


def _wander_dominated(m: NoiseModel) -> bool:
    """A random walk (or an AR(1) with phi >= 0.95, a random walk over the variogram's 16 lags) whose per-sample
    steps are at least half the white part's size (theta <= 0.5: q / sigma_w^2 = (1 - theta)^2 / theta >= 0.5),
    seen in the sample-to-sample behaviour itself."""
    return len(m.b) == 2 and -m.b[1] >= 0.95 and -m.a[-1] <= 0.5


def _still_wandering(m: NoiseModel) -> bool:
    """The fine-scale filter of a residual with the generic structures taken away still shows a wander whose
    steps dominate the white part (theta <= 0.5). A random walk's steps are there at every scale: the smooth
    hats shorten its apparent memory (phi 0.99 -> 0.9 on 800 samples) but leave theta ~ 0. A smooth departure
    (a drift, a re-clamped specimen) that looked like wander over 16 lags goes with the hats, and what is left
    is the sensor's own noise, its white part dominant (theta 0.7 behind an AR(1) sensor)."""
    return len(m.b) == 2 and -m.b[1] >= 0.9 and -m.a[-1] <= 0.5


def reference_noise(ctx: Context, r: np.ndarray) -> NoiseModel:
    """The noise model of what is left of ``r`` once every generic structure has been fitted to it, read
    from its fine scales (``fine_scale_noise``).

    A filter profiled on a structured residual hides the structure: a slow misfit looks like a random walk,
    a ripple like a resonant AR(2) (both whiten it for free), and the test loses all its power. Fitted
    after the structures, on the fine scales, the filter sees only the noise."""
    Q, _ = np.linalg.qr(_nuisance(ctx))
    # not the line in the measured response: its columns follow the response itself, so they also draw part of
    # any slow departure (a re-clamped specimen's change of compliance), and what is left looks whiter than the
    # sensor (family 2's re-clamped recording read "agrees"); a line is a line at the fine scales too
    groups = {k: g for k, g in _groups(ctx, r).items() if k != "periodic_response"}
    B, _ = _project_out(np.column_stack([g for g, *_ in groups.values()]), Q)
    r0 = r - Q @ (Q.T @ r)
    # a sensor whose wander is as strong as its white noise shows it sample to sample; then its wander, not
    # the residual left after the slow structures took it away, says what slow structure can be claimed ...
    # ... provided the wander is still there once they are taken away (_still_wandering). Judged on the raw
    # residual alone, a warm-up drift 7.7 noise sigmas RMS behind an AR(1) sensor and a re-clamped specimen
    # (2.5 sigma) were read as wander and "agrees" (family 2, seeds 0 and 1)
    raw = fine_scale_noise(r0)
    rest = r0 - B @ (B.T @ r0) if B.shape[1] else r0
    model = fine_scale_noise(rest)
    if _wander_dominated(raw) and _still_wandering(model):
        return raw
    return dataclasses.replace(model, slow_inflation=slow_power_inflation(rest, model),
                               flicker=flicker_noise(rest, model))


def _wander(drawn: np.ndarray) -> float:
    """RMS (white sigmas) that a random walk of WANDER_SIGMAS std puts at the frequencies of ``drawn``:
    WANDER_SIGMAS sqrt((6/pi^2) sum_k p_k / k^2), p_k the share of drawn's power at k cycles per record."""
    power = np.abs(np.fft.rfft(drawn - drawn.mean()))[1:] ** 2
    total = float(power.sum())
    if total <= 0.0:
        return 0.0
    k = np.arange(1, len(power) + 1)
    return WANDER_SIGMAS * math.sqrt(6.0 / math.pi ** 2 * float(np.sum(power / k ** 2)) / total)


class _Scorer:
    """Generalised least squares of residuals on ONE basis under ONE noise filter: the basis is whitened and
    factored once, so each residual costs two products (structure_test scores ~40 residuals of a recording
    on the same bases, for speed)."""

    def __init__(self, basis: np.ndarray, noise: NoiseModel):
        self.basis = basis
        self.noise = noise
        self.qw = self.rw = None
        if basis.shape[1]:
            wb = noise.whiten(basis)
            qw, rw = np.linalg.qr(wb)
            d = np.abs(np.diag(rw))
            # a (nearly) dependent whitened column: least squares by SVD, as a factor would divide by ~0
            self.wb = wb
            if d.size and d.min() > 1e-10 * d.max():
                self.qw, self.rw = qw, rw

    def score(self, r: np.ndarray, skip: int = 0) -> tuple[float, np.ndarray | None]:
        """-2 ln L (up to constants) of r minus its GLS multiple of the basis, and the fitted part of r drawn by
        the columns after the first ``skip`` (the structure without the nuisance), or None without a basis."""
        wr = self.noise.whiten(r)
        m = len(wr)
        drawn = None
        if self.basis.shape[1]:
            if self.qw is not None:
                proj = self.qw.T @ wr
                wr = wr - self.qw @ proj
                c = np.linalg.solve(self.rw, proj) if skip < self.basis.shape[1] else None
            else:
                c, *_ = np.linalg.lstsq(self.wb, wr, rcond=None)
                wr = wr - self.wb @ c
            drawn = self.basis[:, skip:] @ c[skip:] if c is not None else np.zeros(len(r))
        rss = float(wr @ wr)
        return m * math.log(max(rss, m * NOISE_FLOOR ** 2) / m), drawn


def _scorer(ctx: Context, noise: NoiseModel, key: tuple | None, build) -> _Scorer:
    """The _Scorer of the basis ``build()``, memoised on the recording's context per noise filter under ``key``
    (group names and details); ``key`` None: a basis with a searched group (a spectral line of this residual),
    rarely met again, built and not kept (a kept one holds two whitened copies of the basis)."""
    memo = ctx.cache.setdefault("structure_scorers", {})
    full = None if key is None else (key, noise.b.tobytes(), noise.a.tobytes())
    if full in memo:
        return memo[full]
    out = _Scorer(build(), noise)
    if full is not None:
        memo[full] = out
    return out


def _projected(ctx: Context, key: tuple | None, G) -> tuple[np.ndarray, int]:
    """_project_out of the group columns ``G()`` from the nuisance, memoised on the context by ``key`` (None:
    not kept, see _scorer)."""
    memo = ctx.cache.setdefault("structure_projections", {})
    if key in memo:
        return memo[key]
    Q, _ = np.linalg.qr(_nuisance(ctx))
    out = _project_out(G(), Q)
    if key is not None:
        memo[key] = out
    return out


def structure_test(ctx: Context, r: np.ndarray, sigma_white: float, prior_chi2: float = 0.0,
                   noise: NoiseModel | None = None) -> StructureTest:
    """Generic structures of the residual ``r`` (normalised units) and their evidence.

    ``noise``: the recording's noise model (``reference_noise`` of the baseline residual), the same for every
    residual of one recording so that a model cannot buy a better score with a redder noise; estimated
    from ``r`` itself when not given.
    ``prior_chi2`` = ((s - 1)/u)^2 of the model's stiffness scale: a stiffness beyond its stated uncertainty
    is the one structure a residual cannot show (the scale absorbed it), so it is scored from the prior:
    it is significant when ((s - 1)/u)^2 > 6.63, a stiffness 2.6 prior sigmas (99 %) from the simulation.
    """
    noise = noise if noise is not None else reference_noise(ctx, r)
    n = len(r)
    ln_n = math.log(n)
    Q, _ = np.linalg.qr(_nuisance(ctx))
    base_score, _ = _scorer(ctx, noise, (), lambda: Q).score(r)
    groups = _groups(ctx, r)
    # a group is named by its name and detail (a searched frequency), which fix its columns on this context
    keys = {name: (name, detail) for name, (_, _, detail) in groups.items()}
    searched = {name for name, (_, extra, _) in groups.items() if extra}

    def kept(names) -> tuple | None:
        return None if searched.intersection(names) else tuple(keys[nm] for nm in names)

    bases = {}
    alone = {}
    size = {}
    drawns = {}
    white = {}
    for name, (G, extra, detail) in groups.items():
        key = kept((name,))
        B, rank = _projected(ctx, key, lambda G=G: G)
        bases[name] = (B, rank, extra, detail)
        score, drawn = _scorer(ctx, noise, key, lambda B=B: np.column_stack([Q, B])).score(r, Q.shape[1])
        penalty = (rank + extra) * ln_n
        drawns[name] = drawn
        alone[name] = noise.deflate(base_score - score, drawn) - penalty
        # a line in time is sized against the noise WITHOUT it: a mains line 3 white sigmas high inflates the
        # second differences it is read from, and was hidden below its own visibility floor
        white[name] = min(sigma_white, noise_std(r - drawn)) if name in UNTIED_TO_LOAD and rank else sigma_white
        size[name] = (math.sqrt(float(np.mean(drawn ** 2))) / white[name], _wander(drawn)) if rank else (0.0, 0.0)

    def joint_of(names: tuple[str, ...]) -> float:
        key = kept(names)
        key = None if key is None else ("joint",) + key
        B, _ = _projected(ctx, key, lambda: np.column_stack([bases[nm][0] for nm in names]))
        score, _ = _scorer(ctx, noise, key, lambda: np.column_stack([Q, B])).score(r)
        return score

    # joint fit: the unique share of each structure given all the others
    joint = joint_of(tuple(bases))
    structures = []
    for name, (B, rank, extra, detail) in bases.items():
        others = tuple(nm for nm in bases if nm != name)
        without = joint_of(others) if others else base_score
        unique = noise.deflate(without - joint, drawns[name]) - (rank + extra) * ln_n
        visible = name not in UNTIED_TO_LOAD or float(np.ptp(drawns[name])) >= MIN_COMPONENT_SIGMAS * white[name]
        structures.append(Structure(name, float(alone[name]), float(unique), detail,
                                    size=size[name][0], wander=size[name][1], visible=visible))
    # a stiffness outside its prior is judged as the prior states it: beyond 2.6 sigma (p < 0.01)
    structures.append(Structure("stiffness", float(prior_chi2), float(prior_chi2), threshold=STIFFNESS_CHI2))
    w = noise.whiten(r)
    return StructureTest(tuple(structures), float(np.mean(r ** 2)) / max(sigma_white ** 2, 1e-300), lag1(r),
                         float(w @ w) * n / max(len(w), 1))


def describe(test: StructureTest, ctx: Context, located_text: str, dt_s: float | None, stride: int = 1) -> str:
    """The residual's structure in physical terms (what a test engineer can act on). ``dt_s``: time between
    fitted rows; ``stride``: recording rows per fitted row (periods are quoted in recording rows)."""
    if not test.structured:
        return "the residual is consistent with the noise"
    sig = {s.name for s in test.significant}
    parts = []
    load_like = sig & {"odd", "even", "load"}
    if load_like:
        if "odd" in sig and "even" not in sig:
            kind = "odd in load (the same change for both torque signs, mirrored)"
        elif "even" in sig and "odd" not in sig:
            kind = "even in load (different for the two load signs: one-sided)"
        elif {"odd", "even"} <= sig:
            kind = "neither odd nor even in load"
        else:
            kind = "a function of the load"
        parts.append(f"it depends on the load, {kind}; {located_text}")
    if "stiffness" in sig:
        parts.append("the linear stiffness differs from the baseline by more than its stated uncertainty")
    if "branch" in sig:
        parts.append("it is hysteretic: loading and unloading branches differ")
    if "rate" in sig and (test.get("rate").unique_delta_bic > THRESHOLD or "branch" not in sig):
        parts.append("it depends on the loading rate (a viscous or viscoelastic part, or one channel recorded "
                     "later than the other)")
    if "creep" in sig and (test.get("creep").unique_delta_bic > THRESHOLD or not ({"rate", "branch"} & sig)):
        parts.append("it creeps: the response keeps moving while the load is held (a viscoelastic part, or "
                     "relaxation in the load train: rate-dependent, a test at a second loading rate or with a "
                     "hold shows it)")
    if "time_load" in sig and (test.get("time_load").unique_delta_bic > THRESHOLD or not load_like):
        parts.append("the compliance changes during the test (time-varying stiffness: a re-clamped or "
                     "exchanged specimen, a sensor gain that drifts, or a rate-dependent (creeping) part)")
    if "time" in sig and (test.get("time").unique_delta_bic > THRESHOLD or not (load_like or "branch" in sig)):
        parts.append("it varies in time at constant load (a drift that is not linear, or creep)")
    if "periodic_time" in sig and (test.get("periodic_time").unique_delta_bic > THRESHOLD or len(sig) == 1):
        f = float(test.get("periodic_time").detail)
        period = (f"{stride / f:.4g} samples" + (f" = {dt_s / f:.4g} s" if dt_s else "")) if f > 0 else "?"
        # read on every stride-th row, a ripple faster than two strides folds onto a slower one
        alias = (f"; read on every {stride}th row, so a ripple faster than {2 * stride} rows would show at this "
                 f"period (an alias): check it on the full recording") if stride > 1 else ""
        parts.append(f"it is periodic in time with period {period} (not a function of the load){alias}")
    if "angle_load" in sig and (test.get("angle_load").unique_delta_bic > THRESHOLD or len(sig) == 1):
        parts.append("it ripples with the input angle, growing with the load (a torsional stiffness that varies "
                     "with the wave generator's angle: mesh stiffness variation, or a crack opening and closing as "
                     "the major axis passes it)")
    if "periodic_response" in sig and (test.get("periodic_response").unique_delta_bic > THRESHOLD or len(sig) == 1):
        f = float(test.get("periodic_response").detail)
        parts.append(f"it is periodic in the measured response itself, period {ctx.Y / f:.4g} {ctx.response_unit} "
                     f"of the reading, at any load and time (an angle encoder's interpolation error repeats every "
                     f"line pitch)")
    if "periodic_angle" in sig:
        parts.append(f"it is periodic in the input angle, {test.get('periodic_angle').detail} per revolution")
    if not parts:
        parts.append("structured, but no single simple pattern dominates")
    parts.append(f"residual variance {test.chi2_per_sample:.3g} x the white-noise estimate, lag-1 "
                 f"autocorrelation {test.lag1:.2f}")
    return "; ".join(parts)


__all__ = ["MIN_COMPONENT_SIGMAS", "NoiseModel", "Structure", "StructureTest", "THRESHOLD", "describe", "fine_scale_noise", "flicker_noise",
           "reference_noise", "structure_test"]
