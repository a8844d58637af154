"""Added torsional flexibility of a full external circumferential crack in a HOLLOW shaft (mode III).

Seed 000's K_III (Tada's solid round bar, M_M(d_e/d_s)) ignores the bore; a hollow shaft carries a
higher outer-fibre stress tau_o = T r_o / J_hollow and its crack cuts a wall of finite thickness t.

Hollow-tube strip form (shallow cracks, any wall): the wall is an anti-plane strip of width t under
tau_o with an edge crack of depth a. Tada, Paris & Irwin (The Stress Analysis of Cracks Handbook,
edge-cracked strip in anti-plane shear; exact, because the strip's free faces are symmetry planes of a
periodic array of collinear cracks of period 2t):

    K_III = tau_o sqrt(pi a) sqrt((2t / (pi a)) tan(pi a / 2t))

Seed 000's eq 4 with dA = 2 pi r_o da and G = E/2(1+nu) integrates in closed form
(int pi a F^2 da = (4 t^2 / pi) ln sec(pi a / 2t)):

    dlambda_strip = 8 r_o^3 t^2 / (G J^2) ln sec(pi a / 2t)          (J = pi/2 (r_o^4 - r_i^4))

It neglects the curvature of the wall: the inward fall of tau (tau ~ r) and the shrinking front, both
O(a / r_o), and for deep cracks the net section of a thick tube, which carries T over a smaller polar
moment than a flat strip's ligament does.

Thick-tube form (strainwave's, deep cracks in thick tubes; no handbook solution for a circumferential
crack in a tube under torsion was found in the sources searched): the strip's K_III^2 is multiplied by
the tube's net-section amplification relative to the strip's own,

    A(a) = [tau_net(a) / tau_o] / [t / (t - a)],    tau_net = T r_e / J_net, r_e = r_o - a,
    J_net = pi/2 (r_e^4 - r_i^4),

raised to a power m: A = 1 for a thin wall at every depth (the strip is exact there) and for a -> 0.
m = THICK_TUBE_EXPONENT was fitted to the exact axisymmetric FEA (fea/shaft_axisym.py) on two geometries
only, d_i/d = 0.5 and 0.8 (r_o = 35 mm, a/t = 1/32 .. 3/4, tip a/160 Richardson-extrapolated): m = 0.646,
largest deviation on those fitted geometries 3.9 % (THICK_TUBE_FIT_SCATTER). Confirmed against the same FEA,
within 3.9 % + 3 GCI, on geometries it was not fitted on (tests/test_fea_shaft_axisym.py: d_i/d = 0.643 and
0.9; tests/test_analytic_tube_crack.py: d_i/d = 0.1, 0.3, 0.5 over a/t up to 0.75): CONFIRMED_RANGE. Outside
it the form misses: d_i/d = 0.3 at a/t = 0.75 by -17 %, d_i/d = 0.1 at every depth (+5.5 % at a/t = 0.125,
-7.8 % at 0.5, -40 % at 0.75): a use there is flagged (``range_note``).
"""
from __future__ import annotations

import math

from scipy import integrate

__all__ = ["CONFIRMED_RANGE", "confirmed", "range_note", "THICK_TUBE_EXPONENT", "THICK_TUBE_FIT_SCATTER", "THICK_TUBE_FIT_RATIOS", "strip_factor",
           "tube_outer_stress_per_torque", "hollow_tube_strip_flexibility", "thick_tube_amplification",
           "thick_tube_flexibility"]

# Fitted on d_i/d = 0.5 and 0.8 only (see the module docstring); the scatter on those fitted geometries is
# the model allowance every check of this form carries, fixed here before any unfitted geometry is solved.
THICK_TUBE_EXPONENT = 0.646
THICK_TUBE_FIT_SCATTER = 0.039
THICK_TUBE_FIT_RATIOS = (0.5, 0.8)
# Where the FEA confirmed the form (module docstring): (lowest d_i/d, highest d_i/d, largest a/t)
CONFIRMED_RANGE = ((0.5, 0.9, 0.75), (0.3, 0.9, 0.5))


def confirmed(d_ratio: float, a_over_t: float) -> bool:
    """True where the thick-tube form was confirmed against the axisymmetric FEA (CONFIRMED_RANGE)."""
    eps = 1e-9
    return any(lo - eps <= d_ratio <= hi + eps and 0.0 <= a_over_t <= a_max + eps for lo, hi, a_max in CONFIRMED_RANGE)


def range_note(d_ratio: float, a_over_t: float) -> str:
    """"" inside CONFIRMED_RANGE, else the sentence a report prints beside the value."""
    if confirmed(d_ratio, a_over_t):
        return ""
    spans = "; ".join(f"d_i/d {lo:g}-{hi:g} up to a/t {a:g}" for lo, hi, a in CONFIRMED_RANGE)
    return (f"thick-tube form used outside its confirmed range (d_i/d = {d_ratio:.3g}, a/t = {a_over_t:.3g}; "
            f"confirmed: {spans})")


def _check(r_o_mm: float, r_i_mm: float, a_mm: float) -> None:
    if not (0.0 <= r_i_mm < r_o_mm and 0.0 <= a_mm < r_o_mm - r_i_mm):
        raise ValueError(f"need 0 <= r_i < r_o and 0 <= a < wall: r_o = {r_o_mm}, r_i = {r_i_mm}, a = {a_mm}")


def strip_factor(a_over_t: float) -> float:
    """sqrt((2t/(pi a)) tan(pi a/2t)): Tada's anti-plane edge-cracked strip; 1 at a -> 0."""
    if a_over_t <= 0.0:
        return 1.0
    x = 0.5 * math.pi * a_over_t
    return math.sqrt(math.tan(x) / x)


def tube_outer_stress_per_torque(r_o_mm: float, r_i_mm: float) -> float:
    """tau_o / T = r_o / J_hollow, J_hollow = pi/2 (r_o^4 - r_i^4), in 1/mm^3."""
    return r_o_mm / (0.5 * math.pi * (r_o_mm ** 4 - r_i_mm ** 4))


def hollow_tube_strip_flexibility(r_o_mm: float, r_i_mm: float, a_mm: float, G_MPa: float) -> float:
    """dlambda = 8 r_o^3 t^2/(G J^2) ln sec(pi a/2t) in rad/(N mm): the hollow-tube strip form (module doc)."""
    _check(r_o_mm, r_i_mm, a_mm)
    t = r_o_mm - r_i_mm
    J = 0.5 * math.pi * (r_o_mm ** 4 - r_i_mm ** 4)
    return 8.0 * r_o_mm ** 3 * t ** 2 / (G_MPa * J ** 2) * -math.log(math.cos(0.5 * math.pi * a_mm / t))


def thick_tube_amplification(r_o_mm: float, r_i_mm: float, a_mm: float) -> float:
    """A(a) = [tau_net/tau_o] (t - a)/t: the tube's net-section stress rise over the flat strip's (>= 1)."""
    _check(r_o_mm, r_i_mm, a_mm)
    t, r_e = r_o_mm - r_i_mm, r_o_mm - a_mm
    net_over_gross = (r_e / r_o_mm) * (r_o_mm ** 4 - r_i_mm ** 4) / (r_e ** 4 - r_i_mm ** 4)
    return net_over_gross * (t - a_mm) / t


def thick_tube_flexibility(r_o_mm: float, r_i_mm: float, a_mm: float, G_MPa: float,
                           exponent: float = THICK_TUBE_EXPONENT) -> float:
    """Seed 000's eq 4 with K_III^2 = (strip K_III)^2 A(a)^m, dA = 2 pi r_o da (module doc), rad/(N mm)."""
    _check(r_o_mm, r_i_mm, a_mm)
    t = r_o_mm - r_i_mm
    k_per_T = tube_outer_stress_per_torque(r_o_mm, r_i_mm)

    def integrand(s: float) -> float:
        k2 = (k_per_T * strip_factor(s / t)) ** 2 * math.pi * s
        return k2 * thick_tube_amplification(r_o_mm, r_i_mm, s) ** exponent * 2.0 * math.pi * r_o_mm / G_MPa

    value, _ = integrate.quad(integrand, 0.0, a_mm, epsabs=0.0, epsrel=1e-10, limit=200)
    return value
