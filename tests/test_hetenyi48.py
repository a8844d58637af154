"""The rim's Hetenyi kernels against a beam on a Winkler foundation solved by finite differences (decision 077-hetenyi48).

The reference is E I y'''' + k y = q discretised on a long beam, with a point force and a couple (two opposite
forces one step either side of the origin): no Hetenyi formula enters it, so it settles signs and factors."""
import math

import numpy as np
import pytest
from scipy.linalg import solve_banded

from strainwave.analytic import mesh_compliance as mc
from strainwave.analytic.wg_bearing import peak_ball_load_N

E, I, K = 2.1e5, 50.0, 300.0
BETA = (K / (4.0 * E * I)) ** 0.25
H = 0.005 / BETA                      # step: beta h = 0.005 (O(h^2) away from the load, O(h) at it)
N = 2 * int(12.0 / (BETA * H)) + 1    # +-12 / beta: the far ends carry e^-12 of the load
X = (np.arange(N) - N // 2) * H
MID = N // 2
BX = np.array([0.0, 0.4, math.pi / 4, 1.0, 1.7, 2.5, 3.5])   # beta x: both sides of C's zero at pi/4


def _solve(q_N_per_mm: np.ndarray) -> np.ndarray:
    """Deflection of the beam under the line load q (ends held: y = 0 beyond them)."""
    c = E * I / H ** 4
    ab = np.zeros((5, N))
    ab[0, 2:], ab[1, 1:], ab[2, :], ab[3, :-1], ab[4, :-2] = c, -4 * c, 6 * c + K, -4 * c, c
    return solve_banded((2, 2), ab, q_N_per_mm)


def _force(at: int) -> np.ndarray:
    q = np.zeros(N)
    q[at] = 1.0 / H
    return _solve(q)


def _couple(at: int) -> np.ndarray:
    """A unit counter-clockwise couple: +1/(2h) N up one step right of ``at``, down one step left."""
    q = np.zeros(N)
    q[at + 1], q[at - 1] = 1.0 / (2 * H * H), -1.0 / (2 * H * H)
    return _solve(q)


def _slope(y: np.ndarray, i: np.ndarray) -> np.ndarray:
    return (y[i + 1] - y[i - 1]) / (2 * H)


def _nodes(bx: np.ndarray) -> np.ndarray:
    return MID + np.round(bx / (BETA * H)).astype(int)


def test_force_kernel_is_the_beams_deflection():
    y = _force(MID)
    i = _nodes(BX)
    ref = mc.rim_on_foundation_green_mm_per_N(X[i], E, I, K)
    assert y[i] == pytest.approx(ref, abs=1e-3 * ref[0])
    # the most loaded ball carries its pitch's share of the peak foundation pressure k y(0) = P beta / 2
    s = 0.3 / BETA
    assert peak_ball_load_N(1.0, BETA, s) == pytest.approx(K * y[MID] * s, rel=1e-3)


def test_rotation_under_a_couple_is_the_slope_of_its_deflection_not_hetenyis_D():
    """Differentiate the couple's deflection numerically at several x (both sides): the kernel is its slope."""
    y = _couple(MID)
    for sign in (1.0, -1.0):
        i = _nodes(sign * BX)
        i[0] = MID     # x = 0
        got = mc.rim_moment_green_rad_per_Nmm(X[i], E, I, K)
        # 1 % of the peak: the force pair one step either side makes an O(beta h) kink at the origin
        assert got == pytest.approx(_slope(y, i), abs=1e-2 * BETA ** 3 / K)
    # the old kernel (D = e^-bx cos bx) agrees at x = 0 only: beyond it is off by more than the peak's 30 %
    i = _nodes(BX[2:])
    D = BETA ** 3 / K * np.exp(-BX[2:]) * np.cos(BX[2:])
    assert np.max(np.abs(D - _slope(y, i))) > 0.3 * BETA ** 3 / K
    # a couple turns no rigid body: the rotation integrates to zero (D's integral is beta^2/k)
    x = np.linspace(-30.0 / BETA, 30.0 / BETA, 600001)
    assert abs(np.trapezoid(mc.rim_moment_green_rad_per_Nmm(x, E, I, K), x)) < 1e-6 * BETA ** 2 / K


def test_maxwell_betti_between_the_force_and_the_couple():
    """The module's two kernels are reciprocal: a unit couple is the limit of a force pair, so the rotation it makes
    (the slope, by Maxwell-Betti the work-conjugate of the couple) is minus the force kernel's second derivative."""
    x = X[_nodes(BX[1:])]
    d = 1e-3 / BETA
    G = lambda s: mc.rim_on_foundation_green_mm_per_N(s, E, I, K)
    second = (G(x + d) - 2 * G(x) + G(x - d)) / d ** 2
    assert mc.rim_moment_green_rad_per_Nmm(x, E, I, K) == pytest.approx(-second, abs=1e-4 * BETA ** 3 / K)


def test_couple_kernel_is_symmetric_positive_definite_on_a_tooth_row():
    """A Green's function of a self-adjoint positive operator: its matrix on any row of teeth is positive."""
    pts = np.linspace(0.0, 6.0 / BETA, 15)
    Kmat = mc.rim_moment_green_rad_per_Nmm(pts[:, None] - pts[None, :], E, I, K)
    assert np.allclose(Kmat, Kmat.T)
    assert np.min(np.linalg.eigvalsh(Kmat)) > 0.0


def test_free_play_is_the_loss_at_zero_torque_whichever_edge_the_path_holds_there():
    """A loop with a dead band (lo, hi) and no friction: the path's exact zeros sit at the band's far edge (decision
    072's convention); the loss read with the band is its width, read without it the far edges give minus that."""
    from strainwave.analytic.catalogue_loss import hysteresis_loss_rad
    from strainwave.fea.mesh_contact import torque_history
    lo, hi, k = -3e-5, 5e-5, 1e4
    T = torque_history(10.0, 8)
    j = np.arange(len(T))
    down = (j >= np.argmax(T)) & (j <= np.argmin(T))
    far = np.where(down, lo, hi)        # at T = 0: unloading ends at lo, reloading at hi
    tw = T / k + np.where(T > 0, hi, np.where(T < 0, lo, far))
    assert hysteresis_loss_rad(T, tw, (lo, hi)) == pytest.approx(hi - lo, rel=1e-12)
    assert hysteresis_loss_rad(T, tw) == pytest.approx(lo - hi, rel=1e-12)
