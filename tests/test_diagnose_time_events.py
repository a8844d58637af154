"""Events in time the catalogue cannot draw (time_events.py): a one-way slip, creep under a hold, a thermal zero
drift. Each generated here in a form the detector does not assume (slips spread over samples, a logarithmic
creep, a square-root warm-up), each found and named; clean recordings, and a stick-slip joint stepping both
ways, trigger none."""
import math

import numpy as np
import pytest

from strainwave.compare.diagnose.drive_curve import ARCMIN
from strainwave.compare.diagnose.generators import drive_rig
from strainwave.compare.diagnose.generators.family2_outside import log_creep, stick_slip_twist
from strainwave.compare.diagnose.time_events import find_hold_creep, find_slips, find_time_events

CHA20 = drive_rig.DriveTruth(16e3, 25e3, 29e3, 7.0, 25.0, clearance_rad=0.6 * ARCMIN, loss_rad=0.5 * ARCMIN)
STEP = drive_rig.ENCODER_STEP_RAD


@pytest.fixture(scope="module")
def drive():
    t, T, phi = drive_rig.drive_test(CHA20, 37.5, T_rated=34.0, n=3000, seed=1)
    return t, T * 1e3, phi


def _walking_flange(T):
    """A flange that slips forward by 2 arcmin, spread over two samples, each time the torque first passes
    93 % of its peak on the positive side (a clamp too weak one way)."""
    out, total = np.zeros_like(T), 0.0
    top = 0.93 * float(np.max(T))
    for k in range(1, len(T)):
        if T[k] > top >= T[k - 1]:
            out[k:k + 2] += ARCMIN * np.array([1.0, 2.0])[:len(out[k:k + 2])]
            total += 2 * ARCMIN
            out[k + 2:] += 2 * ARCMIN
    return out, total


def test_a_walking_flange_is_a_one_way_slip_and_taken_out(drive):
    t, T, phi = drive
    walk, total = _walking_flange(T)
    y, said = find_slips(T, phi + walk)
    assert said is not None and "one-way slip" in said and "up" in said
    assert float(said.split(", ")[2].split(" ")[0]) == pytest.approx(total, rel=0.05)
    assert np.ptp(y - phi) < 0.05 * total                     # taken out: the clean twist is left
    assert find_slips(T, phi)[1] is None                       # the clean drive: no slip


def test_a_stick_slip_joint_stepping_both_ways_is_no_one_way_slip_nor_a_drift(drive):
    t, T, phi = drive
    steps = stick_slip_twist(T, 60 * STEP, 8000.0)
    assert find_slips(T, phi + steps)[1] is None
    assert find_time_events(T, phi + steps, t, 375) is None


def test_a_square_root_warm_up_is_a_thermal_drift_and_the_clean_drive_is_not(drive):
    t, T, phi = drive
    assert find_time_events(T, phi, t, 375) is None
    warm = 20 * STEP * np.sqrt(t / t[-1])                      # a body heated at its surface: sqrt(t), no tau
    found = find_time_events(T, phi + warm, t, 375)
    assert found is not None and len(found.sentences) == 1 and "thermal zero drift" in found.sentences[0]
    kept = slice(375, None)                                    # after the first loading, as the detector reads
    beyond_line = warm[kept] - np.polyval(np.polyfit(t[kept], warm[kept], 1), t[kept])
    said = float(found.sentences[0].split("straight line by ")[1].split(" ")[0])
    assert said == pytest.approx(np.ptp(beyond_line), rel=0.25)
    left = (found.response - phi)[kept]
    left = left - np.polyval(np.polyfit(t[kept], left, 1), t[kept])      # the line is the nuisance fit's
    assert np.std(left) < 0.35 * np.std(beyond_line)


def _held(n=900):
    """Up to +T, hold, down to -T, hold, back: (time s, torque N*mm)."""
    knots = [0.0, 1.0, 1.0, -1.0, -1.0, 0.0]
    s = np.linspace(0.0, len(knots) - 1, n)
    return np.linspace(0.0, 90.0, n), 1e6 * np.interp(s, np.arange(len(knots)), knots)


def _held_creep():
    """A torque held at +-T with logarithmic creep in each hold (no exponential assumed), kept after it."""
    t, T = _held()
    c, sigma = 1e-9, 2e-6
    noise = sigma * np.random.default_rng(5).standard_normal(t.size)
    held = np.abs(T) >= 1e6 - 1e-6
    edges = np.flatnonzero(np.diff(held.astype(int)))
    creep = log_creep(t, t[edges[0] + 1], t[edges[1]], 8 * sigma, 2.0) \
        - log_creep(t, t[edges[2] + 1], t[edges[3]], 8 * sigma, 2.0)
    return t, T, c, sigma, noise, held, creep


def test_creep_under_a_hold_is_named_with_a_time_constant_and_a_clean_hold_is_not():
    t, T, c, sigma, noise, held, creep = _held_creep()
    y, said = find_hold_creep(T, c * T + creep + noise, t, sigma, "rad")
    assert len(said) == 2 and all("creep under a hold" in s and "time constant" in s for s in said)
    assert np.std((y - c * T - noise)[held]) < 0.3 * np.std(creep[held])
    _, none = find_hold_creep(T, c * T + noise, t, sigma, "rad")
    assert none == []
    # a drift during a hold that goes on the same way under the opposite torque is no creep
    _, drift = find_hold_creep(T, c * T + noise + 8 * sigma * np.sqrt(t / t[-1]), t, sigma, "rad")
    assert len(drift) <= 1


# --- a thermal zero drift read beside every verdict (decision 069) -------------------------------------------

def _ar1(n, phi, sigma, seed):
    """AR(1) sensor noise (a drifting amplifier, not the detector's white model)."""
    e = sigma * np.random.default_rng(seed).standard_normal(n)
    out = np.zeros(n)
    for k in range(1, n):
        out[k] = phi * out[k - 1] + e[k]
    return out


def _warm_up(shape, x):
    """Warm-ups of unit size on x = t / t_end, none of them the detector's one exponential."""
    return {"square_root": np.sqrt(x),                                          # a surface-heated body
            "ramp_to_plateau": np.minimum(x / 0.5, 1.0),                        # a heater's linear ramp, then steady
            "heater": np.where(x < 0.3, 0.5 * (x / 0.3) ** 2, 1.0 - 0.5 * np.exp(-(x - 0.3) / 0.15)),
            "exponential": 1.0 - np.exp(-x / 0.2)}[shape]


def _said_drift(sentence):
    return float(sentence.split("not load, by ")[1].split(" ")[0])


@pytest.mark.parametrize("shape, ar1", [("square_root", False), ("ramp_to_plateau", False), ("heater", False),
                                        ("exponential", True), ("square_root", True)])
def test_a_warm_up_of_any_shape_is_a_thermal_drift_with_its_rate(drive, shape, ar1):
    from strainwave.compare.diagnose.time_events import find_thermal_drift
    t, T, phi = drive
    # behind the AR(1) sensor (std 2.3 encoder steps, its wander slow) a warm-up of 80 steps; 40 behind white
    warm = (80 if ar1 else 40) * STEP * _warm_up(shape, t / t[-1])
    noise = _ar1(t.size, 0.9, STEP, 11) if ar1 else 0.0
    found = find_thermal_drift(T, phi + noise + warm, t, 375)
    assert found is not None and "thermal zero drift" in found.said and "mean rate" in found.said
    # the drift it reports is the one over the rows it read (after the first loading): within 15 % behind white
    # noise, 20 % behind the AR(1) sensor (whose own wander over the record is a tenth of the drift)
    tolerance = 0.2 if ar1 else 0.15
    assert _said_drift(found.said) == pytest.approx(warm[-1] - warm[375], rel=tolerance)
    rate = float(found.said.split("mean rate ")[1].split(" ")[0])
    assert rate == pytest.approx((warm[-1] - warm[375]) / (t[-1] - t[375]), rel=tolerance)
    # what it takes out is the warm-up's departure from a line (the nuisance fit keeps the line)
    kept = slice(375, None)
    beyond = warm[kept] - np.polyval(np.polyfit(t[kept], warm[kept], 1), t[kept])
    left = (phi + warm - found.curve)[kept] - phi[kept]
    left = left - np.polyval(np.polyfit(t[kept], left, 1), t[kept])
    assert np.std(left) < 0.35 * np.std(beyond)


@pytest.mark.parametrize("case", ["clean", "ar1_alone", "straight_line", "stick_slip", "one_way_slip"])
def test_no_thermal_drift_where_the_twist_does_not_drift_in_time_beyond_a_line(drive, case):
    from strainwave.compare.diagnose.time_events import find_thermal_drift
    t, T, phi = drive
    extra = {"clean": lambda: 0.0, "ar1_alone": lambda: _ar1(t.size, 0.9, STEP, 12),
             "straight_line": lambda: 40 * STEP * t / t[-1],           # the nuisance fit's own drift
             "stick_slip": lambda: stick_slip_twist(T, 60 * STEP, 8000.0),
             "one_way_slip": lambda: _walking_flange(T)[0]}[case]()
    assert find_thermal_drift(T, phi + extra, t, 375) is None


def test_creep_under_a_hold_is_no_thermal_drift():
    from strainwave.compare.diagnose.time_events import find_thermal_drift
    t, T, c, sigma, noise, held, creep = _held_creep()
    assert find_thermal_drift(T, c * T + creep + noise, t, 150) is None
