"""A recording without a header, described by flags, and a report in the recording's own units."""
import json
import math
import subprocess

import numpy as np
import pytest

from strainwave.compare.diagnose.generators.cha import cha_rows
from strainwave.compare.diagnose.recording import RecordingKind, TestFlags, parse_text
from strainwave.compare.diagnose.units import Display
from strainwave.errors import InputError

ROW = cha_rows()[0]                        # CHA-14 ratio 30: K1 = 1.9e3 N m/rad, T1 = 2 N m, T2 = 6.9 N m
ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi    # by hand, not by the units library under test


def _rows(n: int = 300) -> tuple[np.ndarray, np.ndarray]:
    amplitude = 1.5 * ROW.T2_Nmm
    T = np.interp(np.linspace(0.0, 5.0, n), np.arange(6), [0.0, 1.0, -1.0, 1.0, -1.0, 0.0]) * amplitude
    return T, ROW.twist_rad(T) + 2e-6 * np.random.default_rng(3).standard_normal(n)


def _headerless(n: int = 300) -> str:
    T, phi = _rows(n)
    return "Torque [Nm];Angle [arcmin]\n" + "\n".join(f"{t / 1e3:.6f};{p * ARCMIN_PER_RAD:.6f}"
                                                      for t, p in zip(T, phi)) + "\n"


def test_flags_describe_a_recording_without_a_header():
    rec = parse_text(_headerless(), "cha.csv", TestFlags("torsion", "gear", "1.9e3 Nm/rad", "10.35 Nm"))
    assert (rec.kind, rec.specimen) == (RecordingKind.TORSION, "gear")
    assert rec.baseline_stiffness == pytest.approx(1.9e6) and rec.rated_torque == pytest.approx(10350.0)
    assert rec.units == {"torque_Nmm": "Nm", "twist_rad": "arcmin"}
    T, phi = _rows()
    np.testing.assert_allclose(rec.load, T, atol=1e-3)
    np.testing.assert_allclose(rec.response, phi, atol=1e-6 / ARCMIN_PER_RAD)


def test_flags_override_the_header_and_bare_numbers_are_canonical():
    T, phi = _rows(40)
    text = ('# [test]\n# kind = "torsion"\n# specimen = "output_shaft"\ntorque_Nmm,twist_rad\n'
            + "\n".join(f"{t:.9g},{p:.9g}" for t, p in zip(T, phi)) + "\n")
    rec = parse_text(text, "r.csv", TestFlags(specimen="gear", stiffness="1.9e6", rated_torque="7800"))
    assert rec.specimen == "gear" and rec.baseline_stiffness == 1.9e6 and rec.rated_torque == 7800.0
    assert parse_text(text, "r.csv").specimen == "output_shaft"


def test_no_header_and_no_flags_names_the_flags():
    with pytest.raises(InputError, match="--kind"):
        parse_text(_headerless(40), "cha.csv")
    with pytest.raises(InputError, match="--specimen"):
        parse_text(_headerless(40), "cha.csv", TestFlags(kind="torsion"))


@pytest.mark.parametrize("flags, key", [
    (TestFlags("bending", "gear"), "--kind"),
    (TestFlags("torsion", "ewg_ring"), "--specimen"),
    (TestFlags("torsion", "gear", stiffness="fast"), "--stiffness"),
    (TestFlags("torsion", "gear", stiffness="-5 Nm/rad"), "--stiffness"),
    (TestFlags("torsion", "gear", stiffness="5 N/mm"), "--stiffness"),
    (TestFlags("torsion", "gear", rated_torque="7 furlongs"), "--rated-torque"),
    (TestFlags("ring_compression", "ewg_ring", rated_torque="7 Nm"), "--rated-torque"),
])
def test_bad_flag_values_are_refused_naming_the_flag(flags, key):
    with pytest.raises(InputError) as err:
        parse_text(_headerless(40), "cha.csv", flags)
    assert err.value.key == key


def test_the_display_speaks_the_recordings_units():
    shown = Display.of({"torque_Nmm": "Nm", "twist_rad": "arcmin", "time_s": ""})
    k, unit = shown.convert(ROW.K1_Nmm_per_rad, "N*mm/rad")
    assert unit == "Nm/arcmin" and k == pytest.approx(ROW.K1_Nmm_per_rad / 1e3 / ARCMIN_PER_RAD, rel=1e-12)
    assert shown.convert(2.0e-3, "rad") == (pytest.approx(2.0e-3 * ARCMIN_PER_RAD, rel=1e-12), "arcmin")
    assert shown.convert(6900.0, "N*mm") == (pytest.approx(6.9, rel=1e-12), "Nm")
    assert shown.convert(12.5, "%") == (12.5, "%")
    assert Display.of({"torque_Nmm": "", "twist_rad": ""}).convert(2.0, "rad") == (2.0, "rad")


def test_cli_headerless_recording_reports_in_its_own_units(strainwave_cmd, tmp_path):
    rec = tmp_path / "cha.csv"
    rec.write_text(_headerless(160))
    out = subprocess.run([*strainwave_cmd, "diagnose", str(rec), "--kind", "torsion", "--specimen", "gear",
                          "--stiffness", "1.9e3 Nm/rad", "--rated-torque", "10.35 Nm", "--json", "-"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert report["units"] == {"torque": "Nm", "angle": "arcmin"}
    values = report["catalogue"]["values"]
    for key, truth in (("K1", ROW.K1_Nmm_per_rad), ("K2", ROW.K2_Nmm_per_rad), ("K3", ROW.K3_Nmm_per_rad)):
        assert values[key]["unit"] == "Nm/arcmin"
        assert values[key]["value"] == pytest.approx(truth / 1e3 / ARCMIN_PER_RAD, rel=0.02)
    assert values["T1"]["unit"] == "Nm" and values["T1"]["value"] == pytest.approx(2.0, rel=0.05)
    assert values["lost_motion_arcmin"]["value"] == pytest.approx(2 * 0.04 * 10350.0 / ROW.K1_Nmm_per_rad
                                                                  * ARCMIN_PER_RAD, rel=0.05)


def test_cli_bad_flag_exits_2_in_one_line_and_writes_nothing(strainwave_cmd, tmp_path):
    rec = tmp_path / "cha.csv"
    rec.write_text(_headerless(40))
    out = subprocess.run([*strainwave_cmd, "diagnose", str(rec), "--kind", "torsion", "--specimen", "gear",
                          "--rated-torque", "7 furlongs", "--json", str(tmp_path / "d.json")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 2 and "--rated-torque" in out.stderr and "furlongs" in out.stderr
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert list(tmp_path.iterdir()) == [rec]
