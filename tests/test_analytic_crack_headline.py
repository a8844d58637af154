"""Seed 000's headline from the confirmed crack forms (analytic.crack_headline)."""
import warnings

import pytest

from strainwave.analytic import crack_headline as ch, tube_crack
from strainwave.params import load_params


@pytest.fixture(scope="module")
def headline():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ch.crack_headline(load_params())


def test_seed_depth_costs_far_less_than_the_seed_claims(headline):
    # 0.1 mm cracks: the shaft's thick-tube form dominates; its shallow limit is pi^2 r_o^3 a^2/(G J^2)
    import math
    G = 2.1e5 / 2.6
    J = math.pi / 2 * (35.0 ** 4 - 22.5 ** 4)
    shaft = headline.components[0]
    assert shaft.delta_lambda_at_seed_depth == pytest.approx(math.pi ** 2 * 35.0 ** 3 * 0.01 / (G * J ** 2), rel=0.01)
    assert headline.drop_all_three < 1e-4 * ch.SEED_CLAIM_PERCENT
    assert headline.components[2].delta_lambda_at_seed_depth == 0.0


def test_one_percent_depth_is_a_root_of_the_form(headline):
    shaft = headline.components[0]
    a = shaft.depth_for_target_mm
    d = tube_crack.thick_tube_flexibility(35.0, 22.5, a, 2.1e5 / 2.6)
    assert d / (headline.lambda_sum_uncracked + d) == pytest.approx(ch.TARGET_DROP, rel=1e-6)
    assert 0 < a < ch.SHAFT_CONFIRMED_A_OVER_T * 12.5
    # the flexspline's through crack needs a half-length beyond the flat-sheet range; the closed bearing crack never
    assert headline.components[1].depth_for_target_mm is None and headline.components[2].depth_for_target_mm is None
