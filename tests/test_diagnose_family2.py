"""Family 2's generators against first principles (friction dissipates, stiffening is monotone and
smooth, the dead zone sits where it was put, a crack closes under the other sign, Ramberg-Osgood leaves
a positive set and closes Masing loops, coloured noise has its stated statistics, out-of-catalogue
physics has its defining signature), and every class is a parseable recording carrying its truth."""
import math
import warnings

import numpy as np
import pytest

from strainwave.compare.diagnose.generators import family2_elastic as fe
from strainwave.compare.diagnose.generators import family2_hysteresis as fh
from strainwave.compare.diagnose.generators import family2_outside as fo
from strainwave.compare.diagnose.generators import family2_sensors as fs
from strainwave.compare.diagnose.generators import generate_family2 as g2
from strainwave.compare.diagnose.generators.cha import ARCMIN, cha_rows
from strainwave.compare.diagnose.generators.loop_metrics import measure_loop, set_after_unloading
from strainwave.compare.diagnose.recording import parse_text

A = 1e5
LAWS = {
    "bouc_wen_gamma_pos": lambda T: fh.bouc_wen_twist(T, 1e8, 0.2 * A, 1e-4, beta=0.6, gamma=0.2, n=1.5),
    "bouc_wen_gamma_neg": lambda T: fh.bouc_wen_twist(T, 1e8, 0.1 * A, 5e-4, beta=0.5, gamma=-0.4, n=1.0),
    "bouc_wen_n_2.5": lambda T: fh.bouc_wen_twist(T, 1e8, 0.3 * A, 3e-4, beta=0.9, gamma=0.9, n=2.5),
    "play_operators": lambda T: fh.play_sum_twist(T, np.linspace(0, 0.4 * A, 15), np.exp(-np.linspace(0, 2, 15)) * 1e-9),
    "preisach": lambda T: 1e-4 * fh.preisach_twist(T, A, coercive=0.3, coercive_spread=0.5, bias_spread=0.3),
}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_every_family2_friction_law_dissipates(name):
    law = LAWS[name]
    loop = measure_loop(law, A, per_leg=400)
    assert loop.energy_Nmm_rad > 0 and loop.loss_rad > 0
    assert set_after_unloading(law, A, per_leg=400) > 0


def test_play_sum_loss_is_twice_the_weighted_thresholds():
    # every play element with 2 r_i <= 2A is fully reversed on a full cycle: width 2 c_i r_i at T = 0
    r, c = np.linspace(0, 0.4 * A, 15), np.exp(-np.linspace(0, 2, 15)) * 1e-9
    assert measure_loop(LAWS["play_operators"], A, per_leg=400).loss_rad == pytest.approx(2 * c @ r, rel=1e-9)


def test_bouc_wen_saturates_at_its_friction_torque():
    # sliding: the tangent stiffness tends to k_e; right after a reversal it is k_e + T_f A / phi_y
    k_e, Tf, phi_y = 1e8, 0.2 * A, 1e-4
    T = np.concatenate([np.linspace(0, A, 2001), np.linspace(A, 0.9 * A, 201)[1:]])
    phi = fh.bouc_wen_twist(T, k_e, Tf, phi_y, beta=0.5, gamma=0.5, n=1.0)
    k_slide = (T[1999] - T[1990]) / (phi[1999] - phi[1990])
    k_stick = (T[2001] - T[2000]) / (phi[2001] - phi[2000])
    assert k_slide == pytest.approx(k_e, rel=0.01)
    assert k_stick == pytest.approx(k_e + Tf / phi_y, rel=0.02)


@pytest.mark.parametrize("law", ["sinh", "power"])
def test_stiffening_is_monotone_and_smooth(law):
    K1 = 1e9
    T = np.linspace(0.0, A, 4001)
    phi = (fe.sinh_stiffening_twist(T, K1, A / (K1 * math.sqrt(2.0 ** 2 - 1))) if law == "sinh"
           else fe.power_stiffening_twist(T, K1, A, 1.5))
    k = 1.0 / np.gradient(phi, T)
    assert k[1] == pytest.approx(K1, rel=1e-3) and k[-2] == pytest.approx(2.0 * K1, rel=2e-3)   # ratio 2 at full scale
    assert np.all(np.diff(k[1:-1]) > 0)                                                        # monotone
    assert np.max(np.abs(np.diff(k[1:-1], 2))) < 1e-4 * K1                                      # no knee


def test_power_stiffening_matches_its_closed_form_at_q_1():
    T = np.linspace(-A, A, 101)
    exact = np.sign(T) * (3e4 / 1e9) * np.log1p(np.abs(T) / 3e4)
    np.testing.assert_allclose(fe.power_stiffening_twist(T, 1e9, 3e4, 1.0), exact, rtol=1e-7, atol=1e-15)


def test_hertz_backlash_dead_zone_is_centred_where_specified():
    gap, k_w, k_L, d_h, T0 = 1e-4, 3e7, 1e9, 2e-5, 7e3
    T = T0 + np.linspace(-A, A, 2001)
    phi = fe.hertz_backlash_twist(T, gap, k_w, k_L, d_h, centre_Nmm=T0)
    np.testing.assert_allclose(phi, -phi[::-1], atol=1e-15)                  # odd about T0
    assert abs(float(np.interp(T0, T, phi))) < 1e-15
    assert np.all(np.diff(phi) > 0)
    np.testing.assert_allclose(fe.hertz_backlash_torque(phi, gap, k_w, k_L, d_h), T - T0, rtol=1e-9, atol=1e-6)
    # inside the clearance only the weak spring carries torque; beyond it the Hertz onset, then linear flanks
    inside = np.abs(T - T0) < 0.5 * k_w * gap
    assert inside.sum() > 10
    np.testing.assert_allclose(phi[inside], (T - T0)[inside] / k_w, rtol=1e-9, atol=1e-18)
    slope_far = (T[-1] - T[-11]) / (phi[-1] - phi[-11])
    assert slope_far == pytest.approx(k_w + k_L, rel=0.05)


@pytest.mark.parametrize("sign", [1, -1])
def test_gradual_crack_closes_over_its_range(sign):
    cx, Tcl = 2e-10, 1e4
    T = np.linspace(-A, A, 4001)
    comp = np.gradient(fe.gradual_crack_twist(T, cx, Tcl, m=2.0, open_sign=sign), T)
    open_side, closed_far = sign * T > 10.0, sign * T < -10 * Tcl
    np.testing.assert_allclose(comp[open_side], cx, rtol=1e-6)
    assert np.all(comp[closed_far] < 0.011 * cx)                            # 1/(1 + 10^2)
    closing = (sign * T < 0) & (sign * T > -10 * Tcl)
    c_closing = comp[closing] if sign == -1 else comp[closing][::-1]
    assert np.all(np.diff(c_closing) < 1e-9 * cx)                          # faces close progressively


def test_ramberg_osgood_leaves_the_masing_set_and_closes_minor_loops():
    c, F0, alpha, n = 1e-3, 60.0, 0.1, 10.0
    g = lambda F: float(fe.ramberg_osgood_skeleton(np.array([F]), c, F0, alpha, n)[0])
    d = fe.ramberg_osgood_masing(np.concatenate([np.linspace(0, 100, 101), np.linspace(100, 0, 101)[1:]]),
                                 c, F0, alpha, n)
    assert d[-1] == pytest.approx(g(100) - 2 * g(50)) and d[-1] > 0          # positive permanent set
    F = np.interp(np.linspace(0, 4, 401), [0, 1, 2, 3, 4], [0, 60, 5, 100, 0])
    d = fe.ramberg_osgood_masing(F, c, F0, alpha, n)
    assert F[270] > 60 and d[270] == pytest.approx(g(F[270]), rel=1e-9)     # past the minor loop: skeleton
    assert F[250] < 60 and d[250] == pytest.approx(d[200] + 2 * g((F[250] - F[200]) / 2))   # Masing reload
    assert d[300] == pytest.approx(g(100))


@pytest.mark.parametrize("kind", ["white", "ar1", "lowpass", "random_walk"])
def test_coloured_noise_has_its_stated_std_and_colour(kind):
    rng = np.random.default_rng(0)
    e = fs.coloured_noise(rng, 200_000, 2.0, kind, rho=0.9, fc=0.1, wander=0.6)
    lag1 = np.corrcoef(e[1:], e[:-1])[0, 1]
    assert float(np.std(e)) == pytest.approx(2.0, rel=0.05)
    expected = {"white": (-0.01, 0.01), "ar1": (0.89, 0.91), "lowpass": (0.9, 1.0), "random_walk": (0.3, 0.4)}[kind]
    assert expected[0] < lag1 < expected[1]


def test_zener_loop_dissipates_and_widens_with_the_loading_rate():
    def width(seconds_per_leg):
        t = np.linspace(0, 4 * seconds_per_leg, 4001)
        T = A * np.interp(t, seconds_per_leg * np.arange(5), [0, 1, 0, -1, 0])
        phi = fo.zener_twist(T, t, 1e-9, 2e-10, 1.0)
        energy = float(np.sum(0.5 * (T[1:] + T[:-1]) * np.diff(phi)))
        return energy
    assert 0 < width(20.0) < width(2.0)        # slower loading relaxes more: a narrower loop


def test_stick_slip_steps_and_channel_delay():
    T = A * np.interp(np.linspace(0, 2, 2001), [0, 1, 2], [0, 1, 0])
    stair = fo.stick_slip_twist(T, 1e-5, 0.1 * A)
    jumps = np.diff(stair)[np.abs(np.diff(stair)) > 0]
    assert len(jumps) == 20 and np.allclose(np.abs(jumps), 1e-5)           # 10 slips up, 10 back
    y = np.arange(10.0)
    np.testing.assert_array_equal(fs.delay(y, 3), [0, 0, 0, 0, 1, 2, 3, 4, 5, 6])


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


@pytest.mark.parametrize("cls", g2.CLASSES)
def test_every_family2_class_is_a_recording_with_its_truth(cls, params):
    c = g2.generate(cls, np.random.default_rng(11), params, rows=(300, 400))
    rec = parse_text(c.text)
    assert rec.n >= 300 and c.family == 2
    if cls in g2.IN_CATALOGUE:
        assert c.truth == g2.IN_CATALOGUE[cls] and c.snr > 0 and not c.out_of_catalogue
        assert (c.loss_arcmin is not None) == ("hysteresis" in c.truth)
        if c.loss_arcmin is not None:
            assert c.energy_Nmm_rad > 0
    elif cls in g2.OUT_OF_CATALOGUE:
        assert c.out_of_catalogue == cls and not c.truth and c.snr >= 4.0
    else:
        assert c.clean and (c.noise == "white") == (cls == "clean_white")


def test_family2_cha_recording_carries_the_table_and_a_dissipative_loop():
    row = cha_rows()[4]
    c = g2.cha_recording(row, loop=True, rng=np.random.default_rng(0))
    rec = parse_text(c.text)
    assert rec.baseline_uncertainty == 0.3 and rec.baseline_stiffness == pytest.approx(row.K1_Nmm_per_rad, rel=0.21)
    assert c.stiffness_Nmm_per_rad == (row.K1_Nmm_per_rad, row.K2_Nmm_per_rad, row.K3_Nmm_per_rad)
    assert 0 < c.loss_arcmin < row.hysteresis_limit_arcmin and c.energy_Nmm_rad > 0
    assert c.loss_arcmin * ARCMIN > 0


@pytest.mark.parametrize("seed", range(8))
def test_a_spliced_recording_changes_its_compliance_inside_the_test(seed, params):
    """Two specimens spliced: the slopes of the first and the last quarter differ by more than the 2 %
    stiffness uncertainty (the splice is 10-30 %), for the two-sided torsion paths and the one-sided ring
    paths alike (the first version spliced rings at their end point: nothing changed)."""
    c = g2.generate("spliced", np.random.default_rng(seed), params, rows=(600, 800))
    rec = parse_text(c.text)
    q = rec.n // 4
    slopes = []
    for part in (slice(0, q), slice(rec.n - q, rec.n)):
        u, y = rec.load[part], rec.response[part]
        A = np.column_stack([np.ones_like(u), np.arange(len(u)), u])
        slopes.append(np.linalg.lstsq(A, y, rcond=None)[0][2])
    assert abs(slopes[1] / slopes[0] - 1.0) > 0.05
