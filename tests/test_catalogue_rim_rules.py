"""Decision 069: the rim under the teeth from the flexspline steel's Goodman line (HDS patent 9534681's sizing),
and the 2 m rule; one rule for every row, similar drives at a fixed ratio."""
import math

import pytest

from strainwave.analytic.catalogue_rules import MeshRules, RimRule, fatigue_rim_mm

STEEL = (625.0, 1080.0, 1.07 * 1.9, 1.4)      # sigma_-1, R_m, K_delta K_sigma, [n]: defaults.toml's


def _goodman_n(t, d, m, w0, E, T):
    """Decision 066's factor, written out independently: n = 1 / (K sigma_a / sigma_-1 + sigma_m / R_m)."""
    s_1, R_m, K, _ = STEEL
    R = 0.5 * d - 1.25 * m - 0.5 * t
    sigma_a = 1.5 * E * t * w0 / R ** 2
    sigma_m = math.sqrt(3.0) * T / (2.0 * math.pi * R ** 2 * t)
    return 1.0 / (K * sigma_a / s_1 + sigma_m / R_m)


@pytest.mark.parametrize("ratio", [30, 100])
def test_the_fatigue_rim_sits_on_the_permissible_factor(ratio):
    d, E, T = 63.5, 2.1e5, 6.25e4
    m = d / (2 * ratio)
    t = fatigue_rim_mm(d, m, m, E, T, STEEL)
    assert _goodman_n(t, d, m, m, E, T) == pytest.approx(1.4, rel=1e-9)
    assert _goodman_n(1.2 * t, d, m, m, E, T) < 0.9 * 1.4          # 20 % thicker: fails the line
    assert _goodman_n(0.8 * t, d, m, m, E, T) > 1.4 / 0.9          # 20 % thinner: passes with margin


def test_the_fatigue_rim_thickens_as_the_module_shrinks_and_keeps_similitude():
    r = MeshRules(rim_rule=RimRule.FATIGUE)
    t = {i: r.rim_mm(25, i) / r.pitch_diameter_mm(25) for i in (30, 50, 100)}
    assert t[30] < t[50] < t[100]                                   # flexure strain ~ t w0: w0 = m ~ 1 / i
    assert t[100] / t[30] == pytest.approx(100 / 30, rel=0.1)
    assert r.rim_mm(50, 50) == pytest.approx(2.0 * r.rim_mm(25, 50), rel=1e-9)
    assert MeshRules(rim_rule="module").rim_mm(25, 50) == pytest.approx(2.0 * 63.5 / 100)
    assert MeshRules(rim_rule="blank").rim_mm(25, 50) == pytest.approx(63.5 * 2.24 / 160)


def test_an_impossible_torque_has_no_rim():
    with pytest.raises(ValueError, match="Goodman"):
        fatigue_rim_mm(63.5, 0.3175, 0.3175, 2.1e5, 1e9, STEEL)
