"""The exact torque-twist loop of a mesh path, sampled on a fixed torque grid (decisions 073, 074).

Between contact-set changes the contact path is linear (mesh_contact), and the solver records every change and
every stick-to-slip onset as a knot: the knots are the exact piecewise-linear loop, so interpolating between
them is exact and a reading of the loop sampled on a fixed torque grid does not depend on the solve's torque
step. The tooth-mesh study (fea/tooth_mesh.py) and the catalogue's drive curve (analytic/drive_curve.py) read
their knees this way.
"""
from __future__ import annotations

import numpy as np

__all__ = ["READ_STEPS_PER_LEG", "exact_loop", "elastic_twist", "legs", "on_leg", "resample", "resampled_loop",
           "branch_twist"]

READ_STEPS_PER_LEG = 400         # the reader's fixed torque grid on the exact loop (decision 073)


def exact_loop(path) -> tuple[np.ndarray, np.ndarray]:
    """(torque, twist) at the knots of the exact piecewise-linear loop (the history's steps if none were recorded)."""
    knots = getattr(path, "knots", None)
    if knots is None:
        return np.asarray(path.torque_Nmm, float), np.asarray(path.twist_rad, float)
    return knots[:, 0], knots[:, 1]


def elastic_twist(theta: np.ndarray, dead_band_rad: tuple[float, float]) -> np.ndarray:
    """The twist measured from the backlash's edge on its own side: theta - clip(theta, theta-, theta+) (decision
    073: the catalogue's curve has no dead band; the backlash is lost motion, reported apart)."""
    lo, hi = dead_band_rad
    return np.asarray(theta, float) - np.clip(theta, lo, hi)


def legs(T: np.ndarray) -> tuple[slice, slice, slice]:
    """0 -> +T, +T -> -T, -T -> +T as index ranges sharing their end points."""
    k1 = int(np.argmax(T))
    k2 = k1 + int(np.argmin(T[k1:]))
    return slice(0, k1 + 1), slice(k1, k2 + 1), slice(k2, None)


def on_leg(T: np.ndarray, y: np.ndarray, leg: slice, torques: np.ndarray) -> np.ndarray:
    """``y`` at ``torques`` on one leg of the loop's knots (a leg is monotone in torque, so linear between knots)."""
    t, v = np.asarray(T[leg], float), np.asarray(y[leg], float)
    # the backlash band is crossed at zero torque; the solve leaves its knots at 1e-11..1e-7 N mm of round-off
    t = np.where(np.abs(t) <= 1e-9 * float(np.max(np.abs(t))), 0.0, t)
    falling = t[-1] < t[0]
    if falling:
        t, v = t[::-1], v[::-1]
    # round-off at a pivot must not break np.interp's order
    t = np.maximum.accumulate(t)
    torques = np.asarray(torques, float)
    out = np.interp(torques, t, v)
    # on a vertical segment (the band at 0 N m) the drive keeps the twist it arrives with: nothing pushes it across
    i = np.searchsorted(t, torques, side="right") - 1 if falling else np.searchsorted(t, torques, side="left")
    i = np.clip(i, 0, t.size - 1)
    jump = (t[i] == torques) & (np.searchsorted(t, torques, "right") - np.searchsorted(t, torques, "left") > 1)
    return np.where(jump, v[i], out)


def resample(T: np.ndarray, y: np.ndarray, steps_per_leg: int = READ_STEPS_PER_LEG) -> tuple[np.ndarray, np.ndarray]:
    """(grid, y on it): a 0 -> +A -> -A -> +A loop given at its knots (T, y), on ``steps_per_leg`` torques a leg."""
    from strainwave.fea.mesh_contact import torque_history
    T, y = np.asarray(T, float), np.asarray(y, float)
    grid = torque_history(float(np.max(T)), steps_per_leg)
    parts = [on_leg(T, y, lk, grid[lg])[(1 if i else 0):] for i, (lk, lg) in enumerate(zip(legs(T), legs(grid)))]
    return grid, np.concatenate(parts)


def resampled_loop(path, steps_per_leg: int = READ_STEPS_PER_LEG) -> tuple[np.ndarray, np.ndarray]:
    """(torque, elastic twist) of the exact loop on ``steps_per_leg`` torques a leg: between knots the loop is
    linear, so the interpolation is exact and the reading does not depend on the solve's torque step."""
    T, th = exact_loop(path)
    return resample(T, elastic_twist(th, getattr(path, "dead_band_rad", (0.0, 0.0))), steps_per_leg)


def branch_twist(path, torque_Nmm: float, direction: int) -> float:
    """The twist at ``torque_Nmm`` (not 0) on the steady unloading (-1: +T -> -T) or reloading (+1: -T -> +T) branch
    of the exact loop: read on the elastic twist (single-valued in torque), the band's edge on that side added back."""
    T, th = exact_loop(path)
    band = getattr(path, "dead_band_rad", (0.0, 0.0))
    _, down, up = legs(T)
    y = on_leg(T, elastic_twist(th, band), down if direction < 0 else up, np.array([torque_Nmm]))[0]
    return float(y + (band[1] if torque_Nmm > 0 else band[0]))
