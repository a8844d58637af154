"""Ball-load laws (analytic/hertz_ball_loads.py): Stribeck's Hertz sum, linear springs, and Hertz with a ring
spring in series, which runs from the first (g -> 0) towards the second (g -> infinity)."""
import numpy as np
import pytest

from strainwave.analytic import hertz_ball_loads as hb


def test_stribeck_and_linear_limits():
    assert hb.hertz_load_ratio(24) == pytest.approx(4.3696, abs=1e-4)
    assert hb.linear_spring_load_ratio(24) == pytest.approx(4.0, rel=1e-12)      # sum cos^2 over the half = Z/4
    assert hb.hertz_load_ratio(400) == pytest.approx(4.37, abs=0.01)           # Stribeck's Z -> infinity
    with pytest.raises(ValueError):
        hb.loaded_ball_angles_rad(2)


def test_series_spring_runs_from_hertz_to_linear():
    F, Z, K = 2500.0, 24, 3.3e6
    q = hb.series_spring_loads_N(F, Z, K, 0.0)
    c = np.cos(hb.loaded_ball_angles_rad(Z))
    assert q @ c == pytest.approx(F, rel=1e-10)
    assert hb.series_spring_load_ratio(F, Z, K, 0.0) == pytest.approx(hb.hertz_load_ratio(Z), rel=1e-10)
    soft = hb.series_spring_load_ratio(F, Z, K, 1e-3)          # the spring dominates: nearly linear
    assert soft == pytest.approx(hb.linear_spring_load_ratio(Z), rel=2e-3)
    shifts = [hb.ring_compliance_shift(F, Z, K, g) for g in (1e-8, 1e-7, 1e-6)]
    assert 0 < shifts[0] < shifts[1] < shifts[2] < 1 - hb.linear_spring_load_ratio(Z) / hb.hertz_load_ratio(Z)
