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
