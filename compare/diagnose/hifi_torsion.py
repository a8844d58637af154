"""Higher-fidelity torsion physics for the concealed-data generator (never used by the diagnosis).

Each function returns the ADDITIONAL twist (rad) an effect adds to the linear twist for a torque
history T (N*mm, acquisition order). They differ on purpose from the catalogue's simple models:
Maxwell-slip friction with many elements instead of Dahl, a contact-spread stiffness law instead of
three slopes, a Hertz-onset backlash with friction instead of tanh, a crack whose faces close gradually.
"""
from __future__ import annotations

import numpy as np


def maxwell_slip_twist(T: np.ndarray, loss_rad: float, slip_fraction: float, n_elements: int = 40) -> np.ndarray:
    """Maxwell-slip (Prandtl-Ishlinskii stop operators): n elastic-slip elements with spread thresholds.

    Element i (spring + Coulomb slider) carries a torque share clipped at its slip torque r_i; its twist
    is that share. Thresholds spread uniformly up to ``slip_fraction`` max|T|, weights fall linearly.
    Scaled so the loop width at zero torque after a full cycle is ``loss_rad``.
    """
    tmax = float(np.max(np.abs(T)))
    r = np.linspace(1.0 / n_elements, 1.0, n_elements) * slip_fraction * tmax
    w = np.linspace(1.0, 0.2, n_elements)
    s = np.zeros(n_elements)
    out = np.empty(len(T))
    prev = T[0]
    for k, x in enumerate(T):
        s = np.clip(s + (x - prev), -r, r)
        prev = x
        out[k] = w @ s
    # loop width at zero torque of a full +/- cycle: every stop saturated at -+r_i
    width = 2.0 * float(w @ r)
    return out * (loss_rad / width)


def contact_spread_twist(T: np.ndarray, K1: float, K3: float, T_c: float, p: float = 1.5) -> np.ndarray:
    """Stiffness growing smoothly as contact spreads: K(|T|) = K1 + (K3 - K1)(1 - exp(-(|T|/T_c)^p)).

    Returns sgn(T) int_0^|T| dt/K(t) - T/K1 (numerical quadrature on a fine grid).
    """
    tmax = float(np.max(np.abs(T)))
    grid = np.linspace(0.0, tmax, 4001)
    K = K1 + (K3 - K1) * (1.0 - np.exp(-(grid / T_c) ** p))
    inv = 1.0 / K
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(grid))])
    mag = np.interp(np.abs(T), grid, cum)
    return np.sign(T) * mag - T / K1


def backlash_twist(T: np.ndarray, lost_rad: float, band_Nmm: float, friction_Nmm: float) -> np.ndarray:
    """Clearance taken up with a Hertz-like onset, shifted by a friction torque in the direction of motion.

    phi(v) = sgn(v) (1 - (1 - min(|v|, 1))^2): C1, saturating at |v| = 1 (flank contact fully closed).
    """
    d = np.sign(np.gradient(T))
    d[d == 0] = 1.0
    v = (T - friction_Nmm * d) / band_Nmm
    m = np.minimum(np.abs(v), 1.0)
    return 0.5 * lost_rad * np.sign(v) * (1.0 - (1.0 - m) ** 2)


def breathing_crack_twist(T: np.ndarray, extra_compliance: float, closure_Nmm: float, sign: int = 1) -> np.ndarray:
    """Extra compliance only while the crack is open (sign * T > 0), with faces closing over closure_Nmm.

    d(twist)/dT = c_x (1 + tanh(sign T / T_w))/2, integrated in closed form.
    """
    x = sign * T / closure_Nmm
    return 0.5 * extra_compliance * (T + sign * closure_Nmm * np.logaddexp(x, -x) - sign * closure_Nmm * np.log(2.0))


def series_compliance_twist(T: np.ndarray, extra_compliance: float) -> np.ndarray:
    """A bolted fixture or coupling: a linear series compliance."""
    return extra_compliance * T
