"""Family-2 non-dissipative (or, for Ramberg-Osgood, plastic) laws, independent of the catalogue and of
family 1. Torsion laws return the whole twist (rad) for torques T (N*mm); the ring law the whole
deflection (mm) for forces F (N).

- ``sinh_stiffening_twist``: an exponentially hardening spring T = K1 phi0 sinh(phi/phi0): the tangent
  stiffness K1 cosh(phi/phi0) rises smoothly from K1, no knee anywhere.
- ``power_stiffening_twist``: tangent stiffness K1 (1 + (|T|/T_s)^q), integrated numerically.
- ``hertz_backlash_twist``: a clearance +/- g centred at the torque T0 with a weak centring spring k_w
  in it, and flank contact in parallel beyond it whose force law T_c = k_L d^1.5 / (d + d_h)^0.5 is
  Hertzian (d^1.5) at first contact and linear (tooth bending) once loaded; inverted by bisection.
- ``gradual_crack_twist``: a crack open for sign*T > 0 (extra compliance c_x); under the other sign its
  faces come into contact and the extra compliance falls as c_x / (1 + (|T|/T_cl)^m) (asperity
  contact stiffening with the contact load), so it closes gradually over about T_cl.
- ``ramberg_osgood_masing``: a ring whose force-deflection skeleton is d = c F (1 + alpha |F/F0|^(n-1)),
  unloading and reloading by Masing's rule (branches = skeleton doubled from the reversal point) with
  memory (a closed minor loop resumes the earlier branch; passing the peak rejoins the skeleton).
"""
from __future__ import annotations

import numpy as np


def sinh_stiffening_twist(T: np.ndarray, K1: float, phi0_rad: float) -> np.ndarray:
    return phi0_rad * np.arcsinh(np.asarray(T, dtype=float) / (K1 * phi0_rad))


def _odd_integral(T: np.ndarray, compliance_of_abs, n_grid: int = 20001) -> np.ndarray:
    """sgn(T) * int_0^|T| compliance(t) dt by the trapezoid rule on a fine grid."""
    T = np.asarray(T, dtype=float)
    top = float(np.max(np.abs(T))) or 1.0
    grid = np.linspace(0.0, top, n_grid)
    f = compliance_of_abs(grid)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(grid))])
    return np.sign(T) * np.interp(np.abs(T), grid, cum)


def power_stiffening_twist(T: np.ndarray, K1: float, T_s_Nmm: float, q: float) -> np.ndarray:
    return _odd_integral(T, lambda t: 1.0 / (K1 * (1.0 + (t / T_s_Nmm) ** q)))


def _contact_torque(d: np.ndarray, k_L: float, d_h: float) -> np.ndarray:
    d = np.maximum(d, 0.0)
    return k_L * d ** 1.5 / np.sqrt(d + d_h)


def hertz_backlash_torque(phi: np.ndarray, gap_rad: float, k_w: float, k_L: float, d_h_rad: float) -> np.ndarray:
    """Torque carried at twist phi (measured from the centre of the clearance): spring + flank contact."""
    phi = np.asarray(phi, dtype=float)
    return k_w * phi + np.sign(phi) * _contact_torque(np.abs(phi) - gap_rad, k_L, d_h_rad)


def hertz_backlash_twist(T: np.ndarray, gap_rad: float, k_w: float, k_L: float, d_h_rad: float,
                         centre_Nmm: float = 0.0) -> np.ndarray:
    """Twist at torques T: the inverse of ``hertz_backlash_torque`` (strictly increasing) about T0."""
    tau = np.asarray(T, dtype=float) - centre_Nmm
    lo = np.minimum(tau / k_w, 0.0) - 1e-30        # |phi| <= |tau| / k_w since the contact only adds torque
    hi = np.maximum(tau / k_w, 0.0) + 1e-30
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        below = hertz_backlash_torque(mid, gap_rad, k_w, k_L, d_h_rad) < tau
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def gradual_crack_twist(T: np.ndarray, extra_compliance: float, closure_Nmm: float, m: float = 2.0,
                        open_sign: int = 1) -> np.ndarray:
    """Extra twist of the crack (rad): c_x tau while open, the closing integral under the other sign."""
    if open_sign not in (1, -1):
        raise ValueError("open_sign must be +1 or -1")
    tau = open_sign * np.asarray(T, dtype=float)
    closing = _odd_integral(np.minimum(tau, 0.0),
                            lambda t: extra_compliance / (1.0 + (t / closure_Nmm) ** m))
    return open_sign * np.where(tau >= 0.0, extra_compliance * tau, closing)


def ramberg_osgood_skeleton(F: np.ndarray, c: float, F0: float, alpha: float, n: float) -> np.ndarray:
    F = np.asarray(F, dtype=float)
    return c * F * (1.0 + alpha * np.abs(F / F0) ** (n - 1.0))


def ramberg_osgood_masing(F: np.ndarray, c: float, F0: float, alpha: float, n: float) -> np.ndarray:
    """Deflection (mm) along the force path F (N) from the virgin state."""
    g = lambda x: float(ramberg_osgood_skeleton(np.array([x]), c, F0, alpha, n)[0])
    stack: list[tuple[float, float]] = []        # reversal points (F, d), most recent last
    out = np.empty(len(F))
    d, direction = 0.0, 0.0
    prev = float(F[0])
    out[0] = g(prev)
    for k in range(1, len(F)):
        x = float(F[k])
        step = x - prev
        if step != 0.0:
            new_dir = 1.0 if step > 0 else -1.0
            if direction != 0.0 and new_dir != direction:
                stack.append((prev, out[k - 1]))              # a reversal at the previous sample
            direction = new_dir
            while True:                                        # memory: closed loops resume older branches
                if len(stack) >= 2 and (x - stack[-2][0]) * direction >= 0.0:
                    stack.pop()
                    stack.pop()
                elif len(stack) == 1 and abs(x) >= abs(stack[0][0]):
                    stack.pop()                                # beyond the largest excursion: skeleton
                else:
                    break
        if stack:
            Fr, dr = stack[-1]
            d = dr + 2.0 * g(0.5 * (x - Fr))
        else:
            d = g(x)
        out[k] = d
        prev = x
    return out


__all__ = ["gradual_crack_twist", "hertz_backlash_torque", "hertz_backlash_twist", "power_stiffening_twist",
           "ramberg_osgood_masing", "ramberg_osgood_skeleton", "sinh_stiffening_twist"]
