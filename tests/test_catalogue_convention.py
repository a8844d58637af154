"""Decision 069: K1/K2/K3 as the catalogue defines them (CHA manual 1018854 eq. 68.1-68.4), the secant slopes of the
loop's mean curve over 0-T1, T1-T2 and T2 to the amplitude."""
import numpy as np
import pytest

from strainwave.analytic.drive_curve import catalogue_secants, mean_twist_rad
from strainwave.fea.mesh_contact import torque_history

K = (6.7e4, 1.1e5, 1.2e5)       # the manual's worked example: HFUC-32-100, T1 29, T2 108 N m
T1, T2 = 29.0, 108.0


def _catalogue_phi(T):
    """The manual's piecewise-linear torsion angle, odd in T."""
    a = np.abs(T)
    phi = np.minimum(a, T1) / K[0] + np.clip(a - T1, 0.0, T2 - T1) / K[1] + np.maximum(a - T2, 0.0) / K[2]
    return np.sign(T) * phi


def _loop(amplitude, half_width_rad=0.0):
    T = 1e-3 * torque_history(1e3 * amplitude, int(amplitude))    # 1 N m steps: the knees on the grid
    rate = np.sign(np.concatenate([[1.0], np.diff(T)]))
    # a loop around the catalogue's curve, closed at its tips: the twist lags the torque on each branch
    return T, _catalogue_phi(T) - rate * half_width_rad * (1.0 - (T / amplitude) ** 2)


def test_the_manuals_example_angle():
    """60 N m on the example's curve is 7.15e-4 rad (2.5 arcmin), as the manual computes."""
    assert _catalogue_phi(np.array([60.0]))[0] == pytest.approx(7.15e-4, rel=2e-3)


@pytest.mark.parametrize("width", [0.0, 3e-5])
def test_secants_recover_the_catalogue_slopes_through_a_loop(width):
    T, phi = _loop(150.0, width)
    assert mean_twist_rad(T, phi, np.array([60.0]))[0] == pytest.approx(_catalogue_phi(np.array([60.0]))[0], rel=1e-9)
    sec = catalogue_secants(T, phi, T1, T2)
    for name, k in zip(("K1_Nm_per_rad", "K2_Nm_per_rad", "K3_Nm_per_rad"), K):
        assert sec[name] == pytest.approx(k, rel=1e-9)


def test_windows_off_the_catalogues_knees_read_other_slopes():
    """Read over windows 20 % off the curve's own knees, K1 and K2 move by more than the goals' resolution."""
    T, phi = _loop(150.0)
    sec = catalogue_secants(T, phi, 1.2 * T1, 1.2 * T2)
    assert abs(sec["K1_Nm_per_rad"] / K[0] - 1.0) > 0.02 and abs(sec["K2_Nm_per_rad"] / K[1] - 1.0) > 0.005
    with pytest.raises(ValueError, match="T1 < T2 < amplitude"):
        catalogue_secants(T, phi, T1, 200.0)


def _row_prediction(values):
    from strainwave.analytic.catalogue_predict import TableRow, _with_secants
    from strainwave.analytic.drive_curve import DriveCurve
    T, phi = _loop(150.0)
    curve = DriveCurve(1.0, 2.0, 3.0, 25.0, 100.0, 0.0, 0.0, 150.0, T, phi)     # the reader's numbers: markers
    return _with_secants(TableRow(32.0, "100", values, 2), curve)


def test_a_row_reads_its_own_windows_and_falls_back_where_they_do_not_fit():
    rp = _row_prediction({"T1_Nm": T1, "T2_Nm": T2, "K3_Nm_per_rad": 1.2e5})
    assert rp.predicted("K3_Nm_per_rad") == pytest.approx(K[2], rel=1e-9) and rp.windows_from == "catalogue"
    assert rp.reader("K3_Nm_per_rad") == 3.0 and rp.predicted("T2_Nm") == 100.0    # the knees stay the reader's
    blank = _row_prediction({"T1_Nm": T1})                   # no T2: the predicted knee's
    assert blank.windows_Nm == (T1, 100.0) and "predicted" in blank.windows_from
    beyond = _row_prediction({"T1_Nm": T1, "T2_Nm": 160.0})  # T2 past the loop: the reader's K, said so
    assert beyond.predicted("K3_Nm_per_rad") == 3.0 and beyond.windows_from.startswith("none")
