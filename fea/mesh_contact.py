"""Frictional contact of the teeth in mesh at one wave-generator angle, along a torque history.

The circular spline turns by the output twist theta (the wave generator and the flexspline's far end
held). Each flank pair i closes along its line of action by lever_i * theta (lever in mm: a flank that
carries negative torque has a negative lever). Its gap and normal force obey the contact law

    g = clearance - lever * theta + C F >= 0,   F >= 0,   g . F = 0          (C: compliance, SPD)

so for a fixed set of touching pairs F is linear in theta. Coulomb friction on the flanks slides by
slide_i * d(theta); it resists the twist with mu * |slide_i| * F_i, so the output torque is

    T = sum (lever_i + mu * d * |slide_i|) F_i,     d = sign of the twist rate,

and when the torque reverses the flanks stick (theta held) until T has crossed the band that friction
spans. The normal problem is solved exactly by following theta from one contact-set change to the next
(a parametric LCP; C is a P-matrix, so the path is unique); scipy's NNLS (the LCP of an SPD matrix is
a bound-constrained least-squares problem) resets the set where a step is degenerate.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

__all__ = ["MeshSystem", "MeshPath", "solve_torque_path", "normal_forces", "torque_history",
           "loop_area_Nmm_rad", "dead_band"]

TOL = 1e-12          # relative: a gap or force this small (on its scale) is zero


@dataclass(frozen=True)
class MeshSystem:
    """The teeth in mesh at one wave-generator angle (lengths mm, forces N)."""

    clearance_mm: np.ndarray           # (n,) unloaded gap of each flank pair along its line of action; >= 0
    compliance_mm_per_N: np.ndarray    # (n, n) flexibility along the lines of action (SPD)
    lever_mm: np.ndarray               # (n,) torque arm of each pair's normal force (output torque = sum lever F)
    slide_mm_per_rad: np.ndarray       # (n,) flank sliding per unit output twist (friction's lever)
    friction_coefficient: float
    rim_radius_mm: float

    def __post_init__(self):
        n = len(self.clearance_mm)
        if self.compliance_mm_per_N.shape != (n, n) or len(self.lever_mm) != n or len(self.slide_mm_per_rad) != n:
            raise ValueError("MeshSystem: clearance, compliance, lever and slide must agree in size")
        if np.any(np.asarray(self.clearance_mm) < 0.0):
            raise ValueError("MeshSystem: clearance_mm must be >= 0")
        if self.friction_coefficient < 0.0:
            raise ValueError("MeshSystem: friction_coefficient must be >= 0")


@dataclass(frozen=True)
class MeshPath:
    """The system's answer along a torque history (m steps)."""

    torque_Nmm: np.ndarray     # (m,) the applied output torque
    twist_rad: np.ndarray      # (m,) the output twist
    forces_N: np.ndarray       # (m, n) normal force of each flank pair
    contact: np.ndarray        # (m, n) bool, the pair carries load
    iterations: np.ndarray     # (m,) contact-set changes (pivots) taken to reach each step
    work_Nmm: np.ndarray       # (m,) the integral of T d(theta) from the previous step (exact on the path)
    # (k, 2) torque and twist of the exact piecewise-linear loop: every history step, every contact-set change
    # (pivot) and every stick-to-slip onset, in path order (None: only the steps are known)
    knots: np.ndarray | None = None
    # (theta-, theta+) the backlash's dead band: the twist at which the first flank of each side touches unloaded
    dead_band_rad: tuple[float, float] = (0.0, 0.0)

    def gaps_mm(self, system: MeshSystem) -> np.ndarray:
        """(m, n) the gaps g = c - lever theta + C F (>= 0 to round-off)."""
        return (system.clearance_mm[None, :] - self.twist_rad[:, None] * system.lever_mm[None, :]
                + self.forces_N @ system.compliance_mm_per_N.T)


def torque_history(amplitude_Nmm: float, steps_per_leg: int = 40) -> np.ndarray:
    """0 -> +T -> -T -> +T, the study's load (the first loading is virgin, the rest a steady loop)."""
    up = np.linspace(0.0, amplitude_Nmm, steps_per_leg + 1)
    down = np.linspace(amplitude_Nmm, -amplitude_Nmm, 2 * steps_per_leg + 1)[1:]
    return np.concatenate([up, down, -down])


def normal_forces(system: MeshSystem, theta: float) -> np.ndarray:
    """The normal forces at twist ``theta`` by NNLS: min 1/2 F C F + q F, F >= 0 with q = c - lever theta."""
    q = system.clearance_mm - system.lever_mm * theta
    L = np.linalg.cholesky(system.compliance_mm_per_N)
    F, _ = nnls(L.T, -np.linalg.solve(L, q))
    return F


class _Tracker:
    """Follows theta through the contact-set changes of the normal problem."""

    def __init__(self, s: MeshSystem):
        self.s = s
        self.C = np.asarray(s.compliance_mm_per_N, float)
        self.lever = np.asarray(s.lever_mm, float)
        self.c = np.asarray(s.clearance_mm, float)
        self.sl = np.abs(np.asarray(s.slide_mm_per_rad, float))
        self.theta = 0.0
        self.active = np.zeros(len(self.c), dtype=bool)     # unloaded: zero gaps close as the twist moves
        self.work = 0.0
        self.knots = [(0.0, 0.0)]          # (torque, twist) where the loop's slope changes

    def linear(self):
        """F = a + b theta on the active set (zero elsewhere)."""
        n = len(self.c)
        a, b = np.zeros(n), np.zeros(n)
        A = self.active
        if A.any():
            CA = self.C[np.ix_(A, A)]
            a[A] = np.linalg.solve(CA, -self.c[A])
            b[A] = np.linalg.solve(CA, self.lever[A])
        return a, b

    def torque(self, theta: float, d: float) -> float:
        a, b = self.linear()
        return float((self.lever + self.s.friction_coefficient * d * self.sl) @ (a + b * theta))

    def forces(self) -> np.ndarray:
        a, b = self.linear()
        return np.maximum(a + b * self.theta, 0.0)

    def _event(self, a, b, d):
        """(step along d to the first contact-set change, its index) from the current theta."""
        F = a + b * self.theta
        gap = self.c - self.lever * self.theta + self.C @ F
        gap_rate = d * (-self.lever + self.C @ b)
        F_rate = d * b
        tol_g = TOL * max(float(np.max(np.abs(self.c), initial=0.0)), 1e-9)
        best, idx = np.inf, -1
        for i in range(len(self.c)):
            if self.active[i] and F_rate[i] < 0.0:
                step = max(F[i], 0.0) / -F_rate[i]
            elif not self.active[i] and gap_rate[i] < 0.0:
                step = max(gap[i], 0.0) / -gap_rate[i] if gap[i] > tol_g else 0.0
            else:
                continue
            if step < best:
                best, idx = step, i
        return best, idx

    def move_to(self, target: float, d: float) -> int:
        """Twist along d until the torque (sliding in d) reaches ``target``; returns the pivots taken."""
        mu = self.s.friction_coefficient
        pivots = 0
        for _ in range(20 * len(self.c) + 20):
            a, b = self.linear()
            w = self.lever + mu * d * self.sl
            alpha, beta = float(w @ a), float(w @ b)
            need = (target - alpha) / beta - self.theta if abs(beta) > 0.0 else d * np.inf
            need = max(d * need, 0.0)
            step, idx = self._event(a, b, d)
            move = min(need, step)
            t0 = self.theta
            self.theta += d * move
            # T is linear in theta between contact-set changes: the work of the segment is exact
            self.work += (alpha + 0.5 * beta * (t0 + self.theta)) * (self.theta - t0)
            if need <= step:
                return pivots
            self.knots.append((alpha + beta * self.theta, self.theta))   # exact: the set changes here
            self.active[idx] = not self.active[idx]
            pivots += 1
        self._reset(d)                # degenerate cycling: take the set from NNLS just past theta
        return pivots + self.move_to(target, d)

    def _reset(self, d: float) -> None:
        h = 1e-9 * max(abs(self.theta), 1e-9)
        self.active = normal_forces(self.s, self.theta + d * h) > 0.0


def solve_torque_path(system: MeshSystem, torque_Nmm: np.ndarray) -> MeshPath:
    """Twist, forces and contact set at each torque of the history (starting unloaded at theta = 0)."""
    tr = _Tracker(system)
    T = np.asarray(torque_Nmm, float)
    m, n = len(T), len(system.clearance_mm)
    theta, forces = np.zeros(m), np.zeros((m, n))
    pivots = np.zeros(m, dtype=int)
    work = np.zeros(m)
    for k, Tk in enumerate(T):
        tr.work = 0.0
        up, down = tr.torque(tr.theta, 1.0), tr.torque(tr.theta, -1.0)
        if Tk > up:                  # slides forward (from the torque where the stick ends)
            tr.knots.append((up, tr.theta))
            pivots[k] = tr.move_to(Tk, 1.0)
        elif Tk < down:              # slides back
            tr.knots.append((down, tr.theta))
            pivots[k] = tr.move_to(Tk, -1.0)
        # else: friction holds the flanks (stick), theta unchanged
        theta[k], forces[k], work[k] = tr.theta, tr.forces(), tr.work
        tr.knots.append((float(Tk), tr.theta))
    return MeshPath(T, theta, forces, forces > 0.0, pivots, work, np.asarray(tr.knots, float), dead_band(system))


def dead_band(system: MeshSystem) -> tuple[float, float]:
    """(theta-, theta+): the unloaded twists at which the first flank of each side touches (its gap c - lever theta
    reaches 0); 0 on a side with no flank."""
    c, lever = np.asarray(system.clearance_mm, float), np.asarray(system.lever_mm, float)
    pos, neg = lever > 0.0, lever < 0.0
    hi = float(np.min(c[pos] / lever[pos])) if pos.any() else 0.0
    lo = float(np.max(c[neg] / lever[neg])) if neg.any() else 0.0
    return lo, hi


def loop_area_Nmm_rad(path: MeshPath) -> float:
    """The work put in over the closed loop after the first peak (+T -> -T -> +T): the integral of T d(theta),
    > 0 when the loop dissipates (the twist lags the torque)."""
    k0 = int(np.argmax(path.torque_Nmm))
    return float(np.sum(path.work_Nmm[k0 + 1:]))
