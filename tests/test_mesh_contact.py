"""The tooth-mesh contact solver against first principles (spring law, friction loop, LCP conditions)."""
import numpy as np
import pytest

from strainwave.fea.mesh_contact import (MeshSystem, loop_area_Nmm_rad, normal_forces, solve_torque_path,
                                              torque_history)


def _two_flanks(mu, k=1e4, lever=50.0, c=0.01, slide=5.0):
    """One tooth, both flanks: a spring of stiffness k along each line of action, gap c either side."""
    return MeshSystem(np.array([c, c]), np.diag([1.0 / k, 1.0 / k]), np.array([lever, -lever]),
                      np.array([slide, slide]), mu, 80.0)


def test_one_tooth_follows_the_spring_law():
    k, lever, c = 2e4, 40.0, 0.02
    s = MeshSystem(np.array([c]), np.array([[1.0 / k]]), np.array([lever]), np.array([0.0]), 0.0, 80.0)
    T = np.linspace(0.0, 5e4, 11)
    path = solve_torque_path(s, T)
    loaded = T > 0
    expected = c / lever + T / (k * lever ** 2)
    assert np.allclose(path.twist_rad[loaded], expected[loaded], rtol=1e-10)
    assert np.allclose(path.forces_N[:, 0], T / lever, rtol=1e-10)


def test_no_friction_no_loop():
    path = solve_torque_path(_two_flanks(0.0), torque_history(1e5, 20))
    assert abs(loop_area_Nmm_rad(path)) < 1e-9 * 1e5 * np.ptp(path.twist_rad)
    # the same torque on loading and unloading gives the same twist (away from zero, where the backlash floats)
    T, th = path.torque_Nmm, path.twist_rad
    for t in (5e4, -5e4):
        hits = th[np.isclose(T, t)]
        assert np.ptp(hits) < 1e-12


def test_friction_loop_dissipates_the_coulomb_work():
    mu, k, lever, c, slide, Tmax = 0.1, 1e4, 50.0, 0.01, 5.0, 1e5
    path = solve_torque_path(_two_flanks(mu, k, lever, c, slide), torque_history(Tmax, 50))
    area = loop_area_Nmm_rad(path)
    x = Tmax / (k * (lever + mu * slide))           # flank compression at the peak, sliding forward
    expected = 2.0 * mu * slide * k * x ** 2 / lever   # both flanks: the integral of 2 mu s F d(theta)
    assert area > 0.0
    assert area == pytest.approx(expected, rel=1e-9)
    # the twist lags the torque: at zero torque the unloading branch sits at the larger twist
    k_down = np.flatnonzero(np.diff(np.sign(path.torque_Nmm)) < 0)[0]
    assert path.twist_rad[k_down] > 0.0


def test_many_teeth_satisfy_the_contact_conditions():
    rng = np.random.default_rng(3)
    n = 24
    B = rng.normal(size=(n, n))
    C = 1e-5 * (B @ B.T / n + np.eye(n))
    lever = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * rng.uniform(30.0, 60.0, n)
    s = MeshSystem(rng.uniform(0.0, 0.02, n), C, lever, rng.uniform(0.0, 10.0, n), 0.08, 80.0)
    path = solve_torque_path(s, torque_history(2e5, 15))
    gaps = path.gaps_mm(s)
    F = path.forces_N
    assert np.all(F >= 0.0)
    assert np.all(gaps >= -1e-10)
    assert np.max(np.abs(F * gaps)) < 1e-8
    for th, f in zip(path.twist_rad[::7], F[::7]):       # the path's forces are the LCP's unique solution
        assert np.allclose(f, normal_forces(s, th), atol=1e-6 * max(1.0, f.max()))
    # more torque engages more teeth
    n_contact = path.contact.sum(axis=1)
    assert n_contact[np.argmax(path.torque_Nmm)] >= n_contact[1]
