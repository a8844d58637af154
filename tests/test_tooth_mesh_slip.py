"""The tooth-mesh study's true-slip system (decision 073-slipstudy48): the 2 x 2 band flexibility by translation
symmetry against direct FE on the whole rim, and the torque-prescribed friction path against the twist-driven one."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.analytic.mesh_engagement import mesh_geometry
from strainwave.fea import tooth_mesh as tm
from strainwave.fea import tooth_mesh_fe as fe
from strainwave.fea.assembly import Lame
from strainwave.fea.mesh_friction import BandSystem, _targets, torque_path, twists_for_torques
from strainwave.params import load_params


@pytest.fixture(scope="module")
def small_rim():
    """A 60-tooth rim (m 2.67 mm) on a coarse P2 mesh: its tooth-0 blocks and the direct band flexibility."""
    params = load_params(None, {"flexspline_cup": {"teeth": 60, "module_mm": 160.0 / 60},
                                "gear": {"radial_deformation_mm": 160.0 / 60}})
    geo = mesh_geometry(params)
    m = geo.fs.module_mm
    rim = fe.rim_model(geo.fs, geo.r_bore_mm, 0.8 * m, Lame.from_young(2.1e5, 0.3), geo.face_width_mm)
    radii = geo.fs.root_radius_mm + m * np.array([0.9, 1.3, 1.7])
    band = 0.2 * m
    blocks = fe.influence_blocks(rim, geo.fs.root_radius_mm, radii, band, +1, (1, -1), np.arange(geo.z_f),
                                 geo.r_bore_mm)
    # pairs on both flanks, near and far teeth, on the grid's radii (no interpolation between them)
    pairs = {"side": np.array([1, 1, 1, -1, -1, -1]), "tooth": np.array([0, 1, 7, 0, 3, 58]),
             "cs_space": np.zeros(6, int), "fs_radius_mm": radii[[0, 2, 1, 1, 0, 2]],
             "cs_radius_mm": np.full(6, 1.0)}
    infl = {"fs_radii": radii, "cs_radii": np.array([0.5, 1.5]), "fs_t_same": blocks[1], "fs_t_other": blocks[-1],
            "cs_t": np.zeros((2, 2, 2 * tm.CS_NEIGHBOURS + 1, 2, 2))}
    cols = []
    for s, j, r in zip(pairs["side"], pairs["tooth"], pairs["fs_radius_mm"]):
        F, M = fe.flank_loads(rim, np.array([j]), np.array([r]), band, int(s))
        cols.append((F, M))
    F = np.hstack([c[0] for c in cols])
    M = np.concatenate([c[1] for c in cols])
    G = fe.turned(rim, F)
    shear = fe.bore_shear(rim, geo.r_bore_mm)
    B = np.hstack([F - shear[:, None] * M[None, :], G - shear[:, None] * fe.load_moments(rim, G)[None, :]])
    direct = B.T @ fe.displacements(rim, B)
    return tm.pair_flexibility(infl, pairs, geo.z_f, geo.z_c), 0.5 * (direct + direct.T), pairs


def test_band_flexibility_by_symmetry_is_the_direct_fe(small_rim):
    """Every entry of [[Cff, Cfg], [Cgf, Cgg]] from tooth 0's blocks (both flanks, the mirror's sign of t) is the
    direct FE's B^T K^-1 B on the whole rim within 2 % of its diagonals' scale (the rim mesh is not periodic)."""
    S, D, _ = small_rim
    scale = np.sqrt(np.outer(np.diag(D), np.diag(D)))
    assert np.all(np.abs(S - D) <= 0.02 * scale)
    assert np.all(np.linalg.eigvalsh(S) > 0.0)


def test_the_mirror_turns_the_tangent(small_rim):
    """The -1 flanks' normal-tangential coupling is large and takes the mirror's sign: without it, it would fail."""
    S, D, pairs = small_rim
    n = len(pairs["side"])
    minus = np.flatnonzero(pairs["side"] < 0)
    fg = D[:n, n:][np.ix_(minus, minus)]
    scale = np.sqrt(np.outer(np.diag(D)[:n], np.diag(D)[n:]))[np.ix_(minus, minus)]
    assert np.max(np.abs(fg) / scale) > 0.2                  # the coupling is not small
    assert np.all(np.abs(-fg - S[:n, n:][np.ix_(minus, minus)]) > 0.2 * scale * (np.abs(fg) / scale > 0.2))


def _lobes(mu: float, seed: int, n: int = 8) -> BandSystem:
    """Flank pairs of both flanks (levers of both signs), SPD coupled band flexibility, slides of both signs."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(2 * n, 2 * n))
    lever = rng.uniform(70.0, 80.0, n) * np.where(np.arange(n) % 2, -1.0, 1.0)
    return BandSystem(rng.uniform(0.0, 2e-3, n), 1e-7 * (A @ A.T / (2 * n) + np.eye(2 * n)), lever,
                      rng.uniform(-30.0, 30.0, n), mu)


@pytest.mark.parametrize("mu, seed", [(0.0, 1), (0.1, 4), (0.3, 2), (0.6, 5)])
def test_torque_path_is_the_twist_driven_path_on_the_same_increments(mu, seed):
    """0 -> +T -> -T -> +T in 2 torque increments a step: mesh_friction's twist-driven path (false position on each
    increment's end twist) on the same increments gives the same twists and forces to 1e-6 wherever it lands on
    its torque; torque_path lands on every torque."""
    s = _lobes(mu, seed)
    hist = np.concatenate([np.linspace(0, 6e4, 5), np.linspace(6e4, -6e4, 9)[1:], np.linspace(-6e4, 6e4, 9)[1:]])
    path, Q = torque_path(s, hist, 2, exact=False)
    targets, idx = _targets(hist, 2)
    recs = twists_for_torques(s, targets, increments=1, rtol=1e-13)
    th = np.array([0.0] + [r["twist_rad"] for r in recs])[idx + 1]
    T_old = np.array([0.0] + [r["torque_Nmm"] for r in recs])[idx + 1]
    F = np.vstack([np.zeros(8)] + [r["forces_N"] for r in recs])[idx + 1]
    on = np.abs(T_old - np.where(hist == 0.0, T_old, hist)) <= 1e-9 * 6e4
    assert on.sum() >= 18
    assert path.twist_rad[on] == pytest.approx(th[on], rel=1e-6, abs=1e-6 * np.abs(th).max())
    assert path.forces_N[on] == pytest.approx(F[on], rel=1e-6, abs=1e-6 * np.abs(F).max())
    T_new = path.forces_N @ s.lever_mm - Q @ s.slide_mm_per_rad
    assert T_new[hist != 0] == pytest.approx(hist[hist != 0], rel=1e-9)
    assert np.all(np.abs(Q) <= mu * path.forces_N * (1 + 1e-9) + 1e-9)


@pytest.mark.parametrize("mu", [0.05, 0.3])
def test_torque_path_dissipates_and_refuses_an_uncarried_torque(mu):
    """Flanks that slip (slides 10x): friction's work over the loop +T -> -T -> +T is > 0, and 0 without friction;
    every torque is carried (seed 0 at mu 0.05 takes the twist-driven increment where the torque-driven sets
    cycle); a torque whose sign no flank carries is refused."""
    from strainwave.fea.mesh_contact import loop_area_Nmm_rad
    hist = np.concatenate([np.linspace(0, 6e4, 5), np.linspace(6e4, -6e4, 9)[1:], np.linspace(-6e4, 6e4, 9)[1:]])
    for seed in (0, 1, 2):
        s = _lobes(mu, seed)
        slips = BandSystem(s.clearance_mm, s.flex_mm_per_N, s.lever_mm, 10 * s.slide_mm_per_rad, mu)
        path, Q = torque_path(slips, hist, 4)
        T = path.forces_N @ slips.lever_mm - Q @ slips.slide_mm_per_rad
        assert T[hist != 0] == pytest.approx(hist[hist != 0], rel=1e-9)
        assert loop_area_Nmm_rad(path) > 1e-3
        frictionless = BandSystem(s.clearance_mm, s.flex_mm_per_N, s.lever_mm, 10 * s.slide_mm_per_rad, 0.0)
        assert abs(loop_area_Nmm_rad(torque_path(frictionless, hist, 4)[0])) < 1e-5   # trapezoids at set changes
    one_side = BandSystem(s.clearance_mm, s.flex_mm_per_N, np.abs(s.lever_mm), s.slide_mm_per_rad, mu)
    with pytest.raises(ValueError, match="not carried"):
        torque_path(one_side, [0.0, -1e3])


def test_frictionless_torque_path_is_the_study_lcp_path():
    """mu = 0 (no tangential load): torque_path and fea/mesh_contact's exact parametric LCP path are one answer on
    the study's history, the zero torques at the dead band's far edge in both."""
    from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path, torque_history
    s = _lobes(0.0, 5)
    n = len(s.clearance_mm)
    history = torque_history(6e4, steps_per_leg=8)
    got, Q = torque_path(s, history, 1)
    assert np.all(Q == 0.0)
    ref = solve_torque_path(MeshSystem(s.clearance_mm, s.flex_mm_per_N[:n, :n], s.lever_mm, s.slide_mm_per_rad,
                                       0.0, 80.0), history)
    assert got.twist_rad == pytest.approx(ref.twist_rad, rel=1e-7, abs=1e-7 * np.abs(ref.twist_rad).max())
    assert got.forces_N == pytest.approx(ref.forces_N, rel=1e-7, abs=1e-8 * ref.forces_N.max())


def test_torque_path_starts_unloaded_and_reads_a_round_off_zero_as_zero():
    """A history that does not begin at 0 is solved from the unloaded state; a zero torque written as 1e-13 of the
    amplitude lands where an exact zero does (the dead band's far edge)."""
    s = _lobes(0.3, 2)
    ref, _ = torque_path(s, [0.0, 3e4, 6e4, 0.0, -3e4], 2)
    got, _ = torque_path(s, [3e4, 6e4, 6e4 * 1e-13, -3e4], 2)
    assert got.twist_rad == pytest.approx(ref.twist_rad[1:], rel=1e-9)
    assert got.forces_N == pytest.approx(ref.forces_N[1:], rel=1e-9, abs=1e-9 * ref.forces_N.max())
    assert ref.twist_rad[3] * ref.twist_rad[2] < 0.0          # past the dead band: the other flanks touch


def test_torque_path_carries_what_the_knee_reader_needs():
    """Two gapped springs a side, frictionless: the true-slip path's knots (its increments) and dead band give the
    knees mesh_contact's exact loop gives (the second spring's knee between two increments: 1 %); without its knots
    the reading would fall back to the history's steps."""
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import solve_torque_path, torque_history
    k, lever, c, g = 1e4, 50.0, 0.01, 0.004
    rated = 4.0 * k * lever * g
    clear, levers = np.array([c, c + g, c, c + g]), np.array([lever, lever, -lever, -lever])
    from strainwave.fea.mesh_contact import MeshSystem
    exact = solve_torque_path(MeshSystem(clear, np.eye(4) / k, levers, np.full(4, 5.0), 0.0, 80.0),
                              torque_history(rated, 10))
    flex = np.block([[np.eye(4) / k, np.zeros((4, 4))], [np.zeros((4, 4)), np.eye(4) / k]])
    path, _ = torque_path(BandSystem(clear, flex, levers, np.full(4, 5.0), 0.0), torque_history(rated, 10), 4)
    assert path.dead_band_rad == exact.dead_band_rad and path.knots.shape[0] > 4 * path.torque_Nmm.size - 8
    got, ref = tm.knee_values(path, rated), tm.knee_values(exact, rated)
    for name in ("K1", "K2", "K3", "T1", "T2"):
        assert got[name] == pytest.approx(ref[name], rel=0.01), name
    assert got["K1"] == pytest.approx(k * lever ** 2, rel=1e-6)


@pytest.mark.parametrize("mu, seed", [(0.1, 4), (0.3, 2), (0.05, 0)])
def test_exact_torque_path_does_not_depend_on_the_step(mu, seed):
    """Decision 078-slipknots48: every state change split out at its own ratio, the rate-independent Coulomb path
    is one curve: the loop's knots at 20 and 40 steps a leg (and 4 increments a step) read the same twists on a
    fixed torque grid to 1e-6 of the loop's twist, and friction's work per cycle is > 0 and the same."""
    from strainwave.fea.mesh_contact import loop_area_Nmm_rad, torque_history
    from strainwave.fea.mesh_loop import resample
    s = _lobes(mu, seed)
    s = BandSystem(s.clearance_mm, s.flex_mm_per_N, s.lever_mm, 10 * s.slide_mm_per_rad, mu)
    paths = [torque_path(s, torque_history(6e4, k), inc)[0] for k, inc in ((20, 1), (40, 1), (20, 4))]
    reads = [resample(p.knots[:, 0], p.knots[:, 1], 200)[1] for p in paths]
    scale = np.abs(reads[0]).max()
    for r in reads[1:]:
        assert np.max(np.abs(r - reads[0])) <= 1e-6 * scale
    areas = [loop_area_Nmm_rad(p) for p in paths]
    assert areas[0] > 1e-3
    assert areas[1:] == pytest.approx([areas[0]] * 2, rel=1e-6)


def test_exact_frictionless_knots_are_the_lcp_knots():
    """mu = 0: the exact torque path's loop is fea/mesh_contact's exact parametric LCP loop on a fixed grid, at a
    coarse step (5 a leg) where the increments' ends alone would cut its corners."""
    from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path, torque_history
    from strainwave.fea.mesh_loop import resample
    s = _lobes(0.0, 3)
    n = len(s.clearance_mm)
    got = torque_path(s, torque_history(6e4, 5), 1)[0]
    ref = solve_torque_path(MeshSystem(s.clearance_mm, s.flex_mm_per_N[:n, :n], s.lever_mm, s.slide_mm_per_rad,
                                       0.0, 80.0), torque_history(6e4, 40))
    a, b = (resample(p.knots[:, 0], p.knots[:, 1], 200)[1] for p in (got, ref))
    assert np.max(np.abs(a - b)) <= 1e-7 * np.abs(b).max()
    assert got.knots.shape[0] > 3 * 5 + 2              # the set changes are knots of their own


def test_a_flank_closing_at_the_band_edge_sticks_from_there():
    """One flank, friction ample for its stick ratio: it closes at the band's edge with N = Q = 0 and sticks from
    there, so Q / N is the stick solution's constant ratio at every load (holding its slip from twist 0 instead
    would load it tangentially at N = 0 and make it slip)."""
    C = 1e-7 * np.array([[2.0, 0.6], [0.6, 1.5]])
    s = BandSystem(np.array([1e-3]), C, np.array([75.0]), np.array([20.0]), 2.0)
    path, Q = torque_path(s, [0.0, 2e4, 4e4, 6e4], 1)
    ratio = Q[1:, 0] / path.forces_N[1:, 0]
    # stick: dslip = Cgf dN + Cgg dQ + w dtheta = 0 and dgap = Cff dN + Cfg dQ - lever dtheta = 0
    w, lev = 20.0, 75.0
    expected = -(C[1, 0] + w * C[0, 0] / lev) / (C[1, 1] + w * C[0, 1] / lev)
    assert ratio == pytest.approx(np.full(3, expected), rel=1e-9)
    assert path.twist_rad[1] > 1e-3 / 75.0
