"""fea/mesh_friction.py: Coulomb friction on the true slip of the teeth in mesh, from first principles (cheap)."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.mesh_contact import MeshSystem, normal_forces
from strainwave.fea.mesh_friction import BandSystem, solve_twist_path, turned_bands, twists_for_torques


def _system(mu: float, seed: int = 3, n: int = 5) -> BandSystem:
    """A lobe-like system: SPD band flexibility with coupling, levers ~ the base radius, slides of both signs."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(2 * n, 2 * n))
    flex = 1e-7 * (A @ A.T / (2 * n) + np.eye(2 * n))
    return BandSystem(rng.uniform(0.0, 2e-3, n), flex, rng.uniform(70.0, 80.0, n), rng.uniform(-30.0, 30.0, n), mu)


def test_frictionless_is_the_normal_contact():
    """mu = 0: the normal forces are the LCP's (NNLS, another solver) and no pair carries a tangential force."""
    s = _system(0.0)
    n = len(s.clearance_mm)
    ms = MeshSystem(s.clearance_mm, s.flex_mm_per_N[:n, :n], s.lever_mm, s.slide_mm_per_rad, 0.0, 80.0)
    for rec in solve_twist_path(s, [4e-5, 1e-5, 3e-5], increments=7):
        assert rec["forces_N"] == pytest.approx(normal_forces(ms, rec["twist_rad"]), rel=1e-9, abs=1e-9)
        assert np.all(rec["tangential_N"] == 0.0)


@pytest.mark.parametrize("mu, sticks", [(0.5, True), (0.05, False)])
def test_one_pair_sticks_or_slips_as_coulomb_says(mu, sticks):
    """One uncoupled pair: from closure Q / N = -w Cff / (lever Cgg) while it sticks, so it sticks for ever when
    that is inside the cone and slips from the start (Q = -mu N sign(w)) when it is not."""
    cff, cgg, lever, w, c = 1e-6, 4e-6, 75.0, 30.0, 1e-3
    s = BandSystem(np.array([c]), np.diag([cff, cgg]), np.array([lever]), np.array([w]), mu)
    ratio = w * cff / (lever * cgg)                  # 0.1
    for rec in solve_twist_path(s, [2 * c / lever, 3 * c / lever], increments=10):
        N, Q = rec["forces_N"][0], rec["tangential_N"][0]
        assert N == pytest.approx((lever * rec["twist_rad"] - c) / cff, rel=1e-9)
        assert Q == pytest.approx(-ratio * N if sticks else -mu * N, rel=1e-9)
        assert bool(rec["stick"][0]) is sticks


def test_coulomb_cone_gaps_and_torque_targets():
    """Along a loading, unloading and reloading history: |Q| <= mu N, gaps open or closed with N >= 0, and each
    leg ends on its torque; the same history twice gives the same answer (no hidden state)."""
    s = _system(0.3)
    n = len(s.clearance_mm)
    torques = [6e4, 2e4, 6e4]
    recs = twists_for_torques(s, torques, increments=15)
    for rec, T in zip(recs, torques):
        assert rec["torque_Nmm"] == pytest.approx(T, rel=1e-8)
        N, Q = rec["forces_N"], rec["tangential_N"]
        assert np.all(N >= 0.0) and np.all(np.abs(Q) <= 0.3 * N * (1 + 1e-9) + 1e-9)
        gap = s.clearance_mm - s.lever_mm * rec["twist_rad"] + (s.flex_mm_per_N @ np.concatenate([N, Q]))[:n]
        assert np.all(gap >= -1e-12) and np.all(np.abs(gap * N) <= 1e-9 * np.abs(N).max())
    again = twists_for_torques(s, torques, increments=15)
    assert [r["twist_rad"] for r in again] == [r["twist_rad"] for r in recs]


def test_friction_dissipates_over_a_closed_twist_cycle():
    """The work of the torque over a closed twist cycle (a -> b -> a, after a first loading) is > 0 with friction
    and zero without (elastic)."""
    a, b = 4e-5, 1.5e-5
    path = np.concatenate([np.linspace(0.0, a, 41)[1:], np.linspace(a, b, 41)[1:], np.linspace(b, a, 41)[1:]])

    def loop_work(mu: float) -> float:
        recs = solve_twist_path(_system(mu), path, increments=1)
        th = np.array([r["twist_rad"] for r in recs])[39:]
        T = np.array([r["torque_Nmm"] for r in recs])[39:]
        return float(np.sum(0.5 * (T[1:] + T[:-1]) * np.diff(th)))

    w0, w1, w2 = loop_work(0.0), loop_work(0.1), loop_work(0.3)
    assert w1 > 0.0 and w2 > 0.0
    assert abs(w0) <= 1e-6 * w1


def test_turned_bands_are_tangential_tractions():
    """Each nodal force turned by -90 degrees: the resultant lies along the given tangent with unit size."""
    F = np.array([[0.0], [-0.6], [-0.1], [-0.3], [0.1], [-0.1]])          # three nodes pressing along -y (n = +y)
    G = turned_bands(F, np.array([[-1.0, 0.0]]))     # t = (-n_y, n_x) = (-1, 0)
    assert G[0::2].sum() == pytest.approx(-1.0) and G[1::2].sum() == pytest.approx(0.0, abs=1e-12)
    assert G[0::2] * F[0::2] + G[1::2] * F[1::2] == pytest.approx(np.zeros((3, 1)), abs=1e-15)   # per node
    assert np.hypot(G[0::2], G[1::2]) == pytest.approx(np.hypot(F[0::2], F[1::2]))


def test_a_torque_no_flank_carries_is_refused():
    with pytest.raises(ValueError, match="not reached"):
        twists_for_torques(_system(0.3), [-1e4])


def test_bad_sizes_are_refused():
    with pytest.raises(ValueError, match="agree in size"):
        BandSystem(np.zeros(2), np.eye(3), np.ones(2), np.ones(2), 0.1)
    with pytest.raises(ValueError, match="clearance_mm"):
        BandSystem(-np.ones(1), np.eye(2), np.ones(1), np.ones(1), 0.1)
    with pytest.raises(ValueError, match="friction_coefficient"):
        BandSystem(np.zeros(1), np.eye(2), np.ones(1), np.ones(1), -0.1)
