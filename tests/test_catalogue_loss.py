"""Decision 070-loss48: the catalogue's hysteresis loss (width at 0 N m of the +/-rated loop) and lost motion (end to
end of a +/-4 % loop), the CHA bounds, the optional columns and the per-row left-out phrases."""
import json
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from strainwave.analytic.catalogue_left_out import PHRASES, row_left_out
from strainwave.analytic.catalogue_loss import (ARCMIN, LossReading, cha_bounds, hysteresis_loss_rad,
                                                loop_width_max_rad, lost_motion_rad, read_loss)
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import predict_curve
from strainwave.cli import main
from strainwave.fea.mesh_contact import torque_history

HEADER = "size,ratio,T1_Nm,T2_Nm,K1_e3,K2_e3,K3_e3"


def _loop(amplitude, K, width0, tip_closed=True, steps=50):
    """0 -> +A -> -A -> +A on the line T / K; the twist lags the torque by width0 / 2 at 0 N m (zero at the tips
    when ``tip_closed``, else a constant band): the loop's width at 0 N m is width0 by construction."""
    T = 1e-3 * torque_history(1e3 * amplitude, steps)
    rate = np.sign(np.concatenate([[1.0], np.diff(T)]))
    shape = (1.0 - (T / amplitude) ** 2) if tip_closed else np.ones_like(T)
    return T, T / K - rate * 0.5 * width0 * shape


@pytest.mark.parametrize("closed", [True, False])
def test_a_loop_of_known_width_reads_that_width(closed):
    T, phi = _loop(100.0, 1e5, 4e-4, tip_closed=closed)
    assert hysteresis_loss_rad(T, phi) == pytest.approx(4e-4, rel=1e-12)


def test_a_loop_that_dissipates_more_reads_more():
    """Twice the width (twice the loop's area): twice the loss; no width: none."""
    a = hysteresis_loss_rad(*_loop(100.0, 1e5, 2e-4))
    b = hysteresis_loss_rad(*_loop(100.0, 1e5, 4e-4))
    assert b == pytest.approx(2.0 * a, rel=1e-12) and a > 0.0
    assert hysteresis_loss_rad(*_loop(100.0, 1e5, 0.0)) == pytest.approx(0.0, abs=1e-18)


def test_lost_motion_is_the_loops_end_to_end_angle_at_4_percent():
    """A loop cycled to +/-4 A: its ends differ by 2 T / K; the same torque on a larger loop reads its centre line,
    the same number; a stiffer line (K x 1.2) reads 1/1.2 of it."""
    K, T_lm = 2.0e4, 4.0
    assert lost_motion_rad(*_loop(T_lm, K, 1e-4), T_lm) == pytest.approx(2.0 * T_lm / K, rel=1e-12)
    assert lost_motion_rad(*_loop(100.0, K, 1e-4), T_lm) == pytest.approx(2.0 * T_lm / K, rel=1e-12)
    assert lost_motion_rad(*_loop(T_lm, 1.2 * K, 0.0), T_lm) == pytest.approx(2.0 * T_lm / K / 1.2, rel=1e-12)
    with pytest.raises(ValueError, match="outside the loop"):
        lost_motion_rad(*_loop(T_lm, K, 0.0), 2.0 * T_lm)


def test_cha_bounds_by_ratio():
    assert cha_bounds(30.0) == (3.0, 1.0) and cha_bounds(50.0) == (1.0, 1.0) and cha_bounds(100.0) == (1.0, 1.0)


def _drive_loss(mu):
    r = replace(MeshRules(cup_zone_elements=None), friction_coefficient=mu)
    d, A, s = r.design(14, 30), r.rated_torque_Nm(14), r.cup_flexibility_rad_per_Nmm(14)
    c = predict_curve(d, s, A, with_te=False)
    k0 = int(np.argmax(c.loop_torque_Nm))
    work = float(np.sum(0.5 * (c.loop_torque_Nm[k0 + 1:] + c.loop_torque_Nm[k0:-1]) * np.diff(c.loop_twist_rad[k0:])))
    return read_loss(d, s, A, c.loop_torque_Nm, c.loop_twist_rad, cha_bounds(30.0), "rule"), work


def test_flank_friction_on_the_drive_from_first_principles():
    """The drive's own chain: without friction no loop at all; with it the loop dissipates (closed integral of
    T dphi > 0) and more mu dissipates more; the width at 0 N m stays zero: the flanks carry no load there (no
    preload), so Coulomb friction has nothing to act with."""
    free, w0 = _drive_loss(0.0)
    low, w1 = _drive_loss(0.08)
    high, w2 = _drive_loss(0.16)
    assert free.hysteresis_loss_arcmin == pytest.approx(0.0, abs=1e-9)
    assert free.loop_width_max_arcmin == pytest.approx(0.0, abs=1e-9) and abs(w0) < 1e-12
    assert 0.0 < w1 < w2 and 0.0 < low.loop_width_max_arcmin < high.loop_width_max_arcmin
    assert abs(low.hysteresis_loss_arcmin) < 1e-9 and abs(high.hysteresis_loss_arcmin) < 1e-9
    # the lost motion is the low-torque line: friction moves it little, the +/-4 % torque sets it
    assert low.lost_motion_torque_Nm == pytest.approx(0.04 * 1e6 / 160.0 ** 3 * (2.54 * 14) ** 3 * 1e-3)
    assert low.lost_motion_arcmin == pytest.approx(free.lost_motion_arcmin, rel=0.05)


def _fake_row(ratios, loss=None, values=None):
    return SimpleNamespace(ratio_of=lambda n: ratios.get(n), loss=loss,
                           row=SimpleNamespace(values=values or {}, size=14, ratio_label="30"))


def _reading(lm, bound=1.0):
    return LossReading(0.0, lm, 0.1, 5.0, 0.44, 3.0, bound, "rule")


def test_each_miss_gets_the_phrase_of_its_side():
    misses = row_left_out(_fake_row({"K3_Nm_per_rad": 1.5, "T1_Nm": 0.5, "K1_Nm_per_rad": 1.2, "T2_Nm": None}))
    assert [(m["quantity"], m["side"]) for m in misses] == [("K3", "high"), ("T1", "low")]
    assert misses[0]["left_out"] == PHRASES[("K3_Nm_per_rad", "high")]
    assert row_left_out(_fake_row({"K3_Nm_per_rad": 0.7}))[0]["left_out"] == PHRASES[("K3_Nm_per_rad", "low")]
    assert row_left_out(_fake_row({}, _reading(0.9))) == []
    # above the bound: the catalogue's own K1 over the same +/-4 % also above -> the test torque is named
    stiff = row_left_out(_fake_row({}, _reading(1.2), {"K1_Nm_per_rad": 2.0 * 0.44 / (1.5 * ARCMIN)}))
    assert "test torque" in stiff[0]["left_out"] and stiff[0]["catalogue_K1_arcmin"] == pytest.approx(1.5)
    soft = row_left_out(_fake_row({}, _reading(1.2), {"K1_Nm_per_rad": 2.0 * 0.44 / (0.5 * ARCMIN)}))
    assert soft[0]["left_out"] == PHRASES[("lost_motion", "high")]
    # a loop open at 0 N m is free play here: the clearance is named, with its angle
    loose = LossReading(1.5, 1.2, 1.5, 0.0, 0.44, 1.0, 1.0, "rule")
    named = row_left_out(_fake_row({}, loose, {"K1_Nm_per_rad": 2.0 * 0.44 / (0.5 * ARCMIN)}))
    assert [m["quantity"] for m in named] == ["hysteresis loss", "lost motion"]
    assert named[0]["left_out"] == PHRASES[("hysteresis", "high")] and "1.50' of free play" in named[1]["left_out"]


@pytest.mark.parametrize("extra, cell, key", [
    (",hysteresis_arcmin", "abc", "hysteresis_arcmin"),
    (",lost_motion_arcmin", "-1", "lost_motion_arcmin"),
    (",rated_torque_Nm", "0", "rated_torque_Nm"),
])
def test_a_bad_loss_column_exits_2_with_one_line(tmp_path, capsys, extra, cell, key):
    table = tmp_path / "t.csv"
    table.write_text(f"{HEADER}{extra}\n14,30,2,6.9,1.9,2.4,3.4,{cell}\n")
    assert main(["catalogue", str(table)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err and cell in err


def test_the_json_and_the_table_carry_the_loss_and_the_left_out(tmp_path, capsys, monkeypatch):
    from strainwave.analytic import catalogue_predict
    monkeypatch.setattr(catalogue_predict, "MeshRules",
                        lambda: MeshRules(cup_zone_elements=None, cs_body_restraint=None))
    table = tmp_path / "t.csv"
    table.write_text(f"{HEADER},hysteresis_arcmin,lost_motion_arcmin,rated_torque_Nm\n"
                     "14,30,2,6.9,1.9,2.4,3.4,0.5,0.2,5\n14,>50,2,6.9,4.7,6.1,7.1,,,\n")
    out = tmp_path / "o.json"
    assert main(["catalogue", str(table), "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    a, b = doc["rows"]
    assert doc["loss_note"] and "Tables 54.1" in doc["loss_source"]    # the zero loss is said to be a pinched loop
    assert doc["flank_mu"] == 0.08 and "section 4" in doc["flank_mu_source"]
    for row in (a, b):
        for key in ("hysteresis_loss_arcmin_predicted", "lost_motion_arcmin_predicted",
                    "hysteresis_loss_arcmin_catalogue", "lost_motion_arcmin_catalogue", "loop_width_max_arcmin"):
            assert isinstance(row[key], float) and np.isfinite(row[key])
        assert all(m["left_out"] for m in row["left_out"])
    assert (a["hysteresis_loss_arcmin_catalogue"], a["lost_motion_arcmin_catalogue"]) == (0.5, 0.2)
    assert a["loss_bounds_from"] == "table" and a["lost_motion_torque_Nm"] == pytest.approx(0.2)
    assert (b["hysteresis_loss_arcmin_catalogue"], b["lost_motion_arcmin_catalogue"]) == (1.0, 1.0)
    assert b["loss_bounds_from"] == "CHA rule" and b["lost_motion_within_bound"] is True
    assert a["lost_motion_within_bound"] is (a["lost_motion_arcmin_predicted"] < 0.2)
    assert any(m["quantity"] == "K3" for m in b["left_out"])
    text = capsys.readouterr().out
    assert "lost m" in text and "left out, per row" in text and "14/>50: " in text and "flank mu = 0.08" in text


def test_a_clearance_shows_in_both_readings_by_its_free_play():
    """A flank clearance is free play: it opens the loop at 0 N m, and the +/-4 % travel grows by at least as much
    (the free play, plus fewer teeth engaged at low torque): the bounds test the rules' clearances."""
    def read(backlash):
        r = replace(MeshRules(cup_zone_elements=None), backlash_over_d=backlash)
        d, A, s = r.design(14, 100), r.rated_torque_Nm(14), r.cup_flexibility_rad_per_Nmm(14)
        c = predict_curve(d, s, A, with_te=False)
        return read_loss(d, s, A, c.loop_torque_Nm, c.loop_twist_rad, cha_bounds(100.0), "rule")
    tight, loose = read(0.0), read(4e-5)
    d_loss = loose.hysteresis_loss_arcmin - tight.hysteresis_loss_arcmin
    d_lm = loose.lost_motion_arcmin - tight.lost_motion_arcmin
    assert tight.hysteresis_loss_arcmin == pytest.approx(0.0, abs=1e-9) and d_loss > 0.1
    assert d_lm >= d_loss * (1.0 - 1e-6)


def test_left_out_lines_print_each_phrase_once_and_number_it_on_every_row():
    from strainwave.analytic.catalogue_left_out import left_out_lines
    rows = [_fake_row({"K3_Nm_per_rad": 1.5, "T1_Nm": 0.5}), _fake_row({"K3_Nm_per_rad": 1.4}), _fake_row({})]
    lines = left_out_lines(rows)
    text = "\n".join(lines)
    assert text.count(PHRASES[("K3_Nm_per_rad", "high")]) == 1 and text.count(PHRASES[("T1_Nm", "low")]) == 1
    assert lines[1].strip() == "14/30: K3 1.50x [1], T1 0.50x [2]" and lines[2].strip() == "14/30: K3 1.40x [1]"
    assert lines[3].startswith("  [1] compliance not modelled") and lines[4].startswith("  [2] ideal teeth")
    assert len(lines) == 5      # the row with no miss has no line
