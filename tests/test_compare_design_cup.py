"""The design verdict takes the flexspline's fatigue on the wave generator: the governing (smaller) factor."""
from strainwave.compare.validate.design import DesignVerdict
from strainwave.compare.validate.wg_cup_checks import fatigue_factor

RECORD = {"fatigue": {"n_eq13": 1.95, "n_goodman": 1.80, "amplitude_MPa": 164.8, "mean_MPa": 59.1,
                      "where": "band outer fibre", "notch": "K_sigma 1.9"}}


def test_the_smaller_of_eq13_and_goodman_governs_and_can_fail_the_design():
    f = fatigue_factor(RECORD)
    assert f.safety_factor == 1.80 and "Goodman governs" in f.definition
    assert DesignVerdict(1.4, (f,)).passed and not DesignVerdict(1.9, (f,)).passed


def test_a_missing_case_is_not_evaluated_and_fails_the_design():
    f = fatigue_factor({})
    assert f.safety_factor is None and f.reason
    assert not DesignVerdict(1.4, (f,)).passed


def _ring_book(cam_MPa, net_MPa):
    from types import SimpleNamespace

    from strainwave.compare.validate.fea_book import FeaBook
    q = {"race_stress_major_MPa": SimpleNamespace(value=cam_MPa, uncertainty=1.0),
         "net_race_stress_major_MPa": SimpleNamespace(value=net_MPa, uncertainty=1.0)}
    return FeaBook({"wg-bearing": SimpleNamespace(result=SimpleNamespace(quantities=q), error=None,
                                                  case=SimpleNamespace(study="wg-bearing"))})


def test_the_bearing_ring_on_the_cam_is_goodman_on_its_ball_pass_cycle():
    from strainwave.compare.validate.wg_bearing_checks import fatigue_factor as ring_factor
    from strainwave.params import load_params
    params = load_params()
    # cam alone 800 MPa (a mean in the ring's frame), 700 MPa under the ball: sigma_a 50, sigma_m 750
    f = ring_factor(_ring_book(800.0, 700.0), "wg-bearing", params)
    assert f.safety_factor == 1.0 / (50.0 / 625.0 + 750.0 / 1080.0)
    # the cam's mean stress alone takes the ring below [n] = 1.4, which the bonded-bore ring never showed
    assert not DesignVerdict(1.4, (f,)).passed
    # a ring the cam barely bends passes
    assert DesignVerdict(1.4, (ring_factor(_ring_book(60.0, -10.0), "wg-bearing", params),)).passed
    missing = ring_factor(_ring_book(680.0, 600.0), None, params)
    assert missing.safety_factor is None and missing.reason
