"""Which stiffness of a friction loop the simulation's linear stiffness is compared with.

A joint with friction has no one tangent stiffness: right after a load reversal every slider sticks (the
ELASTIC stiffness, the stiffest), near the end of a stroke many slip (the SLIP tangent, the softest), and over
the whole cycle the twist between the two load extremes gives the SECANT stiffness, the catalogue's reading.
A loop law's own stiffness scale s is none of these in general: the play operators read s as the slip tangent
of a fully slipped joint, so on a loop that never fully slips s comes out softer than the specimen, and the
prior on s then called for a series compliance (a "compliance change" of +9.6 % and +13.4 % beside a loop whose
secant was within 1.4 % of nominal). The data support only the elastic and the secant readings of
the fitted loop; the simulated stiffness (a linear elastic model) is one of them, which one depends on whether
the rig's catalogue quotes the stuck or the cycled stiffness, so the prior is judged on the closer one.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.effects.loop import load_path_model, reference_cycle
from strainwave.compare.diagnose.fit import Fit



def applies(fit: Fit) -> bool:
    """A loop whose load path is otherwise linear: only a series compliance beside it keeps a stiffness the two
    readings define (a stiffening changes every tangent: its K1, K2, K3 are read from s and keep the prior on s)."""
    path = [e for e in fit.effects if e.load_path]
    return any(e.loop for e in path) and all(e.loop or e.series_compliance for e in path)


def readings(ctx: Context, fit: Fit, series: bool = True) -> tuple[float, float]:
    """(secant, elastic) compliance of the fitted model over its closed reference loop, in units of the baseline
    compliance: the secant between the two load extremes, and the tangent over the first step after each
    reversal (every slider stuck), averaged over the two reversals. ``series`` False: without a fitted series
    compliance (the specimen the simulation describes, which the prior is about)."""
    ref, start = reference_cycle(ctx)
    y = fit.scale * ref.u + load_path_model(ref, fit)
    if not series:
        y = y - sum((e.contribution(ref, th) for e, th in zip(fit.effects, fit.split_theta())
                     if e.series_compliance), np.zeros_like(ref.u))
    u, y = ref.u[start:], y[start:]
    k = int(np.argmin(u))
    secant = float((y[-1] - y[k]) / (u[-1] - u[k]))
    elastic = 0.5 * float((y[1] - y[0]) / (u[1] - u[0]) + (y[k + 1] - y[k]) / (u[k + 1] - u[k]))
    return secant, elastic


def prior_chi2(ctx: Context, fit: Fit) -> float:
    """-2 ln of the stiffness prior, judged on the reading of the loop closer to the simulation (a series
    compliance fitted beside the loop is the departure from it, outside the prior)."""
    secant, elastic = readings(ctx, fit, series=False)
    return min(((c - 1.0) / fit.uncertainty) ** 2 for c in (secant, elastic))


def with_loop_prior(ctx: Context, fit: Fit) -> Fit:
    """``fit`` with its stiffness prior moved from s to the loop's readings (BIC shifted by the difference);
    unchanged unless ``applies``."""
    if not applies(fit):
        return fit
    if any(e.series_compliance for e in fit.effects):
        fit = _specimen_on_its_prior(ctx, fit)
    chi2 = prior_chi2(ctx, fit)
    return dataclasses.replace(fit, prior_chi2=chi2, bic=fit.bic - fit.prior_chi2 + chi2)


def _specimen_on_its_prior(ctx: Context, fit: Fit) -> Fit:
    """The same model with the specimen's scale s moved so that its closer loop reading is the simulation's, the
    series compliance taking the difference: the two are one linear term in the load, told apart by the prior
    alone, and the fit placed them by the prior on s (the loop law's slip tangent)."""
    secant, elastic = readings(ctx, fit, series=False)
    shift = 1.0 - min((secant, elastic), key=lambda c: abs(c - 1.0))
    theta = fit.theta.copy()
    i = 0
    for e in fit.effects:
        if e.series_compliance:
            theta[i] -= shift        # compliance_offset: y += d u
            break
        i += e.n_params
    b0, b1, scale = fit.nuisance
    return dataclasses.replace(fit, theta=theta, nuisance=(b0, b1, scale + shift))


__all__ = ["applies", "prior_chi2", "readings", "with_loop_prior"]
