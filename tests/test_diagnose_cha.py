"""Real data: Harmonic Drive's CHA stiffness table and the recordings made from it. The model's recovery
of the table (exact set, K within 2 %) is measured by `benchmark-diagnose` (CHA rows, PASS/MISS), not here."""
import math

import numpy as np
import pytest

from strainwave.compare.diagnose.generators.cha import ARCMIN, CHA_SLIP_FRACTION, ENCODER_STEP_RAD, cha_recording, cha_rows
from strainwave.compare.diagnose.generators.hifi_torsion import maxwell_slip_twist
from strainwave.compare.diagnose.generators.loop_metrics import measure_loop
from strainwave.compare.diagnose.recording import parse_text

ROWS = cha_rows()


def test_table_is_read_in_si_units():
    assert len(ROWS) == 21
    r = ROWS[0]
    assert (r.size, r.ratio, r.T1_Nmm, r.K1_Nmm_per_rad) == (14, "30", 2000.0, 1.9e6)
    assert all(r.K1_Nmm_per_rad < r.K2_Nmm_per_rad < r.K3_Nmm_per_rad for r in ROWS)


@pytest.mark.parametrize("row", [ROWS[0], ROWS[11], ROWS[20]], ids=lambda r: f"CHA-{r.size}-{r.ratio}")
def test_curve_has_the_table_slopes_and_the_recording_resolves_them(row):
    T = np.linspace(-1.5 * row.T2_Nmm, 1.5 * row.T2_Nmm, 3001)
    k = np.diff(T) / np.diff(row.twist_rad(T))
    for lo, hi, K in ((0.0, row.T1_Nmm, row.K1_Nmm_per_rad), (row.T1_Nmm, row.T2_Nmm, row.K2_Nmm_per_rad),
                      (row.T2_Nmm, 2 * row.T2_Nmm, row.K3_Nmm_per_rad)):
        sel = (T[:-1] >= lo) & (T[1:] <= hi)          # intervals wholly inside one slope
        np.testing.assert_allclose(k[sel], K, rtol=1e-9)
    rec = parse_text(cha_recording(row, hysteresis=False, n=400))
    assert rec.baseline_stiffness == row.K1_Nmm_per_rad and rec.baseline_uncertainty == 0.3
    steps = np.diff(np.unique(rec.response))
    assert np.min(steps) == pytest.approx(ENCODER_STEP_RAD, rel=1e-6)     # the 20-bit encoder's quantisation
    assert np.ptp(rec.response) > 100 * ENCODER_STEP_RAD                   # the three slopes span many steps


def test_the_cha_loop_is_dissipative_and_inside_the_catalogue_limit():
    row = ROWS[0]
    law = lambda T: maxwell_slip_twist(T, 0.8 * row.hysteresis_limit_arcmin * ARCMIN, CHA_SLIP_FRACTION)
    loop = measure_loop(law, 1.5 * row.T2_Nmm)
    assert loop.energy_Nmm_rad > 0
    assert loop.loss_rad / ARCMIN == pytest.approx(0.8 * row.hysteresis_limit_arcmin, rel=1e-9)
    assert math.isfinite(loop.secant_compliance)


@pytest.mark.parametrize("row", ROWS, ids=lambda r: f"CHA-{r.size}-{r.ratio}")
def test_the_cha_gear_with_its_loop_is_passive(row):
    """A chain of springs and Coulomb sliders has a positive tangent compliance everywhere: along every
    monotonic stretch of torque the twist moves with the torque, also right after a reversal at 1.5 T2."""
    T_max = 1.5 * row.T2_Nmm
    T = np.concatenate([np.linspace(0, T_max, 400), np.linspace(T_max, -T_max, 800)[1:],
                        np.linspace(-T_max, T_max, 800)[1:]])
    twist = row.twist_rad(T) + maxwell_slip_twist(T, 0.8 * row.hysteresis_limit_arcmin * ARCMIN, CHA_SLIP_FRACTION)
    assert np.all(np.diff(twist) * np.sign(np.diff(T)) > 0)
