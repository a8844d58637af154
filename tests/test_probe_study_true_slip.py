"""benchmarks/probe_study_true_slip.py: the study's torque history on the true-slip solver, read as a MeshPath
(cheap, synthetic two-flank lobe; the probe's FE runs are decision 072-slip48's)."""
from __future__ import annotations

import numpy as np
import pytest
from conftest import benchmark_module

from strainwave.fea.mesh_contact import MeshSystem, loop_area_Nmm_rad, solve_torque_path, torque_history
from strainwave.fea.mesh_friction import BandSystem


@pytest.fixture(scope="module")
def probe():
    with benchmark_module("probe_study_true_slip") as mod:
        yield mod


def _lobe(mu: float, n: int = 6, seed: int = 5) -> BandSystem:
    """Pairs on both flanks (levers +- the base radius, so the history's -T is carried), SPD coupled flexibility."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(2 * n, 2 * n))
    flex = 1e-7 * (A @ A.T / (2 * n) + np.eye(2 * n))
    lever = np.where(np.arange(n) < n // 2, 75.0, -75.0)
    return BandSystem(rng.uniform(0.0, 1e-3, n), flex, lever, rng.uniform(10.0, 30.0, n), mu)


def test_frictionless_history_is_the_study_solvers(probe):
    """mu = 0: the probe's path (incremental true slip) and the study's exact LCP path are one answer."""
    s = _lobe(0.0)
    n = len(s.clearance_mm)
    history = torque_history(8e4, steps_per_leg=8)
    got, Q = probe.true_slip_path(s, history, 1)
    assert np.all(Q == 0.0)
    ref = solve_torque_path(MeshSystem(s.clearance_mm, s.flex_mm_per_N[:n, :n], s.lever_mm, s.slide_mm_per_rad,
                                       0.0, 80.0), history)
    # at the history's zero torques both stop at the dead band's far edge (where the other flanks touch)
    assert got.twist_rad == pytest.approx(ref.twist_rad, rel=1e-7, abs=1e-7 * np.abs(ref.twist_rad).max())
    assert got.forces_N == pytest.approx(ref.forces_N, rel=1e-7, abs=1e-8 * ref.forces_N.max())


def test_true_slip_loop_dissipates_and_ends_on_its_torques(probe):
    """With friction the +T -> -T -> +T loop takes work (> 0); without, it is elastic (~0 against it)."""
    history = torque_history(8e4, steps_per_leg=10)
    with_mu = probe.true_slip_path(_lobe(0.3), history, 2)[0]
    without = probe.true_slip_path(_lobe(0.0), history, 2)[0]
    n = len(history)
    assert with_mu.torque_Nmm.shape == (n,) and with_mu.forces_N.shape == (n, 6)
    w1, w0 = loop_area_Nmm_rad(with_mu), loop_area_Nmm_rad(without)
    assert w1 > 0.0
    assert abs(w0) <= 1e-6 * w1
