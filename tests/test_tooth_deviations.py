"""Tooth manufacturing deviations (ISO 1328-1 class) in the closed-form mesh: decision 070-engage48."""
from __future__ import annotations

import numpy as np
import pytest

import strainwave.analytic.tooth_deviations as td
from strainwave.analytic.catalogue_predict import predict_table
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import _loop, catalogue_secants, predict_mean_curve
from strainwave.analytic.mesh_drive import mesh_system
from strainwave.fea.mesh_contact import loop_area_Nmm_rad

SIZE, RATIO = 14.0, 100.0         # Z_f = 200: a cheap drive whose mesh deviations matter (m = 0.18 mm)
UNITS = 6


def _rules(grade=None, **kw) -> MeshRules:
    # the CS body's FE left out (tests/test_cs_housing.py holds it): these tests are the deviations' own
    return MeshRules(cup_zone_elements=None, cs_body_restraint=None, accuracy_grade=grade, deviation_units=UNITS, **kw)


def test_iso_1328_tolerances_by_hand_and_class_step():
    # ISO 1328-1:2013 eq. 5, 6, 8 at d = 100 mm, m = 2 mm, class 5, worked by hand
    t = td.iso1328_tolerances_um(2.0, 100.0, 5)
    assert t.single_pitch_um == pytest.approx(0.1 + 0.8 + 5.0)
    assert t.total_pitch_um == pytest.approx(0.2 + 5.5 + 1.4 + 12.0)
    assert t.profile_form_um == pytest.approx(1.1 + 5.0)
    # two classes coarser double every tolerance (the step sqrt 2 per class)
    t7 = td.iso1328_tolerances_um(2.0, 100.0, 7)
    assert t7.single_pitch_um == pytest.approx(2.0 * t.single_pitch_um)
    assert td.outside_iso_range(0.3, 200) and not td.outside_iso_range(0.6, 200)


def test_a_drawn_unit_has_the_tolerances_as_its_statistics():
    z, m, grade = 2000, 1.0, 6
    dev = td.draw_deviations(z, z + 2, m, grade, seed=3)
    tol = td.iso1328_tolerances_um(m, m * z, grade)
    pitch = 1e3 * np.diff(dev.fs_place_mm)
    # the single pitch deviation has f_pT as its two-sigma bound (the wave adds ~F_p pi / Z per pitch, negligible)
    assert np.std(pitch) == pytest.approx(0.5 * tol.single_pitch_um, rel=0.08)
    # the once-per-revolution wave has amplitude F_pT / 2
    first = 2.0 * np.abs(np.fft.rfft(1e3 * dev.fs_place_mm)[1]) / z
    assert first == pytest.approx(0.5 * tol.total_pitch_um, rel=0.05)
    assert np.std(1e3 * dev.fs_form_mm) == pytest.approx(0.5 * tol.profile_form_um, rel=0.05)
    again = td.draw_deviations(z, z + 2, m, grade, seed=3)
    other = td.draw_deviations(z, z + 2, m, grade, seed=4)
    assert np.array_equal(again.cs_place_mm, dev.cs_place_mm)
    assert not np.allclose(other.cs_place_mm, dev.cs_place_mm)


def test_zero_deviations_reproduce_the_ideal_mesh_exactly(monkeypatch):
    ideal = _rules().design(SIZE, RATIO)
    zero = lambda zf, zc, m, grade, seed: td.ToothDeviations(np.zeros(zf), np.zeros(zc), np.zeros((zf, 2)),
                                                             np.zeros((zc, 2)))
    monkeypatch.setattr(td, "draw_deviations", zero)
    unit = _rules(5.0).design(SIZE, RATIO, 0)
    a, b = mesh_system(ideal)[0], mesh_system(unit)[0]
    assert np.array_equal(a.clearance_mm, b.clearance_mm)
    ser, rated = 1e-8, _rules().rated_torque_Nm(SIZE)
    assert np.array_equal(_loop(ideal, ser, rated, 0.0)[1], _loop(unit, ser, rated, 0.0)[1])
    # no class: the unit argument is ignored
    assert np.array_equal(mesh_system(_rules().design(SIZE, RATIO, 3))[0].clearance_mm, a.clearance_mm)


def test_a_unit_stays_zero_backlash_with_every_gap_open():
    ideal = mesh_system(_rules().design(SIZE, RATIO))[0]
    for u in range(3):
        s = mesh_system(_rules(6.0).design(SIZE, RATIO, u))[0]
        assert np.all(s.clearance_mm >= 0.0)
        for sgn in (1.0, -1.0):
            on = np.sign(s.lever_mm) == sgn
            assert s.clearance_mm[on].min() == ideal.clearance_mm[np.sign(ideal.lever_mm) == sgn].min() == 0.0
        assert not np.allclose(s.clearance_mm, ideal.clearance_mm)


def _low_torque(grade):
    """(mean twist at 20 % of rated on the first loading, mean pairs in contact there) over the units."""
    rules = _rules(grade)
    rated = rules.rated_torque_Nm(SIZE)
    units = [None] if grade is None else range(UNITS)
    tw, n = [], []
    for u in units:
        T, twist, path = _loop(rules.design(SIZE, RATIO, u), 0.0, rated, 0.0)
        k = int(np.argmin(np.abs(T[:len(T) // 5 + 1] - 0.2 * rated)))
        tw.append(twist[k])
        n.append(path.contact[k].sum())
    return float(np.mean(tw)), float(np.mean(n))


def test_wider_tolerances_delay_engagement_and_soften_the_start():
    ideal, fine, coarse = _low_torque(None), _low_torque(3.0), _low_torque(7.0)
    assert ideal[0] < fine[0] < coarse[0]                 # more twist to carry the same low torque
    assert ideal[1] > fine[1] > coarse[1]                 # fewer pairs have closed their gaps


def test_the_units_loops_dissipate_and_stiffen():
    rules = _rules(5.0)
    rated = rules.rated_torque_Nm(SIZE)
    designs = [rules.design(SIZE, RATIO, u) for u in range(UNITS)]
    for d in designs[:3]:
        assert loop_area_Nmm_rad(_loop(d, 0.0, rated, 0.0)[2]) > 0.0
        assert abs(loop_area_Nmm_rad(_loop(d.with_friction(0.0), 0.0, rated, 0.0)[2])) < 1e-9 * rated * 1e3
    curve = predict_mean_curve(designs, 1e-8, rated)
    k = catalogue_secants(curve.loop_torque_Nm, curve.loop_twist_rad, 0.2 * rated, 0.7 * rated)
    assert k["K1_Nm_per_rad"] <= k["K2_Nm_per_rad"] <= k["K3_Nm_per_rad"]
    assert curve.hysteresis_rad >= 0.0


def test_the_catalogue_command_reads_the_mean_of_the_units(tmp_path):
    table = tmp_path / "t.csv"
    table.write_text("size,ratio,T1_Nm,T2_Nm,K1_e3,K2_e3,K3_e3\n14,>50,2,6.9,4.7,6.1,7.1\n")
    ideal = predict_table(table, _rules())
    worn = predict_table(table, _rules(6.0))
    assert "class 6" in worn.to_dict()["tooth_deviations"] and "extrapolated" in worn.summary()
    assert worn.rows[0].ratio_of("K1_Nm_per_rad") < ideal.rows[0].ratio_of("K1_Nm_per_rad")
    data = worn.to_dict()
    assert data["design_rules"]["accuracy_grade"] == 6.0
    # the spread of one unit about the mean is reported beside the mean; ideal teeth have none
    assert data["rows"][0]["T1_Nm_unit_sd"] > 0.0 and "T1_Nm_unit_sd" not in ideal.to_dict()["rows"][0]
    assert "one unit alone scatters" in worn.summary()
