"""Family-2 physics outside the diagnosis catalogue (noise-free, response units; t in seconds).

- ``zener_twist``: a standard-linear-solid (Zener) specimen: creep compliance J(t) = J0 + J1 (1 - e^(-t/tau)),
  phi = J0 T + J1 q with q' = (T - q)/tau, integrated exactly for a torque linear between samples.
  Its loop depends on the loading rate (viscoelastic).
- ``log_creep``: twist creeping logarithmically under a held torque (Andrade-type), kept after the hold.
- ``stick_slip_twist``: a joint that sticks, then slips by a fixed amount each time the torque has
  moved by ``step_torque`` since its last slip in the current direction (stair on every load leg).
- ``warm_up``: an exponential warm-up drift of a sensor, D (1 - e^(-t/tau)).
- ``ripple``: a sinusoid in time (e.g. a fan, a pump, mains pick-up aliased).
"""
from __future__ import annotations

import math

import numpy as np


def zener_twist(T: np.ndarray, t_s: np.ndarray, J0: float, J1: float, tau_s: float) -> np.ndarray:
    T = np.asarray(T, dtype=float)
    q = np.empty(len(T))
    q[0] = T[0]
    for k in range(1, len(T)):
        dt = t_s[k] - t_s[k - 1]
        a = math.exp(-dt / tau_s)
        s = (T[k] - T[k - 1]) / dt if dt > 0 else 0.0
        q[k] = T[k] - s * tau_s + (q[k - 1] - T[k - 1] + s * tau_s) * a
    return J0 * T + J1 * q


def log_creep(t_s: np.ndarray, hold_start_s: float, hold_end_s: float, amplitude_rad: float,
              tau_s: float) -> np.ndarray:
    """0 before the hold, A ln(1 + (t - t0)/tau) during it, frozen at its final value after it."""
    te = np.clip(np.asarray(t_s, dtype=float), hold_start_s, hold_end_s) - hold_start_s
    return amplitude_rad * np.log1p(te / tau_s)


def stick_slip_twist(T: np.ndarray, slip_rad: float, step_torque_Nmm: float) -> np.ndarray:
    """Twist of the slipping joint: a staircase, counted from the last reversal on each leg."""
    T = np.asarray(T, dtype=float)
    out = np.empty(len(T))
    theta = 0.0
    anchor = T[0]            # torque of the last slip (or reversal)
    direction = 0.0
    for k, x in enumerate(T):
        if k:
            step = x - T[k - 1]
            if step != 0.0:
                d = 1.0 if step > 0 else -1.0
                if d != direction:
                    anchor, direction = T[k - 1], d           # stuck again after a reversal
                slips = math.floor((x - anchor) * d / step_torque_Nmm)
                if slips > 0:
                    theta += d * slips * slip_rad
                    anchor += d * slips * step_torque_Nmm
        out[k] = theta
    return out


def warm_up(t: np.ndarray, amplitude: float, tau: float) -> np.ndarray:
    return amplitude * (1.0 - np.exp(-np.asarray(t, dtype=float) / tau))


def ripple(t: np.ndarray, amplitude: float, period: float, phase: float = 0.0) -> np.ndarray:
    return amplitude * np.sin(2.0 * math.pi * np.asarray(t, dtype=float) / period + phase)


__all__ = ["log_creep", "ripple", "stick_slip_twist", "warm_up", "zener_twist"]
