"""`strainwave catalogue TABLE.csv [--json FILE]` (issue 48, item 5): rows, blanks, labels, JSON keys, bad input."""
import json

import pytest

from strainwave.analytic.catalogue_predict import read_table
from strainwave.analytic.catalogue_rules import MeshRules, ratio_of_label
from strainwave.cli import main
from strainwave.errors import InputError

HEADER = "size,ratio,T1_Nm,T2_Nm,K1_e3,K2_e3,K3_e3\n"


def test_two_rows_with_a_blank_cell_and_a_label(tmp_path, capsys, monkeypatch):
    from strainwave.analytic import catalogue_predict
    # the cup-zone FE on coarse meshes, the CS body left out: this test is the command's plumbing
    # (tests/test_cup_zone.py and tests/test_cs_housing.py hold the FE)
    monkeypatch.setattr(catalogue_predict, "MeshRules", lambda: MeshRules(cup_zone_elements=(7, 5, 4),
                                                                          cs_body_restraint=None))
    table = tmp_path / "t.csv"
    table.write_text("# a comment\n" + HEADER + "14,30,2,6.9,1.9,,3.4\n14,>50,2,6.9,4.7,6.1,7.1\n")
    out = tmp_path / "o.json"
    assert main(["catalogue", str(table), "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert [r["ratio"] for r in data["rows"]] == ["30", ">50"]
    assert data["rows"][1]["ratio_number"] == 100.0
    for name in ("K1_Nm_per_rad", "K2_Nm_per_rad", "K3_Nm_per_rad", "T1_Nm", "T2_Nm"):
        assert data["rows"][1][f"{name}_predicted"] > 0.0
        assert f"{name}_catalogue" in data["rows"][0]
    assert data["rows"][0]["K2_Nm_per_rad_catalogue"] is None           # the blank cell: no comparison
    # decision 069: K over the row's own T1, T2 windows; the knee reader's K beside, its T1/T2 the predicted knees
    assert data["rows"][1]["K_windows_Nm"] == [2.0, 6.9] and data["rows"][1]["K_windows_from"] == "catalogue"
    assert data["rows"][1]["K3_Nm_per_rad_reader"] > 0.0
    assert data["rows"][1]["K1_Nm_per_rad_predicted"] != data["rows"][1]["K1_Nm_per_rad_reader"]
    assert data["rows"][1]["K3_Nm_per_rad_catalogue"] == pytest.approx(7100.0)
    assert data["ratio_trend"][0]["catalogue"] == pytest.approx(7.1 / 3.4)
    assert [t["ratio"] for t in data["cup_zone_terms"]] == [30.0, 100.0]
    assert all(t["extra_rad_per_Nmm"]["gci_fine"] >= 0.0 for t in data["cup_zone_terms"])
    assert "predicted / catalogue" in capsys.readouterr().out


def test_the_rules_scale_a_drive_by_similitude():
    """One set of rules, nothing per size: at a fixed ratio every predicted K goes as size^3 exactly."""
    r = MeshRules()
    a, b = r.design(14, 100), r.design(28, 100)
    assert b.geometry.module_mm == pytest.approx(2 * a.geometry.module_mm)
    assert b.geometry.teeth_flexspline == a.geometry.teeth_flexspline == 200
    assert ratio_of_label(">50") == 100.0 and ratio_of_label("160") == 160.0


@pytest.mark.parametrize("text, key", [
    ("size,ratio,T1_Nm\n14,30,2\n", "header"),
    (HEADER + "14,30,2,6.9,abc,2.4,3.4\n", "K1_e3"),
    (HEADER + "14,<30,2,6.9,1.9,2.4,3.4\n", "ratio"),
    (HEADER + "-14,30,2,6.9,1.9,2.4,3.4\n", "size"),
    (HEADER + "14,30,2,6.9\n", "line 2"),
    ("", "t.csv"),
])
def test_a_bad_table_exits_2_with_one_line(tmp_path, capsys, text, key):
    table = tmp_path / "t.csv"
    table.write_text(text)
    assert main(["catalogue", str(table)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err


def test_read_table_names_the_line():
    with pytest.raises(InputError, match="line 3"):
        read_table(HEADER + "14,30,2,6.9,1.9,2.4,3.4\n14,30,2,x,1.9,2.4,3.4\n")


@pytest.mark.parametrize("flags, key", [(["--accuracy-grade", "0.5"], "--accuracy-grade"),
                                        (["--accuracy-grade", "12"], "--accuracy-grade"),
                                        (["--accuracy-grade", "5", "--deviation-units", "0"], "--deviation-units")])
def test_bad_deviation_flags_exit_2_naming_the_flag(tmp_path, capsys, flags, key):
    table = tmp_path / "t.csv"
    table.write_text(HEADER + "14,>50,2,6.9,4.7,6.1,7.1\n")
    assert main(["catalogue", str(table), *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and key in err[0]


def test_the_accuracy_grade_reaches_the_rules(tmp_path, monkeypatch):
    from strainwave.analytic import catalogue_predict
    monkeypatch.setattr(catalogue_predict, "MeshRules", lambda: MeshRules(cup_zone_elements=None))
    table = tmp_path / "t.csv"
    table.write_text(HEADER + "14,>50,2,6.9,4.7,6.1,7.1\n")
    out = tmp_path / "o.json"
    assert main(["catalogue", str(table), "--accuracy-grade", "6", "--deviation-units", "3", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["design_rules"]["accuracy_grade"] == 6.0 and data["design_rules"]["deviation_units"] == 3
    assert "class 6 on both gears, each row the mean of 3 units" in data["tooth_deviations"]
