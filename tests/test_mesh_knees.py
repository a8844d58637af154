"""The study's knees on the exact loop (decision 073): the solver's knots make the loop independent of the torque
step, and the dead band of the backlash is taken out of K1/T1 (lost motion keeps it)."""
import math

import numpy as np
import pytest

from strainwave.fea import tooth_mesh as tm
from strainwave.fea.mesh_contact import MeshSystem, dead_band, solve_torque_path, torque_history

KEYS = ("K1", "K2", "K3", "T1", "T2")


def _gapped_springs(k=1e4, lever=50.0, c=0.01, g=0.004, mu=0.0):
    """Each side: flank A touches at twist c/lever, flank B (same spring) a gap g further along its line."""
    return MeshSystem(np.array([c, c + g, c, c + g]), np.eye(4) / k, np.array([lever, lever, -lever, -lever]),
                      np.full(4, 5.0), mu, 80.0)


def _many_teeth(n=14, seed=5):
    rng = np.random.default_rng(seed)
    B = rng.normal(size=(n, n))
    C = 1e-5 * (B @ B.T / n + np.eye(n))
    lever = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * rng.uniform(30.0, 60.0, n)
    return MeshSystem(rng.uniform(0.002, 0.02, n), C, lever, rng.uniform(0.0, 10.0, n), 0.08, 80.0)


def _raw(path):
    """The same path with no dead band: the reading sees the raw twist."""
    from dataclasses import replace
    return replace(path, dead_band_rad=(0.0, 0.0))


def test_knots_lie_on_the_exact_path_and_make_it_independent_of_the_step():
    s = _many_teeth()
    coarse, fine = (solve_torque_path(s, torque_history(2e5, n)) for n in (6, 12))
    # the loop resampled on the reader's grid is the same curve whatever the solve's step
    T1, y1 = tm.resampled_loop(coarse, 200)
    T2, y2 = tm.resampled_loop(fine, 200)
    assert np.array_equal(T1, T2)
    assert np.allclose(y1, y2, rtol=0.0, atol=1e-12 * np.ptp(y1))
    a, b = tm.knee_values(coarse, 2e5, 200), tm.knee_values(fine, 2e5, 200)
    for k in KEYS:
        assert a[k] == pytest.approx(b[k], rel=1e-6), k
    # the history's steps alone (the old reading) do move with the step
    old = [tm.read_knees(p.torque_Nmm, p.twist_rad, 2e5)["T1"] for p in (coarse, fine)]
    assert abs(old[0] / old[1] - 1.0) > 0.05


def test_a_gapped_pair_of_springs_reads_its_own_knee_with_the_dead_band_out():
    k, lever, c, g = 1e4, 50.0, 0.01, 0.004
    T_knee = k * lever * g                         # flank B closes: the stiffness doubles from k L^2 to 2 k L^2
    rated = 4.0 * T_knee
    path = solve_torque_path(_gapped_springs(k, lever, c, g), torque_history(rated, 10))
    assert dead_band(_gapped_springs(k, lever, c, g)) == pytest.approx((-c / lever, c / lever))
    v = tm.knee_values(path, rated)
    assert v["K1"] == pytest.approx(k * lever ** 2, rel=1e-6)
    assert v["T1"] == pytest.approx(T_knee, rel=1e-4)
    assert v["K3"] == pytest.approx(2 * k * lever ** 2, rel=1e-6)
    # the raw loop's reading spends its knee on the dead band: T1 sits at the reader's first torque sample
    T, th = tm.resampled_loop(_raw(path), 200)
    raw = tm.read_knees(T, th, rated)
    assert raw["T1"] < 2.0 * rated / 200 and raw["K1"] < 0.1 * k * lever ** 2


@pytest.mark.parametrize("factor", [0.8, 1.2])
def test_backlash_moves_the_lost_motion_not_the_knees_and_the_gap_moves_t1(factor):
    k, lever, c, g = 1e4, 50.0, 0.01, 0.004
    rated = 4.0 * k * lever * g
    base = tm.loop_values([solve_torque_path(_gapped_springs(k, lever, c, g, 0.1), torque_history(rated, 10))],
                          rated)
    wider = tm.loop_values([solve_torque_path(_gapped_springs(k, lever, c * factor, g, 0.1),
                                              torque_history(rated, 10))], rated)
    for name in ("K1_Nmm_per_rad", "T1_Nmm", "K3_Nmm_per_rad"):
        assert wider[name] == pytest.approx(base[name], rel=1e-6), name
    # the dead band's 2 c / L is in the lost motion: it moves by 2 (factor - 1) c / L
    moved = (wider["lost_motion_arcmin"] - base["lost_motion_arcmin"]) / tm.ARCMIN
    assert moved == pytest.approx(2.0 * (factor - 1.0) * c / lever, rel=1e-6)
    knee = tm.loop_values([solve_torque_path(_gapped_springs(k, lever, c, g * factor, 0.1),
                                             torque_history(rated, 10))], rated)
    assert knee["T1_Nmm"] / base["T1_Nmm"] == pytest.approx(factor, rel=0.02)
    assert math.isfinite(base["K2_Nmm_per_rad"])
