"""Fit the baseline plus zero, one or two catalogue effects; score each fit by BIC.

Model (normalised units, see effects/base.py):  y = b0 + b1 t + s u + sum_k effect_k(theta_k).
b0, b1 (channel zero offset and drift) and s (stiffness scale) enter linearly and are eliminated
by least squares inside every residual evaluation (variable projection); s carries the Gaussian
prior 1 +/- baseline_uncertainty, so a stiffness error within the stated uncertainty is absorbed
at a small, honest cost instead of being called a mismatch.
The effect parameters are fitted by bounded trust-region least squares from a few starts.

BIC = N ln(RSS_aug / N) + k ln N, RSS_aug = max(RSS, N floor^2) + sigma^2 ((s - 1)/u)^2 (the prior as
one extra datum), k = 3 + effect parameters. Profiling the noise variance keeps the comparison valid even
where the noise estimate is rough.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .effects.base import Context, Effect

# 10 ppm of the full-scale response: no strain gauge or encoder test resolves less; used as the least
# noise level, so synthetic noise-free files do not turn a stiffness error inside the prior into "evidence"
NOISE_FLOOR = 1e-5


@dataclass(frozen=True)
class Fit:
    effects: tuple[Effect, ...]
    theta: np.ndarray            # effect parameters, concatenated
    nuisance: tuple[float, float, float]   # b0, b1, s
    model: np.ndarray            # normalised prediction
    rss: float                   # plain residual sum of squares (normalised units)
    bic: float
    k: int

    @property
    def id(self) -> str:
        return "+".join(e.id for e in self.effects) if self.effects else "baseline"

    @property
    def scale(self) -> float:
        return self.nuisance[2]

    def split_theta(self) -> list[np.ndarray]:
        out, i = [], 0
        for e in self.effects:
            out.append(self.theta[i:i + e.n_params])
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
                starts: list[np.ndarray] | None = None, max_nfev: int = 150) -> Fit:
    """Best fit of baseline + ``effects``; ``sigma`` is the noise std in normalised units."""
    proj = _Projector(ctx, sigma / uncertainty)
    n = len(ctx.u)

    def contribution(theta):
        total = np.zeros(n)
        i = 0
        for e in effects:
            total += e.contribution(ctx, theta[i:i + e.n_params])
            i += e.n_params
        return total

    def residual(theta):
        z = ctx.y - contribution(theta)
        beta = proj.solve(z)
        r = z - proj.A @ beta
        return np.append(r, proj.lam * (beta[2] - 1.0))

    params = [p for e in effects for p in e.params]
    if params:
        lo = np.array([p.lo for p in params])
        hi = np.array([p.hi for p in params])
        candidates = starts if starts is not None else [np.array(c) for c in itertools.product(*(p.starts for p in params))]
        best = None
        for x0 in candidates:
            x0 = np.clip(np.asarray(x0, dtype=float), lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
            sol = least_squares(residual, x0, bounds=(lo, hi), method="trf", x_scale=np.maximum(hi - lo, 1e-3) * 0.1,
                                max_nfev=max_nfev, diff_step=1e-4)
            if best is None or sol.cost < best.cost:
                best = sol
        theta = best.x
    else:
        theta = np.zeros(0)
    z = ctx.y - contribution(theta)
    beta = proj.solve(z)
    model = contribution(theta) + proj.A @ beta
    rss = float(np.sum((ctx.y - model) ** 2))
    # never below the instrument floor: on noise-free data the log of a vanishing RSS would turn any
    # difference into "evidence", while the prior term says a stiffness error within u is no evidence
    rss_aug = max(rss, n * NOISE_FLOOR ** 2) + proj.lam2 * (beta[2] - 1.0) ** 2
    k = 3 + len(params)
    bic = n * math.log(max(rss_aug, 1e-300) / n) + k * math.log(n)
    return Fit(effects, theta, (float(beta[0]), float(beta[1]), float(beta[2])), model, rss, bic, k)
