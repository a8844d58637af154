"""Higher-fidelity torsion physics for the concealed-data generator (never used by the diagnosis).

Each function returns the ADDITIONAL twist (rad) an effect adds to the linear twist for a torque
history T (N*mm, acquisition order). They differ on purpose from the catalogue's simple models:
Maxwell-slip friction with many elements instead of Dahl, a contact-spread stiffness law instead of
three slopes, a Hertz-onset backlash with friction instead of tanh, a crack whose faces close gradually.
"""
from __future__ import annotations

import numpy as np


def maxwell_slip_twist(T: np.ndarray, loss_rad: float, slip_fraction: float, n_elements: int = 40) -> np.ndarray:
    """Maxwell-slip friction under torque control: a series chain of n Jenkins elements (a spring in
    parallel with a Coulomb slider of threshold r_i), i.e. Prandtl-Ishlinskii PLAY operators on the torque.

    An element stays stuck until the torque has come back more than r_i from it, so after a reversal the
    twist lags the torque: the loop dissipates (closed integral of T dphi > 0) and unloading from +T
    leaves a positive twist. (The first version used stop operators, play's complement, whose loop
    generated energy: -0.18 normalised.) The chain's own mean compliance sum_i w_i belongs to the
    measured linear stiffness, so the ADDITIONAL twist returned is sum_i w_i (play_i(T) - T).
    Thresholds spread uniformly up to ``slip_fraction`` max|T| (<= 0.5, so every element slips on a
    full cycle), weights fall linearly; scaled so the loop width at zero torque of a full cycle is
    ``loss_rad`` (each element contributes 2 w_i r_i).
    """
    if not 0.0 < slip_fraction <= 0.5:
        raise ValueError("slip_fraction must be in (0, 0.5]: every element must slip on a full cycle")
    tmax = float(np.max(np.abs(T)))
    r = np.linspace(1.0 / n_elements, 1.0, n_elements) * slip_fraction * tmax
    w = np.linspace(1.0, 0.2, n_elements)
    p = np.zeros(n_elements)
    out = np.empty(len(T))
    for k, x in enumerate(T):
        p = np.maximum(x - r, np.minimum(x + r, p))      # play operator: stuck within +/- r_i
        out[k] = w @ (p - x)
    width = 2.0 * float(w @ r)
    return out * (loss_rad / width)


def maxwell_slip_stuck_drop(loss_rad: float, slip_fraction: float, T_max: float, n_elements: int = 40) -> float:
    """Compliance the chain of ``maxwell_slip_twist`` removes while every element is stuck (right after a
    reversal): sum_i w_i of the scaled weights. Passive only if it stays below the specimen's own compliance."""
    r = np.linspace(1.0 / n_elements, 1.0, n_elements) * slip_fraction * T_max
    w = np.linspace(1.0, 0.2, n_elements)
    return float(w.sum()) * loss_rad / (2.0 * float(w @ r))


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
