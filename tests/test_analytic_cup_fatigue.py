"""Safety factors of the flexspline's revolution cycle (analytic/cup_fatigue.py)."""
import math

import pytest

from strainwave.analytic.cup_fatigue import cup_fatigue_of, cup_fatigue_safety, goodman_safety_factor
from strainwave.params import load_params


def test_fully_reversed_cycle_both_forms_agree():
    s = cup_fatigue_safety(100.0, 0.0, fatigue_limit_MPa=625.0, ultimate_strength_MPa=1080.0,
                           stress_concentration=1.9, mean_stress_influence=0.12)
    assert s.n_eq13 == pytest.approx(625.0 / 190.0)
    assert s.n_goodman == pytest.approx(625.0 / 190.0)


def test_tensile_mean_lowers_both_and_goodman_uses_the_ultimate_strength():
    s = cup_fatigue_safety(161.0, 55.0, fatigue_limit_MPa=625.0, ultimate_strength_MPa=1080.0,
                           stress_concentration=1.9, mean_stress_influence=0.12)
    assert s.n_eq13 == pytest.approx(625.0 / (1.9 * 161.0 + 0.12 * 55.0))
    assert s.n_goodman == pytest.approx(1.0 / (1.9 * 161.0 / 625.0 + 55.0 / 1080.0))
    assert s.n_goodman < 625.0 / (1.9 * 161.0)


def test_compressive_mean_is_not_credited_by_goodman():
    assert goodman_safety_factor(625.0, 1080.0, 1.0, 100.0, -50.0) == pytest.approx(6.25)
    assert math.isinf(goodman_safety_factor(625.0, 1080.0, 1.0, 0.0, -5.0))


def test_from_params_and_bad_input():
    p = load_params()
    s = cup_fatigue_of(p, 50.0, 10.0)
    assert s.ultimate_strength_MPa == p.material.ultimate_strength_MPa == 1080.0
    with pytest.raises(ValueError):
        cup_fatigue_of(p, -1.0, 0.0)
