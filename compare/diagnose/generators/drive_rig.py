"""A rig's torsion test of a whole harmonic drive, simulated from its parts (never used by the diagnosis).

The drive is built as a mechanism, not as the diagnosis's equations:

- stiffness: three groups of tooth pairs come into contact as the twist grows (group 1 from zero, groups 2 and 3
  once the twist closes their gaps). Each group is 30 pairs whose gaps are spread +/- ``knee_spread`` about the
  group's mean gap, so each knee is rounded as contact spreads over the pairs. The group stiffnesses and mean gaps
  are set from the catalogue's K1, K2, K3, T1, T2 (away from the knees the slopes are exactly K1, K2, K3, and the
  asymptotes meet at T1 and T2);
- lost motion: a clearance of ``clearance_rad`` at the output coupling, held centred by a weak spring and taken up
  by flanks whose Hertzian contact compliance (twist ~ torque^(2/3)) closes over a few per cent of the torque;
- the loop: flank friction, a chain of stick-slip contacts whose slip thresholds grow with the torque they carry
  (Coulomb: the normal force grows with the transmitted torque), so the loop is not a fixed-threshold operator;
  scaled to a loop width ``loss_rad`` at zero torque on a full cycle;
- the rig: the twist solved from the torque by bisection on the monotone stiffness law; a 20-bit output encoder
  (quantisation plus half a step of white noise), torque noise 0.05 % of full scale, a slow zero drift.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

ARCMIN = math.pi / (180.0 * 60.0)
ENCODER_STEP_RAD = 2.0 * math.pi / 2 ** 20


@dataclass(frozen=True)
class DriveTruth:
    """What the simulated drive is (SI units: N*m, rad)."""

    K1: float
    K2: float
    K3: float
    T1: float
    T2: float
    clearance_rad: float          # the coupling's clearance (the lost motion's own part)
    loss_rad: float               # loop width at zero torque, full cycle
    knee_spread: float = 0.15     # tooth-pair gaps spread +/- this fraction about each group's mean gap
    friction_load_share: float = 0.2   # how much the flank contacts' slip thresholds grow with the torque
    pairs_per_group: int = 30


def _mesh_torque(phi: np.ndarray, d: DriveTruth) -> np.ndarray:
    """Torque carried by the tooth pairs at twist ``phi`` (odd): each pair a linear spring once its gap is closed."""
    g1 = d.T1 / d.K1                                   # twist where group 2 engages (asymptotes meet at T1)
    g2 = g1 + (d.T2 - d.T1) / d.K2                     # twist where group 3 engages
    m, s = np.abs(phi)[:, None], np.sign(phi)
    n = d.pairs_per_group
    spread = np.linspace(-d.knee_spread, d.knee_spread, n)
    torque = d.K1 * m[:, 0]
    for gap, k in ((g1, d.K2 - d.K1), (g2, d.K3 - d.K2)):
        gaps = gap * (1.0 + spread)
        torque = torque + (k / n) * np.maximum(m - gaps[None, :], 0.0).sum(axis=1)
    return s * torque


def mesh_twist(T: np.ndarray, d: DriveTruth) -> np.ndarray:
    """Twist of the tooth pairs under torque ``T`` (N*m): the mesh law inverted by bisection (monotone)."""
    lo = np.zeros_like(T)
    hi = np.abs(T) / d.K1 + 1e-12
    target = np.abs(T)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = _mesh_torque(mid, d) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return np.sign(T) * 0.5 * (lo + hi)


def coupling_twist(T: np.ndarray, clearance_rad: float, T_rated: float) -> np.ndarray:
    """The clearance: a centring spring takes half the clearance at 0.5 % of the rated torque, then the flanks'
    Hertzian contact (compliance falling as torque^(-1/3)) closes the rest by ~3 % of the rated torque."""
    half = 0.5 * clearance_rad
    t_c = 0.005 * T_rated
    m = np.abs(T)
    centre = half * np.minimum(m / t_c, 1.0) * 0.5
    hertz = 0.5 * half * np.minimum((np.maximum(m - t_c, 0.0) / (0.025 * T_rated)) ** (2.0 / 3.0), 1.0)
    return np.sign(T) * (centre + hertz)


def flank_friction_twist(T: np.ndarray, loss_rad: float, n_contacts: int = 25, load_share: float = 0.2,
                         base: float = 0.3) -> np.ndarray:
    """Stick-slip flank contacts: contact i sticks until the torque moves more than its threshold
    r_i = f_i (base T_max + load_share |T|) from where it stuck (Coulomb friction on a normal force growing with the
    torque); its twist lags the torque (dissipative). Scaled to the loop width ``loss_rad`` at zero torque."""
    tmax = float(np.max(np.abs(T)))
    f = np.linspace(0.04, 0.5, n_contacts)
    w = np.exp(-np.linspace(0.0, 1.5, n_contacts))
    p = np.zeros(n_contacts)
    out = np.empty(len(T))
    for k, x in enumerate(T):
        r = f * (base * tmax + load_share * abs(x))
        p = np.maximum(x - r, np.minimum(x + r, p))
        out[k] = w @ (p - x)
    width = _zero_width(T, out)
    return out * (loss_rad / width) if width > 0 else out


def _branch_at(T: np.ndarray, twist: np.ndarray, level: float, direction: int) -> float:
    """Twist where the LAST stretch moving in ``direction`` crosses torque ``level`` (linear interpolation)."""
    d = np.sign(np.diff(T))
    cross = np.nonzero((d == direction) & ((T[:-1] - level) * (T[1:] - level) <= 0.0) & (T[:-1] != T[1:]))[0]
    if len(cross) == 0:
        return math.nan
    k = int(cross[-1])
    f = (level - T[k]) / (T[k + 1] - T[k])
    return float(twist[k] + f * (twist[k + 1] - twist[k]))


def _zero_width(T: np.ndarray, twist: np.ndarray) -> float:
    """Loop width at zero torque, last crossings: unloading-branch twist minus loading-branch twist."""
    return _branch_at(T, twist, 0.0, -1) - _branch_at(T, twist, 0.0, 1)


def truth_readings(d: DriveTruth, T_amp: float, T_rated: float, cycles: int = 2) -> dict:
    """Harmonic Drive's loss and lost motion of the noiseless simulated drive on its own +/- ``T_amp`` cycles
    (rad): loss = unloading minus loading branch at zero torque; lost motion = unloading branch at +4 % of the
    rated torque minus loading branch at -4 % (last crossings, a dense history)."""
    knots = [0.0] + [1.0, -1.0] * cycles + [0.0]
    T = np.interp(np.linspace(0.0, len(knots) - 1, 40001), np.arange(len(knots)), knots) * T_amp
    tw = mesh_twist(T, d) + coupling_twist(T, d.clearance_rad, T_rated) + \
        flank_friction_twist(T, d.loss_rad, load_share=d.friction_load_share)
    a = 0.04 * T_rated
    return {"loss_rad": _zero_width(T, tw),
            "lost_motion_rad": _branch_at(T, tw, a, -1) - _branch_at(T, tw, -a, 1)}


def drive_test(d: DriveTruth, T_amp: float, *, T_rated: float, n: int = 3000, cycles: int = 2, seed: int = 0,
               drift_rad: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time s, torque N*m measured, twist rad measured) of ``cycles`` full +/- ``T_amp`` cycles from zero."""
    rng = np.random.default_rng(seed)
    knots = [0.0] + [1.0, -1.0] * cycles + [0.0]
    s = np.linspace(0.0, len(knots) - 1, n)
    T = np.interp(s, np.arange(len(knots)), knots) * T_amp
    twist = mesh_twist(T, d) + coupling_twist(T, d.clearance_rad, T_rated) \
        + flank_friction_twist(T, d.loss_rad, load_share=d.friction_load_share)
    dT = np.diff(T)
    moving = np.abs(dT) > 1e-9 * T_amp
    if np.any(np.diff(twist)[moving] / dT[moving] <= 0.0):
        # the stuck contacts would take away more compliance than the drive has: an active, unphysical loop
        raise ValueError(f"loss {d.loss_rad:.3g} rad on a +/-{T_amp:g} N m cycle is not passive with these "
                         f"contacts: the twist would turn back after a reversal")
    time = np.linspace(0.0, 2.0 * n / 100.0, n)
    twist = twist + drift_rad * time / time[-1] + 2.0 * ENCODER_STEP_RAD
    twist = twist + 0.5 * ENCODER_STEP_RAD * rng.standard_normal(n)
    twist = np.round(twist / ENCODER_STEP_RAD) * ENCODER_STEP_RAD
    T_meas = T + 5e-4 * T_amp * rng.standard_normal(n)
    return time, T_meas, twist


def rig_file(time: np.ndarray, T_Nm: np.ndarray, twist_rad: np.ndarray, unit: str = "CHA-20A-100",
             uncertainty: float = 0.3) -> str:
    """The test as a rig exports it: a `#` header saying what was tested (a whole gear: its stiffness known to
    ``uncertainty``), metadata lines, a `;`-separated column row in N m and arcmin."""
    lines = ["# [test]", '# kind = "torsion"', '# specimen = "gear"', f"# baseline_uncertainty = {uncertainty!r}",
             f'# description = "{unit}, rig-style test"', f"Unit: {unit}", "Operator: rig 2",
             "Test: torsional stiffness, +/- cycle", "Time [s];Torque [Nm];Twist [arcmin]"]
    lines += [f"{a:.4f};{b:.5f};{c / ARCMIN:.5f}" for a, b, c in zip(time, T_Nm, twist_rad)]
    return "\n".join(lines) + "\n"


__all__ = ["ARCMIN", "DriveTruth", "coupling_twist", "drive_test", "flank_friction_twist", "mesh_twist", "rig_file",
           "truth_readings"]
