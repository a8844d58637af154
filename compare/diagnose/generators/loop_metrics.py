"""Shape-free measures of a torque-twist loop, computed from any law ``twist_of(T_path) -> twist``.

- loss: the loop width at zero torque (descending minus ascending branch) of the steady +/- A cycle,
  the harmonic-drive catalogue's "hysteresis loss";
- energy: the closed integral of T dphi over that cycle (work done on the specimen; > 0 when it dissipates);
- secant compliance: (phi(+A) - phi(-A)) / 2A on that cycle (the loop's mean slope);
- set after unloading: twist at T = 0 after 0 -> +A -> 0 from the virgin state (> 0 for friction);
- recorded loss: the width at zero torque on the LAST full-scale cycle a given torque path contains. A law
  without return-point memory (Bouc-Wen) settles over several cycles: its first full-scale cycle after the
  virgin loading is up to 13 % wider than the steady one (measured over the family-2 parameter ranges), so a
  recording with one full-scale cycle does not contain the steady width; what it contains is this one.
These are the first-principles checks every hysteresis generator must pass, and the benchmark's truth.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Law = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Loop:
    loss_rad: float
    energy_Nmm_rad: float
    secant_compliance: float


def _legs(knots: list[float], per_leg: int) -> np.ndarray:
    s = np.linspace(0.0, len(knots) - 1, per_leg * (len(knots) - 1) + 1)
    return np.interp(s, np.arange(len(knots)), knots)


def measure_loop(twist_of: Law, amplitude: float, per_leg: int = 1000) -> Loop:
    """Loss, energy and secant of the third +/- ``amplitude`` cycle from the virgin state.

    Path 0 -> A -> -A -> A -> -A -> A -> -A -> A; the last full cycle (A -> -A -> A) is steady for
    rate-independent laws with return-point memory (play, Preisach) and converged for Bouc-Wen.
    """
    knots = [0.0] + [amplitude, -amplitude] * 3 + [amplitude]
    T = _legs(knots, per_leg)
    phi = twist_of(T)
    start = per_leg * (len(knots) - 3)
    Tc, pc = T[start:], phi[start:]
    down, up = slice(0, per_leg + 1), slice(per_leg, 2 * per_leg + 1)
    at_zero_down = float(np.interp(0.0, Tc[down][::-1], pc[down][::-1]))
    at_zero_up = float(np.interp(0.0, Tc[up], pc[up]))
    energy = float(np.sum(0.5 * (Tc[1:] + Tc[:-1]) * np.diff(pc)))
    secant = float((pc[0] - pc[per_leg]) / (2.0 * amplitude))
    return Loop(at_zero_down - at_zero_up, energy, secant)


def set_after_unloading(twist_of: Law, amplitude: float, per_leg: int = 1000) -> float:
    """Twist at T = 0 after loading the virgin specimen to +``amplitude`` and unloading, minus the start."""
    phi = twist_of(_legs([0.0, amplitude, 0.0], per_leg))
    return float(phi[-1] - phi[0])


# a reversal counts as full-scale within this fraction of max|T| (the same rule the diagnosis reads widths by,
# zero_load_width.FULL_SCALE; restated here so the benchmark's truth does not import the tool it scores)
FULL_SCALE = 0.95


def recorded_loss(T: np.ndarray, phi: np.ndarray) -> float | None:
    """Width at zero torque (descending minus ascending branch) of the last full-scale cycle in the noise-free
    path ``T`` with twist ``phi``: a descending stretch from near +max|T| to near -max|T| and the ascending one
    after it, both reaching zero torque. None when the path holds no such cycle."""
    T, phi = np.asarray(T, dtype=float), np.asarray(phi, dtype=float)
    full = FULL_SCALE * float(np.max(np.abs(T)))
    d = np.sign(np.diff(T))
    turns = [0] + [k for k in range(1, len(d)) if d[k] != 0 and d[k] != d[k - 1] and d[k - 1] != 0] + [len(T) - 1]
    legs = [(a, b) for a, b in zip(turns[:-1], turns[1:]) if b > a]
    width = None
    for (a, b), (c, e) in zip(legs[:-1], legs[1:]):
        if T[a] >= full and T[b] <= -full and b == c and T[e] >= 0.0:
            down = float(np.interp(0.0, T[a:b + 1][::-1], phi[a:b + 1][::-1]))
            up = float(np.interp(0.0, T[c:e + 1], phi[c:e + 1]))
            width = down - up
    return width


__all__ = ["FULL_SCALE", "Loop", "measure_loop", "recorded_loss", "set_after_unloading"]
