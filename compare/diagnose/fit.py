"""Fit the baseline plus zero, one or two catalogue effects; score each fit by BIC under coloured noise.

Model (normalised units, see effects/base.py):  y = b0 + b1 t + s u + sum_k effect_k(theta_k) + noise.
b0, b1 (channel zero offset and drift) and s (stiffness scale) enter linearly and are eliminated
by least squares inside every residual evaluation (variable projection); s carries the Gaussian
prior 1 +/- baseline_uncertainty. So are the weights of every form linear in its parameters (Effect.basis: a
density of play operators or relays, a ripple's amplitudes, a monotone stiffening's slope changes), by bounded
linear least squares (`_Separable`).
The other effect parameters are fitted by bounded trust-region least squares from a few starts.

Noise is not assumed white: real sensors drift, are low-pass filtered and wander. The likelihood of
every model is that of an AR(2) or ARMA(1,1) noise process (noise_filter: whichever whitens better, both two
parameters) whose coefficients are profiled on the model's own
residual r (conditional Gaussian likelihood: innovations e_k = r_k - a1 r_(k-1) - a2 r_(k-2)):
    BIC = N ln(RSS_e / N) + ((s - 1)/u)^2 + (k + 2) ln N,   RSS_e = min_a sum e_k^2 (>= N floor^2),
k = 3 + effect parameters, ((s - 1)/u)^2 = -2 ln(prior). For white noise a ~ 0 and this is the usual BIC;
for AR(1) noise with rho -> 1 (a random walk) the innovations are the first differences, so a slow wander
of the residual costs what a random walk of that size costs, not what N independent samples would.
A systematic misfit can therefore raise BIC by at most ~N ln(1.5 .. 2) against a model that fits: the
evidence for a second effect that only mops up a rigid model's misfit stays bounded.
"""
from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import least_squares, lsq_linear, nnls

from strainwave.compare.diagnose.effects.base import Context, Effect

# 10 ppm of the full-scale response: no strain gauge or encoder test resolves less; used as the least
# noise level, so synthetic noise-free files do not turn a stiffness error inside the prior into "evidence"
NOISE_FLOOR = 1e-5
AR_ORDER = 2


def ar_profile(r: np.ndarray, order: int = AR_ORDER) -> tuple[float, np.ndarray]:
    """(innovation sum of squares rescaled to len(r) samples, AR coefficients) of the least-squares AR fit."""
    n = len(r)
    if order == 0 or n <= 4 * order:
        return float(r @ r), np.zeros(order)
    lags = np.column_stack([r[order - 1 - i:n - 1 - i] for i in range(order)])
    target = r[order:]
    coef, *_ = np.linalg.lstsq(lags, target, rcond=None)
    e = target - lags @ coef
    return float(e @ e) * n / (n - order), coef


# ARMA(1,1) grid: a white sensor with a slow wander (random walk, drifting reference) is ARIMA(0,1,1), which a
# short AR filter cannot whiten; e_k = r_k - phi r_(k-1) + theta e_(k-1) can (phi -> 1, theta -> 1)
_PHIS = (0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 1.0)
_THETAS = (0.0, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98)


def noise_filter(r: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """(innovation sum of squares, b, a): the best two-parameter noise filter e = lfilter(b, a, r), AR(2) or
    ARMA(1,1), by least innovation variance (both have two parameters, so the comparison is fair).

    Only white or red noise is allowed (spectral density at zero frequency >= at Nyquist): sensor noise is
    white, low-pass filtered or wandering, never short of slow power. A residual from which structures were
    fitted away IS short of slow power, and a blue filter fitted to it would amplify every slow departure
    (docs/decisions/023-diagnose-noise-model.md)."""
    from scipy.signal import lfilter
    n = len(r)
    white = (float(r @ r), np.array([1.0]), np.array([1.0]))
    rss, coef = ar_profile(r)
    # AR whitening polynomial A(z) = 1 - a1 z - a2 z^2; noise spectrum 1/|A|^2 is red when |A(1)| <= |A(-1)|
    red = abs(1.0 - coef.sum()) <= abs(1.0 + coef[0] - coef[1:].sum()) if len(coef) else True
    best = (rss, np.concatenate([[1.0], -coef]), np.array([1.0])) if red and rss < white[0] else white
    if n <= 8:
        return best
    for phi in _PHIS:
        d = r[1:] - phi * r[:-1]
        for th in _THETAS:
            if th > phi:
                continue                      # (1 - theta z)/(1 - phi z) with theta > phi is blue
            e = lfilter([1.0], [1.0, -th], d) if th else d
            val = float(e @ e) * n / (n - 1)
            if val < best[0]:
                best = (val, np.array([1.0, -phi]), np.array([1.0, -th]))
    return best


def lag1(r: np.ndarray) -> float:
    """Lag-1 autocorrelation of a residual (0 for white noise)."""
    r = r - r.mean()
    den = float(r @ r)
    return float(r[1:] @ r[:-1]) / den if den > 0 else 0.0


def bic_ar(r: np.ndarray, k: int, prior_chi2: float) -> float:
    """BIC of a model with residual ``r``, ``k`` regression parameters, the prior's -2 ln p, AR(2) noise."""
    n = len(r)
    rss_e, _, _ = noise_filter(r)
    return n * math.log(max(rss_e, n * NOISE_FLOOR ** 2) / n) + prior_chi2 + (k + AR_ORDER) * math.log(n)


def bic_fixed_noise(r: np.ndarray, k: int, prior_chi2: float, noise) -> float:
    """BIC of a residual under the recording's ONE noise model (``noise.whiten``, structure.NoiseModel).

    Profiled per model (``bic_ar``), the noise filter is free to whiten a model's slow misfit and buy it as
    "noise" (docs/decisions/023-diagnose-noise-model.md). Held fixed, the filter prices every model's residual alike."""
    e = noise.whiten(r)
    m = len(e)
    return m * math.log(max(float(e @ e), m * NOISE_FLOOR ** 2) / m) + prior_chi2 + (k + AR_ORDER) * math.log(len(r))


@dataclass(frozen=True)
class Fit:
    effects: tuple[Effect, ...]
    theta: np.ndarray            # effect parameters, concatenated
    nuisance: tuple[float, float, float]   # b0, b1, s
    model: np.ndarray            # normalised prediction
    rss: float                   # plain residual sum of squares (normalised units)
    bic: float
    k: int
    # covariance of (theta, s), s last: the stiffness scale's own error enters every slope read from it (K1)
    cov: np.ndarray | None = None
    at_bound: tuple[str, ...] = ()    # parameters that ended on a bound of their plausible range
    prior_chi2: float = 0.0           # ((s - 1)/u)^2
    design: np.ndarray | None = None  # d model / d (theta, b0, b1, s) at the fit (n x (p + 3))
    uncertainty: float = 0.02         # the prior's relative sigma on s (its information 1/u^2 joins the data's)

    @property
    def id(self) -> str:
        return "+".join(e.id for e in self.effects) if self.effects else "baseline"

    @property
    def label(self) -> str:
        return "+".join(e.label for e in self.effects) if self.effects else "baseline"

    @property
    def scale(self) -> float:
        return self.nuisance[2]

    def split_theta(self) -> list[np.ndarray]:
        out, i = [], 0
        for e in self.effects:
            out.append(self.theta[i:i + e.n_params])
            i += e.n_params
        return out

    def split_cov(self) -> list[np.ndarray | None]:
        """Per effect: the covariance of (its theta, s), s last."""
        if self.cov is None:
            return [None] * len(self.effects)
        out, i = [], 0
        for e in self.effects:
            idx = [*range(i, i + e.n_params), self.cov.shape[0] - 1]
            out.append(self.cov[np.ix_(idx, idx)])
            i += e.n_params
        return out

    def rms(self, n: int) -> float:
        return math.sqrt(self.rss / n)


class _Projector:
    """Solves the 3x3 normal equations for (b0, b1, s) with the prior row on s."""

    def __init__(self, ctx: Context, prior_weight: float):
        self.A = np.column_stack([np.ones_like(ctx.u), ctx.t, ctx.u])
        self.lam2 = prior_weight ** 2
        self.M = self.A.T @ self.A
        self.M[2, 2] += self.lam2
        self.Minv = np.linalg.inv(self.M)
        self.lam = prior_weight

    def solve(self, z: np.ndarray) -> np.ndarray:
        rhs = self.A.T @ z
        rhs[2] += self.lam2
        return self.Minv @ rhs


def fit_effects(ctx: Context, effects: tuple[Effect, ...], sigma: float, uncertainty: float,
                starts: list[np.ndarray] | None = None, max_nfev: int = 150, noise=None) -> Fit:
    """Best fit of baseline + ``effects``; ``sigma`` is the noise std in normalised units; ``noise``: the
    recording's noise model to score the BIC with (``bic_fixed_noise``), else profiled (``bic_ar``)."""
    proj = _Projector(ctx, sigma / uncertainty)
    n = len(ctx.u)
    contribution = _Contribution(ctx, effects)

    @_last_call
    def residual(theta):
        z = ctx.y - contribution(theta)
        beta = proj.solve(z)
        r = z - proj.A @ beta
        return np.concatenate((r, [proj.lam * (beta[2] - 1.0)]))

    params = [p for e in effects for p in e.params]
    at_bound: tuple[str, ...] = ()
    if params:
        lo = np.array([p.lo for p in params])
        hi = np.array([p.hi for p in params])
        sep = _Separable(ctx, effects, proj, lo, hi)
        reduced = _last_call(lambda x: sep.residual(residual, x))
        theta = sep.theta(residual, _search(reduced, effects, starts, lo[sep.other], hi[sep.other], sep.other,
                                            max_nfev))
        # a parameter pinned at a bound that is not a physical zero (e.g. a weight >= 0) is reported
        names = [f"{e.id}.{p.name}" for e in effects for p in e.params]
        at_bound = tuple(nm for nm, x, a, b, p in zip(names, theta, lo, hi, params)
                         if (x - a < 1e-4 * (b - a) and a != 0.0) or (b - x < 1e-4 * (b - a)))
    else:
        theta = np.zeros(0)
    z = ctx.y - contribution(theta)
    beta = proj.solve(z)
    model = contribution(theta) + proj.A @ beta
    r = ctx.y - model
    rss = float(r @ r)
    prior_chi2 = ((beta[2] - 1.0) / uncertainty) ** 2
    k = 3 + len(params)
    bic = bic_ar(r, k, prior_chi2) if noise is None else bic_fixed_noise(r, k, prior_chi2, noise)
    design = _design(contribution, theta, proj.A, np.array([p.hi for p in params])) if params else None
    cov = None
    if design is not None:
        if noise is not None:
            cov = gls_cov(design, r, k, noise, uncertainty)
        else:
            # residual variance with the AR(1) effective-sample inflation (1 + rho)/(1 - rho) for correlated noise
            rho = min(max(lag1(r), 0.0), 0.99)
            s2 = rss / max(n - k, 1) * (1.0 + rho) / (1.0 - rho)
            cov = _theta_and_scale(design.T @ design / s2, uncertainty)
    return Fit(effects, theta, (float(beta[0]), float(beta[1]), float(beta[2])), model, rss, bic, k, cov,
               at_bound, float(prior_chi2), design, uncertainty)


class _Contribution:
    """The effects' summed contribution at theta; each effect's last evaluation is kept, so a difference step in
    one effect's parameter (the Jacobian of a pair) does not evaluate the other effect again."""

    def __init__(self, ctx: Context, effects: tuple[Effect, ...]):
        self.ctx, self.effects, self.n = ctx, effects, len(ctx.u)
        self.last: list[tuple[bytes, np.ndarray] | None] = [None] * len(effects)

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        total = np.zeros(self.n)
        i = 0
        for k, e in enumerate(self.effects):
            part = np.asarray(theta[i:i + e.n_params], dtype=float)
            key = part.tobytes()
            if self.last[k] is None or self.last[k][0] != key:
                self.last[k] = (key, e.contribution(self.ctx, part))
            total += self.last[k][1]
            i += e.n_params
        return total


def _last_call(fn):
    """``fn`` (of a float vector) remembering its last argument and result: the optimiser's Jacobian step
    evaluates the residual again at the point it has just accepted."""
    last: list = [None, None]

    def wrapped(theta):
        key = np.asarray(theta, dtype=float).tobytes()
        if last[0] != key:
            last[0], last[1] = key, fn(theta)
        return last[1].copy()
    return wrapped


def _search(reduced, effects: tuple[Effect, ...], starts, lo: np.ndarray, hi: np.ndarray, other: np.ndarray,
            max_nfev: int) -> np.ndarray:
    """The best trust-region fit of the parameters ``other`` (the non-separable ones) over the starts: the
    given ones, else every combination of the parameters' own starting values; starts alike there are run once."""
    if not other.size:
        return np.zeros(0)
    params = [p for e in effects for p in e.params]
    if starts is None:
        starts = [np.array(c) for c in itertools.product(*(params[i].starts for i in other))]
    else:
        starts = [np.asarray(x0, dtype=float)[other] for x0 in starts]
    best, tried = None, set()
    for x0 in starts:
        x0 = np.clip(np.asarray(x0, dtype=float), lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
        if x0.tobytes() in tried:
            continue
        tried.add(x0.tobytes())
        sol = least_squares(reduced, x0, bounds=(lo, hi), method="trf", x_scale=np.maximum(hi - lo, 1e-3) * 0.1,
                            max_nfev=max_nfev, diff_step=1e-4)
        if best is None or sol.cost < best.cost:
            best = sol
    return best.x


class _Separable:
    """The weights of the forms linear in their parameters (Effect.basis), solved inside every residual evaluation
    by bounded linear least squares (variable projection): the trust region searches only the other parameters,
    with fewer difference steps and smaller decompositions, and the weights are the exact optimum given them.

    At zero weights the residual is q; with weights w it is q + J w, J = -(I - P) basis with the prior row
    -lam d beta_s (beta = Minv (A^T (y - c) + lam^2 e_s), so d beta = -Minv A^T basis)."""

    def __init__(self, ctx: Context, effects: tuple[Effect, ...], proj: "_Projector", lo: np.ndarray,
                 hi: np.ndarray):
        offsets = np.cumsum([0] + [e.n_params for e in effects])
        self.linear = np.array([i for e, a, b in zip(effects, offsets[:-1], offsets[1:]) if e.basis is not None
                                for i in range(a, b)], dtype=int)
        self.other = np.setdiff1d(np.arange(offsets[-1]), self.linear)
        self.lo, self.hi = lo[self.linear], hi[self.linear]
        if self.linear.size:
            B = np.column_stack([e.basis(ctx) for e in effects if e.basis is not None])
            dbeta = proj.Minv @ (proj.A.T @ B)
            self.J = np.vstack([-(B - proj.A @ dbeta), -proj.lam * dbeta[2]])
            # a weight whose column vanishes on the recorded path (relays the load never switches) cannot move the
            # residual: it stays at zero (inside its bounds), and the others are solved without it
            norms = np.linalg.norm(self.J, axis=0)
            self.live = norms > 1e-12 * norms.max()
            self.Q, self.R = np.linalg.qr(self.J[:, self.live])

    def _full(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        theta = np.zeros(len(self.linear) + len(self.other))
        theta[self.other] = x
        theta[self.linear] = w
        return theta

    def weights(self, q: np.ndarray) -> np.ndarray:
        """argmin |q + J w| over lo <= w <= hi."""
        w = np.clip(np.zeros(len(self.lo)), self.lo, self.hi)
        if self.live.any():
            w[self.live] = self._live_weights(-(self.Q.T @ q), self.lo[self.live], self.hi[self.live])
        return w

    def _live_weights(self, rhs: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """argmin |R w - rhs| over lo <= w <= hi: the unconstrained optimum where it is inside the box (the problem
        is convex), else the optimum with the lower bounds only (NNLS from lo), else (or when NNLS stalls) the bounded
        one (BVLS)."""
        with np.errstate(all="ignore"):
            try:
                w = solve_triangular(self.R, rhs)
            except np.linalg.LinAlgError:
                w = np.full(len(lo), np.nan)
        if np.all((w >= lo) & (w <= hi)):
            return w
        try:
            w = lo + nnls(self.R, rhs - self.R @ lo)[0]
            if np.all(w <= hi):
                return w
        except RuntimeError:        # scipy's NNLS can stall at its iteration cap on a well-posed problem: BVLS solves it
            pass
        return np.clip(lsq_linear(self.R, rhs, bounds=(lo, hi), method="bvls").x, lo, hi)

    def residual(self, residual, x: np.ndarray) -> np.ndarray:
        """The residual at the other parameters ``x`` with the weights at their optimum given them."""
        q = residual(self._full(x, np.zeros(len(self.linear))))
        return q + self.J @ self.weights(q) if self.linear.size else q

    def theta(self, residual, x: np.ndarray) -> np.ndarray:
        """All parameters, in the effects' order: ``x`` with the weights solved at it."""
        if not self.linear.size:
            return self._full(x, np.zeros(0))
        return self._full(x, self.weights(residual(self._full(x, np.zeros(len(self.linear))))))


def _design(contribution, theta: np.ndarray, nuisance: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """d model / d (theta, b0, b1, s): forward differences of the effects (the optimiser's step, towards the
    interior at an upper bound) beside the nuisance columns (1, t, u), which enter linearly."""
    c0 = contribution(theta)
    cols = []
    for j in range(len(theta)):
        h = 1e-4 * max(1.0, abs(theta[j]))
        if theta[j] + h > hi[j]:
            h = -h
        th = theta.copy()
        th[j] += h
        cols.append((contribution(th) - c0) / h)
    return np.column_stack([*cols, nuisance])


def _theta_and_scale(information: np.ndarray, uncertainty: float) -> np.ndarray:
    """Covariance of (theta, s) from the information of (theta, b0, b1, s) plus the prior's 1/u^2 on s: the
    offset and drift are marginalised, not held fixed."""
    info = information.copy()
    info[-1, -1] += 1.0 / uncertainty ** 2
    cov = np.linalg.pinv(info)
    keep = [*range(info.shape[0] - 3), info.shape[0] - 1]
    return cov[np.ix_(keep, keep)]


def gls_cov(design: np.ndarray, r: np.ndarray, k: int, noise, uncertainty: float) -> np.ndarray:
    """Covariance of (theta, s) under the recording's noise model: the design and the residual both whitened by
    its filter (generalised least squares): the lag-1 inflation of white least squares misses a wandering
    sensor's long-range correlation (docs/decisions/023-diagnose-noise-model.md)."""
    dw, rw = noise.whiten(design), noise.whiten(r)
    s2 = float(rw @ rw) / max(len(rw) - k, 1)
    return _theta_and_scale(dw.T @ dw / s2, uncertainty)


def rescored(fit: Fit, ctx: Context, noise) -> Fit:
    """The same fit with its BIC (and its parameter covariance) under the recording's fixed noise model."""
    r = ctx.y - fit.model
    cov = gls_cov(fit.design, r, fit.k, noise, fit.uncertainty) if fit.design is not None else fit.cov
    return dataclasses.replace(fit, bic=bic_fixed_noise(r, fit.k, fit.prior_chi2, noise), cov=cov)


__all__ = ["AR_ORDER", "Fit", "NOISE_FLOOR", "ar_profile", "bic_ar", "bic_fixed_noise", "noise_filter", "fit_effects",
           "gls_cov", "lag1", "rescored"]
