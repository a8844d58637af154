"""The catalogue's numbers read from a measured loop, as Harmonic Drive defines them.

Harmonic Drive (CHA manual 1018854, "Torsional stiffness") splits the torque-torsion curve into three
linearised regions: K1 from 0 to T1, K2 from T1 to T2, K3 above T2. The curve is the MEAN of the loop's two
branches; the branches' difference is the loop:

- hysteresis loss: the twist on the unloading branch minus the twist on the loading branch at zero torque, of a
  +/- rated torque cycle;
- lost motion: the twist travelled between +4 % and -4 % of the rated torque when the torque reverses, read on
  the loop as (unloading branch at +4 %) - (loading branch at -4 %): the mean curve's twist over +/-4 % plus the
  loop's width there.

One least-squares model of every steady branch (the virgin first loading is left out) draws both at once:
    y = b0 + b1 t + c1 u + (c2 - c1) sgn(u) (|u| - p1)+ + (c3 - c2) sgn(u) (|u| - p2)+ + dir h(|u|),
h a cubic in |u| (the loop's half-width, signed: negative when the twist lags the torque), u and y the
normalised torque and twist (effects.base.Context). T1 = p1 X, T2 = p2 X, K_i = 1 / (c_i c0). p1, p2 are found on
a grid, then refined with the linear terms. Standard errors: the Jacobian's covariance scaled by the residual
variance, inflated by (1 + rho)/(1 - rho) for the residual's lag-1 correlation (a quantised, filtered channel).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.effects.loop import ARCMIN_PER_RAD
from strainwave.compare.diagnose.fit import lag1

LOST_MOTION_FRACTION = 0.04      # of the rated torque (Harmonic Drive's lost-motion torque)
GRID = np.linspace(0.04, 0.96, 24)   # knot positions tried, fraction of the largest torque
MIN_GAP = 0.04                   # T2 - T1 at least this fraction of the largest torque
# a loop read at an amplitude this far from the rated torque is not the catalogue's loss: said in a warning
AMPLITUDE_TOLERANCE = 0.05
SOURCE = "Harmonic Drive AG, CHA manual 1018854 (torsional stiffness K1, K2, K3, T1, T2; hysteresis loss; lost motion)"


@dataclass(frozen=True)
class CatalogueValues:
    """name -> (value, standard error, unit), and what a reader must know about them."""

    values: dict
    warnings: tuple[str, ...]
    source: str = SOURCE


def _steady(ctx: Context) -> np.ndarray:
    """Rows on a branch after a reversal (the first loading starts from an unknown, virgin state)."""
    keep = np.ones(len(ctx.u), dtype=bool)
    if len(ctx.segments) > 1:
        keep[:ctx.segments[1][0]] = False
    return keep


def _columns(u: np.ndarray, t: np.ndarray, d: np.ndarray, p1: float, p2: float) -> np.ndarray:
    m, s = np.abs(u), np.sign(u)
    return np.column_stack([np.ones_like(u), t, u, s * np.maximum(m - p1, 0.0), s * np.maximum(m - p2, 0.0),
                            d, d * m, d * m ** 2, d * m ** 3])


def _model(x: np.ndarray, u, t, d) -> np.ndarray:
    p1, p2 = x[-2], x[-1]
    return _columns(u, t, d, p1, p2) @ x[:-2]


def _grid_start(u, t, d, y, scale: float) -> np.ndarray:
    """The knots (on GRID, in units of the largest torque ``scale``) of least RSS, with their linear terms."""
    best = None
    for i, a in enumerate(GRID * scale):
        for b in GRID[i + 1:] * scale:
            if b - a < MIN_GAP * scale:
                continue
            A = _columns(u, t, d, a, b)
            # normal equations: a 9 x 9 solve per knot pair (the columns are O(1), well conditioned)
            try:
                coef = np.linalg.solve(A.T @ A, A.T @ y)
            except np.linalg.LinAlgError:
                continue                  # a knot beyond the recorded torques: its column is empty
            rss = float(np.sum((A @ coef - y) ** 2))
            if best is None or rss < best[0]:
                best = (rss, np.concatenate([coef, [a, b]]))
    return None if best is None else best[1]


def _fit(ctx: Context) -> tuple[np.ndarray, np.ndarray] | None:
    """(parameters, covariance) of the branch model on the steady rows (None: no knots fit)."""
    keep = _steady(ctx)
    u, t, d, y = ctx.u[keep], ctx.t[keep], ctx.direction[keep], ctx.y[keep]
    scale = float(np.max(np.abs(u)))
    x0 = _grid_start(u, t, d, y, scale)
    if x0 is None:
        return None
    lo = np.full(len(x0), -np.inf)
    hi = np.full(len(x0), np.inf)
    lo[-2:], hi[-2:] = 0.0, scale
    res = least_squares(lambda x: _model(x, u, t, d) - y, x0, bounds=(lo, hi), x_scale="jac")
    r = res.fun
    dof = max(len(y) - len(x0), 1)
    rho = min(max(lag1(r), 0.0), 0.95)
    var = float(r @ r) / dof * (1.0 + rho) / (1.0 - rho)
    return res.x, np.linalg.pinv(res.jac.T @ res.jac) * var


def _readings(x: np.ndarray, ctx: Context, rated: float | None) -> dict:
    """name -> (value, unit) of the catalogue's numbers from the fitted parameters ``x``."""
    c1, d2, d3 = x[2], x[3], x[4]
    p1, p2 = x[-2], x[-1]
    inv = f"{ctx.load_unit}/{ctx.response_unit}"
    out = {"K1": (1.0 / (c1 * ctx.c0), inv), "K2": (1.0 / ((c1 + d2) * ctx.c0), inv),
           "K3": (1.0 / ((c1 + d2 + d3) * ctx.c0), inv),
           "T1": (p1 * ctx.X, ctx.load_unit), "T2": (p2 * ctx.X, ctx.load_unit),
           "hysteresis_loss_arcmin": (-2.0 * x[5] * ctx.Y * ARCMIN_PER_RAD, "arcmin")}
    if rated is not None:
        a = np.array([LOST_MOTION_FRACTION * rated / ctx.X])
        z = np.zeros(1)
        up = _model(x, -a, z, np.ones(1))[0]           # loading branch at -4 %
        down = _model(x, a, z, -np.ones(1))[0]         # unloading branch at +4 %
        out["lost_motion_arcmin"] = ((down - up) * ctx.Y * ARCMIN_PER_RAD, "arcmin")
    return out


def catalogue_values(ctx: Context, rated_torque: float | None = None) -> CatalogueValues | None:
    """The catalogue's numbers of a torsion recording (``rated_torque`` in the load unit, for the lost motion and
    the amplitude the loss should be read at); None without a reversal (no branch to read)."""
    if ctx.response_unit != "rad" or ctx.reversals < 1 or int(np.sum(_steady(ctx))) < 20:
        return None
    fitted = _fit(ctx)
    if fitted is None:
        return None
    x, cov = fitted
    with np.errstate(divide="ignore", invalid="ignore"):     # a slope of zero compliance is an infinite K
        return _with_errors(ctx, x, cov, rated_torque)


def _with_errors(ctx: Context, x: np.ndarray, cov: np.ndarray, rated_torque: float | None) -> CatalogueValues:
    """The readings with their standard errors (J C J^T, J by finite differences) and the reader's warnings."""
    base = _readings(x, ctx, rated_torque)
    J = np.zeros((len(base), len(x)))
    names = list(base)
    for j in range(len(x)):
        h = 1e-6 * max(abs(x[j]), 1e-3)
        xh = x.copy()
        xh[j] += h
        moved = _readings(xh, ctx, rated_torque)
        J[:, j] = [(moved[k][0] - base[k][0]) / h for k in names]
    se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", J, cov, J), 0.0))
    values = {k: (float(base[k][0]), float(e), base[k][1]) for k, e in zip(names, se)}
    amplitude = float(np.max(np.abs(ctx.u[_steady(ctx)]))) * ctx.X
    values["loop_amplitude"] = (amplitude, 0.0, ctx.load_unit)
    warnings = []
    if rated_torque is not None and abs(amplitude / rated_torque - 1.0) > AMPLITUDE_TOLERANCE:
        warnings.append(f"the loop was cycled to +/-{amplitude:.4g} {ctx.load_unit}, not to the rated torque "
                        f"{rated_torque:.4g} {ctx.load_unit}: its hysteresis loss is the loss at that amplitude")
    if rated_torque is not None and LOST_MOTION_FRACTION * rated_torque > amplitude:
        warnings.append("the lost-motion torque lies beyond the recorded range: the lost motion is extrapolated")
    return CatalogueValues(values, tuple(warnings))


__all__ = ["AMPLITUDE_TOLERANCE", "CatalogueValues", "LOST_MOTION_FRACTION", "SOURCE", "catalogue_values"]
