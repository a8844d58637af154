"""A thermal zero drift end to end on a drive's rig file (decision 069): the CHA-20A-100 recording the tests build
from Harmonic Drive's published numbers, plus a warm-up of a shape the detector does not assume, is named a
thermal drift with its rate beside the drive's normal model (stiffening + lost motion + hysteresis), lost motion
kept with its number; the clean file names no drift. Minutes of diagnosis: heavy."""
import math

import numpy as np
import pytest

from strainwave.compare.diagnose.diagnosis import Verdict
from strainwave.compare.diagnose.drive_curve import ARCMIN
from strainwave.compare.diagnose.generators import drive_rig
from strainwave.compare.diagnose.recording import TestFlags as Flags

CHA20 = drive_rig.DriveTruth(16e3, 25e3, 29e3, 7.0, 25.0, clearance_rad=0.6 * ARCMIN, loss_rad=0.5 * ARCMIN)
RATED_NM = 34.0
STEP = drive_rig.ENCODER_STEP_RAD


def _warm_up(shape, x):
    return {"heater": np.where(x < 0.3, 0.5 * (x / 0.3) ** 2, 1.0 - 0.5 * np.exp(-(x - 0.3) / 0.15)),
            "square_root": np.sqrt(x),
            "ramp_to_plateau": np.minimum(x / 0.5, 1.0),
            "exponential": 1.0 - np.exp(-x / 0.2), "none": 0.0 * x}[shape]


# where the catalogue's first answer is "unexplained" the drift is read as decision 067 reads it (one exponential,
# white noise, every row; no rate said): the ramp and the fast exponential land there (decision 069)
FIRST_UNEXPLAINED = pytest.mark.xfail(strict=True, reason="first answer unexplained: decision 067's drift reading")


@pytest.mark.heavy
@pytest.mark.parametrize("shape", ["heater", "square_root", "none",
                                   pytest.param("ramp_to_plateau", marks=FIRST_UNEXPLAINED),
                                   pytest.param("exponential", marks=FIRST_UNEXPLAINED)])
def test_a_warm_up_on_a_cha20_rig_file_is_named_beside_the_drives_normal_model(tmp_path, shape):
    from strainwave.compare.diagnose.pipeline import diagnose_file
    t, T, phi = drive_rig.drive_test(CHA20, 37.5, T_rated=RATED_NM, n=3000, seed=1)
    warm = 40 * STEP * _warm_up(shape, t / t[-1])              # 40 encoder steps (0.8 arcmin)
    path = tmp_path / "cha20.csv"
    path.write_text(drive_rig.rig_file(t, T, phi + warm), encoding="utf-8")
    diag = diagnose_file(path, flags=Flags(stiffness="16e3 Nm/rad", rated_torque=f"{RATED_NM} Nm"))
    assert diag.verdict is Verdict.EXPLAINED
    assert set(diag.named) == {"nonlinear_stiffness", "lost_motion", "hysteresis"}
    truth = drive_rig.truth_readings(CHA20, 37.5, RATED_NM)
    v = diag.catalogue.values
    assert v["lost_motion_arcmin"][0] == pytest.approx(truth["lost_motion_rad"] / ARCMIN, rel=0.10)
    assert v["K1"][0] / 1e3 == pytest.approx(16e3, rel=0.05)
    drifts = [e for e in diag.events if "thermal zero drift" in e]
    if shape == "none":
        assert drifts == []
        return
    assert len(drifts) == 1
    said = drifts[0]
    start = float(said.split(" from ")[1].split(" s")[0])
    k = int(np.searchsorted(t, start))
    change = float(said.split("not load, by ")[1].split(" ")[0])
    assert change == pytest.approx(warm[-1] - warm[k], rel=0.2)
    rate = float(said.split("mean rate ")[1].split(" ")[0])
    assert rate == pytest.approx((warm[-1] - warm[k]) / (t[-1] - t[k]), rel=0.2)
    assert math.isfinite(float(said.split("time constant ")[1].split(" ")[0]))
