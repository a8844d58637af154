"""Is a residual consistent with the noise? A goodness-of-fit test that does not know the catalogue.

The residual r of a model is offered a few generic, catalogue-free structures, each a small linear basis
(binned means in disguise: piecewise-linear hats):
- ``odd`` / ``even`` (two-sided loads) or ``load`` (one-sided): a smooth function of the load;
- ``branch``: a function of the load that differs between loading and unloading (hysteretic);
- ``time``: a slow function of time at any load (drift that is not linear);
- ``time_load``: a compliance that changes during the test (u times hats in time: re-clamping, a second
  specimen, warm-up of the gain);
- ``periodic_time``: a sinusoid at the residual's strongest spectral line (period reported);
- ``periodic_angle``: a sinusoid in the wave generator's input angle (when recorded), k per revolution.
Each is scored under the same coloured-noise likelihood as the catalogue (fit.bic_ar, fit.noise_filter): delta BIC =
N ln(RSS_e(r) / RSS_e(r - G c)) - rank(G) ln N (and + ln N for a searched frequency). A structure is
significant when delta BIC > 10 ("very strong"); its unique share is its drop from the joint fit of all
structures. Coloured noise is no structure: its wander costs what an AR process of that size costs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .effects.base import Context
from .fit import NOISE_FLOOR, lag1, noise_filter

THRESHOLD = 10.0
STIFFNESS_CHI2 = 6.63     # chi-square(1) at 99 %: 2.58 prior sigmas
_TWO_SIDED_KNOTS = (0.0, 0.1, 0.3, 0.55, 0.8, 1.0)
_ONE_SIDED_KNOTS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)


@dataclass(frozen=True)
class Structure:
    name: str
    delta_bic: float           # added alone to the model
    unique_delta_bic: float    # dropped from the joint fit of all structures
    detail: str = ""           # e.g. the period
    threshold: float = THRESHOLD

    @property
    def significant(self) -> bool:
        return self.delta_bic > self.threshold

    def to_dict(self) -> dict:
        return {"name": self.name, "delta_bic": self.delta_bic, "unique_delta_bic": self.unique_delta_bic,
                "detail": self.detail}


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


def _spectral_line(r: np.ndarray) -> tuple[float, float]:
    """(frequency in cycles per sample, refined) of the largest periodogram peak above the slowest 3 bins."""
    n = len(r)
    spec = np.abs(np.fft.rfft((r - r.mean()) * np.hanning(n))) ** 2
    if len(spec) < 8:
        return 0.0, 0.0
    spec[:4] = 0.0
    k = int(np.argmax(spec))
    if 0 < k < len(spec) - 1:
        a, b, c = np.log(spec[k - 1:k + 2] + 1e-300)
        den = a - 2 * b + c
        k = k + (0.5 * (a - c) / den if den < 0 else 0.0)
    return k / n, float(spec.max())


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
    return out


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


def _whiten(x: np.ndarray, b: np.ndarray, a: np.ndarray) -> np.ndarray:
    """Innovations of x under the noise filter (b, a), start-up samples dropped; vectors or column stacks."""
    from scipy.signal import lfilter
    return lfilter(b, a, x, axis=0)[len(b) - 1:]


def _score(r: np.ndarray, basis: np.ndarray) -> float:
    """-2 ln L (up to constants) of r minus the best multiple of ``basis`` under the profiled noise filter.

    The coefficients come from ordinary least squares and from generalised least squares (whitened with the
    noise filter of the current residual, iterated twice); the best pair (coefficients, filter) is kept.
    OLS alone would be wrong under coloured noise: fitting a sharp basis function to a smooth residual puts
    jumps into it that the coloured-noise likelihood then punishes."""
    n = len(r)
    if basis.shape[1] == 0:
        rss, _, _ = noise_filter(r)
        return n * math.log(max(rss, n * NOISE_FLOOR ** 2) / n)
    c = basis.T @ r
    best = None
    filt = noise_filter(r)
    for it in range(3):
        r2 = r - basis @ c
        cur = noise_filter(r2)
        best = cur[0] if best is None or cur[0] < best else best
        if it == 2:
            break
        b, a = (filt[1], filt[2]) if it == 0 else (cur[1], cur[2])
        wb, wr = _whiten(basis, b, a), _whiten(r, b, a)
        c, *_ = np.linalg.lstsq(wb, wr, rcond=None)
    return n * math.log(max(best, n * NOISE_FLOOR ** 2) / n)


def structure_test(ctx: Context, r: np.ndarray, sigma_white: float, prior_chi2: float = 0.0) -> StructureTest:
    """Generic structures of the residual ``r`` (normalised units) and their evidence.

    ``prior_chi2`` = ((s - 1)/u)^2 of the model's stiffness scale: a stiffness beyond its stated uncertainty
    is the one structure a residual cannot show (the scale absorbed it), so it is scored from the prior:
    it is significant when ((s - 1)/u)^2 > 6.63, a stiffness 2.6 prior sigmas (99 %) from the simulation.
    """
    n = len(r)
    ln_n = math.log(n)
    Q, _ = np.linalg.qr(_nuisance(ctx))
    base_score = _score(r, np.zeros((n, 0)))
    groups = _groups(ctx, r)
    bases = {}
    alone = {}
    for name, (G, extra, detail) in groups.items():
        B, rank = _project_out(G, Q)
        bases[name] = (B, rank, extra, detail)
        alone[name] = base_score - _score(r, B) - (rank + extra) * ln_n
    # joint fit: the unique share of each structure given all the others
    allB, _ = _project_out(np.column_stack([b for b, *_ in bases.values()]), Q)
    joint = _score(r, allB)
    structures = []
    for name, (B, rank, extra, detail) in bases.items():
        others = [b for nm, (b, *_rest) in bases.items() if nm != name]
        if others:
            ob, _ = _project_out(np.column_stack(others), Q)
            without = _score(r, ob)
        else:
            without = base_score
        structures.append(Structure(name, float(alone[name]), float(without - joint - (rank + extra) * ln_n), detail))
    # a stiffness outside its prior is judged as the prior states it: beyond 2.6 sigma (p < 0.01)
    structures.append(Structure("stiffness", float(prior_chi2), float(prior_chi2), threshold=STIFFNESS_CHI2))
    rss_e, _, _ = noise_filter(r)
    return StructureTest(tuple(structures), float(np.mean(r ** 2)) / max(sigma_white ** 2, 1e-300), lag1(r),
                         rss_e)


def describe(test: StructureTest, ctx: Context, located_text: str, dt_s: float | None) -> str:
    """The residual's structure in physical terms (what a test engineer can act on)."""
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
    if "time_load" in sig and (test.get("time_load").unique_delta_bic > THRESHOLD or not load_like):
        parts.append("the compliance changes during the test (time-varying stiffness: a re-clamped or "
                     "exchanged specimen, a sensor gain that drifts, or a rate-dependent (creeping) part)")
    if "time" in sig and (test.get("time").unique_delta_bic > THRESHOLD or not (load_like or "branch" in sig)):
        parts.append("it varies in time at constant load (a drift that is not linear, or creep)")
    if "periodic_time" in sig and (test.get("periodic_time").unique_delta_bic > THRESHOLD or len(sig) == 1):
        f = float(test.get("periodic_time").detail)
        period = (f"{1.0 / f:.4g} samples" + (f" = {dt_s / f:.4g} s" if dt_s else "")) if f > 0 else "?"
        parts.append(f"it is periodic in time with period {period} (not a function of the load)")
    if "periodic_angle" in sig:
        parts.append(f"it is periodic in the input angle, {test.get('periodic_angle').detail} per revolution")
    if not parts:
        parts.append("structured, but no single simple pattern dominates")
    parts.append(f"residual variance {test.chi2_per_sample:.3g} x the white-noise estimate, lag-1 "
                 f"autocorrelation {test.lag1:.2f}")
    return "; ".join(parts)


__all__ = ["Structure", "StructureTest", "THRESHOLD", "describe", "structure_test"]
