"""nonlinear_stiffness: stiffness that rises with load as tooth contact spreads (catalogue K1 < K2 < K3).

Model (Harmonic Drive's three-slope stiffness curve, odd in the load):
    twist = sgn(T) [ |T|/K1 - (1/K1 - 1/K2) (|T| - T1)+ - (1/K2 - 1/K3) (|T| - T2)+ ]
In normalised units with s/K1 = s c0: y += -sgn(u) [a1 (|u| - p1)+ + a2 (|u| - p2)+], p2 = p1 + g,
a1, a2 >= 0 so K1 <= K2 <= K3.
Variant ``two-slope`` (K1 <= K2 above T1, two parameters) for weak or single-knee stiffening: with half the
parameters it wins on BIC when the third slope is not resolved.
Variant ``monotone`` (seven parameters): a piecewise-linear compliance curve on fixed knots whose slope can
only fall (a_i >= 0): any monotone stiffening law, whatever its shape; K1..T2 are read from it.
Variant ``smooth-knee`` (five parameters): the same three slopes joined by knees rounded over a load width w
(softplus instead of the ramp), so smooth stiffening laws (tanh, exponential, contact spread) are not forced
into sharp knees and their misfit is not handed to another effect. It still reports K1, K2, K3 (the slopes
far from the knees) and T1, T2 (the knee centres) for the comparison with the catalogue.
Variant ``contact`` (three parameters): no flat K1 range at all; the compliance falls from zero load on as
tooth contact spreads, c(|u|) = s - A (1 - (1 + |u|/x_c)^(q - 1)), the Hertzian way (a point contact's
compliance falls as load^(-1/3), a line contact's about as 1/load: 0 <= q <= 0.75 spans them). The twist
above the asymptotic line keeps growing, like |u|^q or ln|u|: a law whose extra twist levels off (q < 0)
is a clearance taken up (lost_motion), which is why q stops at 0 and x_c at 2 % of full scale.
K1 (zero load), K3 (full load) and T1, T2 (where the compliance has made 1/3 and 2/3 of its fall) are read
from the curve.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param


def _breaks(theta):
    a1, a2, p1, g = theta
    return a1, a2, p1, p1 + g


def _contribution(ctx: Context, theta):
    a1, a2, p1, p2 = _breaks(theta)
    m = np.abs(ctx.u)
    return -np.sign(ctx.u) * (a1 * np.maximum(m - p1, 0.0) + a2 * np.maximum(m - p2, 0.0))


def _report(ctx: Context, theta, s: float) -> dict:
    a1, a2, p1, p2 = _breaks(theta)
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"

    def stiff(comp):
        return 1.0 / (comp * ctx.c0) if comp > 0 else float("inf")
    return {"K1": (stiff(s), inv), "K2": (stiff(s - a1), inv), "K3": (stiff(s - a1 - a2), inv),
            "T1": (p1 * ctx.X, ctx.load_unit), "T2": (p2 * ctx.X, ctx.load_unit)}


def _softramp(x, w):
    """w ln(1 + e^(x/w)): the ramp max(x, 0) with its corner rounded over w (overflow-safe)."""
    return w * np.logaddexp(0.0, x / w)


def _contribution_smooth(ctx: Context, theta):
    a1, a2, p1, g, lw = theta
    w = 10.0 ** lw
    m = np.abs(ctx.u)
    # minus the value at |u| = 0 keeps the curve odd and continuous through zero load
    ramp = (a1 * (_softramp(m - p1, w) - _softramp(-p1, w))
            + a2 * (_softramp(m - p1 - g, w) - _softramp(-p1 - g, w)))
    return -np.sign(ctx.u) * ramp


def _report_smooth(ctx: Context, theta, s: float) -> dict:
    out = _report(ctx, theta[:4], s)
    out["knee_width"] = (10.0 ** theta[4] * ctx.X, ctx.load_unit)
    return out


# Harmonic Drive catalogues give K3/K1 of 1.3 to 3 (CHA table: at most 2.6); a curve that stiffens more
# than 5x is not tooth-contact spreading (clipping, saturation or a stop would look like this)
MAX_STIFFENING = 5.0


def _total_fall(ctx: Context, theta) -> float:
    """The compliance fall over the recorded load range, whichever form."""
    if len(theta) == len(MONOTONE_KNOTS):
        return float(np.sum(theta))
    if len(theta) == 3:   # contact: A (1 - (1 + m/x_c)^(q-1)) at the largest load
        A, lx, q = theta
        return float(A * (1.0 - (1.0 + np.max(np.abs(ctx.u)) / 10.0 ** lx) ** (q - 1.0)))
    return float(theta[0] + (theta[1] if len(theta) in (4, 5) else 0.0))


# A clearance is taken up within 10 % of the largest torque (lost_motion's band bound, LOG10_W_MAX); tooth
# contact spreads over a large part of the rated torque (CHA table: T2 = 3.4-3.6 T1, so a test to 1.5 T2 makes
# its fall at 0.19 and 0.67 of full scale). A curve that has made 90 % of its whole fall within the band is a
# clearance taken up, not stiffening (docs/decisions/060)
CLEARANCE_BAND = 0.1
FALL_DONE = 0.9


def _fall_done_at(ctx: Context, theta) -> float:
    """The load (fraction of the largest) by which the compliance has made FALL_DONE of its fall over the
    recorded range, read from the form's own curve."""
    m_max = float(np.max(np.abs(ctx.u)))
    form = {4: _contribution, 2: _contribution_two, 5: _contribution_smooth, 3: _contribution_contact,
            len(MONOTONE_KNOTS): _contribution_monotone}[len(theta)]
    m = np.linspace(0.0, m_max, 2001)
    # the extra twist on the positive side is minus the ramp; its slope's drop is the compliance fall
    fall = np.gradient(-form(dataclasses.replace(ctx, u=m), theta), m)
    if not fall[-1] > 0:
        return 1.0
    return float(m[np.argmax(fall >= FALL_DONE * fall[-1])] / m_max)


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    a_total = _total_fall(ctx, theta)
    if s - a_total <= s / MAX_STIFFENING:
        ratio = s / (s - a_total) if s > a_total else float("inf")
        return [f"the stiffness rises {ratio:.3g}x over the load range (tooth-contact stiffening gives at most "
                f"~{MAX_STIFFENING:g}x): a stop, clipping or saturation, not stiffening"]
    done = _fall_done_at(ctx, theta)
    if a_total > 0 and done <= CLEARANCE_BAND:
        return [f"the stiffness has made {100 * FALL_DONE:.0f} % of its rise by {done * ctx.X:.4g} {ctx.load_unit} "
                f"({100 * done:.1f} % of the largest torque, within a clearance's band of "
                f"{100 * CLEARANCE_BAND:.0f} %): a clearance taken up (lost_motion), not tooth-contact stiffening"]
    return []


def _where(ctx: Context, theta):
    if len(theta) == 3:
        # the contact law has no knee: its compliance falls from zero load on
        return (((float(ctx.u.min()), float(ctx.u.max())),),
                "over the whole load range, stiffer at higher load on both load signs (odd in load)")
    if len(theta) == len(MONOTONE_KNOTS):
        nz = [p for a, p in zip(theta, MONOTONE_KNOTS) if a > 1e-6]
        p1 = nz[0] if nz else MONOTONE_KNOTS[-1]
    else:
        p1 = float(theta[2] if len(theta) >= 4 else theta[1])
    if len(theta) == 5:
        p1 = max(p1 - 2.0 * 10.0 ** theta[4], 0.0)
    lo, hi = float(ctx.u.min()), float(ctx.u.max())
    ranges = tuple(r for r in ((lo, -p1), (p1, hi)) if r[1] - r[0] > 0)
    return ranges, "above the knee load on both load signs (odd in load: stiffening)"


MONOTONE_KNOTS = (0.05, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9)


def _basis_monotone(ctx: Context) -> np.ndarray:
    """The twist per unit slope change at each knot (len(u) x knots): the form is linear in its weights."""
    return -np.sign(ctx.u)[:, None] * np.maximum(np.abs(ctx.u)[:, None] - np.asarray(MONOTONE_KNOTS)[None, :], 0.0)


def _contribution_monotone(ctx: Context, theta):
    return _basis_monotone(ctx) @ np.asarray(theta, dtype=float)


def _report_monotone(ctx: Context, theta, s: float) -> dict:
    """Slopes of the piecewise-linear monotone curve read as the catalogue's three slopes: K1 at zero load,
    K3 at full load, T1 and T2 where the compliance has fallen by 1/3 and 2/3 of its total fall, K2 between."""
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    a = np.asarray(theta, dtype=float)
    knots = np.asarray(MONOTONE_KNOTS)
    fall = np.cumsum(a)                      # compliance drop reached past each knot
    total = float(fall[-1]) if len(fall) else 0.0

    def stiff(comp):
        return 1.0 / (comp * ctx.c0) if comp > 0 else float("inf")

    def load_at(frac):
        if total <= 0:
            return float("nan")
        k = int(np.searchsorted(fall, frac * total - 1e-15))
        return float(knots[min(k, len(knots) - 1)])
    t1, t2 = load_at(1.0 / 3.0), load_at(2.0 / 3.0)
    mid = 0.5 * (t1 + t2) if np.isfinite(t1) else 0.5
    a_mid = float(np.sum(a[knots <= mid + 1e-12]))
    return {"K1": (stiff(s), inv), "K2": (stiff(s - a_mid), inv), "K3": (stiff(s - total), inv),
            "T1": (t1 * ctx.X, ctx.load_unit), "T2": (t2 * ctx.X, ctx.load_unit)}


def _contact_twist(m, A, xc, q):
    """A (m - x_c G(m/x_c)), G(x) = ((1 + x)^q - 1)/q (ln(1 + x) at q = 0): the integral of the compliance fall."""
    L = np.log1p(m / xc)
    grow = np.where(q > 1e-9, np.expm1(q * L) / max(q, 1e-9), L)
    return A * (m - xc * grow)


def _contribution_contact(ctx: Context, theta):
    A, lx, q = theta
    return -np.sign(ctx.u) * _contact_twist(np.abs(ctx.u), A, 10.0 ** lx, q)


def _report_contact(ctx: Context, theta, s: float) -> dict:
    """K1 at zero load, K3 at the largest load, T1 and T2 where the compliance has made 1/3 and 2/3 of its fall
    over the recorded range (the monotone variant's reading), K2 midway between them."""
    A, lx, q = theta
    xc = 10.0 ** lx
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    m_max = float(np.max(np.abs(ctx.u)))

    def fall(m):
        return A * (1.0 - (1.0 + m / xc) ** (q - 1.0))

    def load_at(frac):
        # fall(m) = frac fall(m_max)  <=>  (1 + m/xc)^(q-1) = 1 - frac fall(m_max)/A
        if A <= 0.0:
            return float("nan")
        return xc * ((1.0 - frac * fall(m_max) / A) ** (1.0 / (q - 1.0)) - 1.0)

    def stiff(comp):
        return 1.0 / (comp * ctx.c0) if comp > 0 else float("inf")
    t1, t2 = load_at(1.0 / 3.0), load_at(2.0 / 3.0)
    mid = 0.5 * (t1 + t2) if np.isfinite(t1) else 0.5 * m_max
    return {"K1": (stiff(s), inv), "K2": (stiff(s - fall(mid)), inv), "K3": (stiff(s - fall(m_max)), inv),
            "T1": (t1 * ctx.X, ctx.load_unit), "T2": (t2 * ctx.X, ctx.load_unit),
            "contact_load": (xc * ctx.X, ctx.load_unit), "contact_exponent_q": (float(q), "1")}


def _contribution_two(ctx: Context, theta):
    a1, p1 = theta
    return -np.sign(ctx.u) * a1 * np.maximum(np.abs(ctx.u) - p1, 0.0)


def _report_two(ctx: Context, theta, s: float) -> dict:
    a1, p1 = theta
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    return {"K1": (1.0 / (s * ctx.c0), inv), "K2": (1.0 / ((s - a1) * ctx.c0) if s > a1 else float("inf"), inv),
            "T1": (p1 * ctx.X, ctx.load_unit)}


EXPLANATION = ("the stiffness rises with torque as more teeth come into contact and the contact zones "
               "spread, so the torque-twist curve bends towards the torque axis (K1 < K2 < K3)")

EFFECT = Effect(
    id="nonlinear_stiffness",
    kinds=("torsion",),
    params=(Param("a1", 0.0, 0.95, (0.1,)), Param("a2", 0.0, 0.95, (0.1,)),
            Param("p1", 0.02, 0.9, (0.1, 0.3)), Param("g", 0.03, 0.9, (0.15, 0.4))),
    contribution=_contribution,
    report=_report,
    explanation=EXPLANATION,
    where=_where,
    plausible=_plausible,
)

# the other model forms of the same physics share the catalogue form's id, explanation, location and bounds


def _variant(variant: str, params: tuple[Param, ...], contribution, report) -> Effect:
    return dataclasses.replace(EFFECT, params=params, contribution=contribution, report=report, variant=variant)


TWO_SLOPE = _variant("two-slope", (Param("a1", 0.0, 0.95, (0.1,)), Param("p1", 0.02, 0.9, (0.1, 0.4))),
                     _contribution_two, _report_two)

SMOOTH_KNEE = _variant("smooth-knee", (Param("a1", 0.0, 0.95, (0.1,)), Param("a2", 0.0, 0.95, (0.1,)),
                                       Param("p1", 0.02, 0.9, (0.1, 0.3)), Param("g", 0.03, 0.9, (0.3,)),
                                       Param("log10_w", -2.0, -0.5, (-1.0,))),
                       _contribution_smooth, _report_smooth)

CONTACT = _variant("contact", (Param("A", 0.0, 0.95, (0.15,)), Param("log10_xc", -1.7, 0.0, (-1.2, -0.6)),
                               Param("q", 0.0, 0.75, (0.5,))),
                   _contribution_contact, _report_contact)

MONOTONE = dataclasses.replace(
    _variant("monotone", tuple(Param(f"a_{p:g}", 0.0, 0.95, (0.0,)) for p in MONOTONE_KNOTS), _contribution_monotone,
             _report_monotone), basis=_basis_monotone)
