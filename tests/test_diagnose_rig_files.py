"""A test-rig engineer's export files, as rig software and spreadsheets write them: each is diagnosed, or refused
with exit status 2 and one line naming file:line, the value and what is allowed, nothing written.

Every accepted file is written here from one physical model, a linear torsion spring of stated stiffness K with
white noise on its twist, so the right answer is known: the numbers read back are the model's, and the diagnosis
"agrees" with K (and does not with K stated 20 % off)."""
import json
import math

import numpy as np
import pytest

from strainwave.cli import main
from strainwave.compare.diagnose import recording as recording_module
from strainwave.compare.diagnose.recording import MAX_BYTES, TestFlags, parse_bytes

K_NM_PER_RAD = 1.9e3                       # the spring's stiffness, stated with --stiffness
AMPLITUDE_NM = 50.0
NOISE_RAD = 2e-6
N = 240
DEG = 180.0 / math.pi                      # by hand, not by the units library under test
FLAGS = ["--kind", "torsion", "--specimen", "output_shaft", "--stiffness", f"{K_NM_PER_RAD} Nm/rad"]


def _spring(n: int = N, seed: int = 5):
    """Time (s), torque (N m) in two triangle cycles of +/-50 N m, twist (rad) = T/K + white noise."""
    t = 0.05 * np.arange(n)
    T = np.interp(np.linspace(0.0, 4.0, n), np.arange(5), [0.0, 1.0, -1.0, 1.0, 0.0]) * AMPLITUDE_NM
    return t, T, T / K_NM_PER_RAD + NOISE_RAD * np.random.default_rng(seed).standard_normal(n)


def _euro(x: float, digits: int = 6, grouped: bool = False) -> str:
    """A number as a German spreadsheet writes it: decimal comma, optionally thousands grouped by points."""
    text = f"{x:,.{digits}f}" if grouped else f"{x:.{digits}f}"
    return text.replace(",", "_").replace(".", ",").replace("_", ".")


def _table(header: str, cells, sep: str, end: str = "\n", trail: str = "") -> str:
    return header + end + end.join(sep.join(row) + trail for row in zip(*cells)) + end


def _files() -> dict:
    """name -> (bytes, extra CLI args); each holds the spring of _spring()."""
    t, T, phi = _spring()
    f = lambda xs, d=6: [f"{x:.{d}f}" for x in xs]   # noqa: E731
    e = lambda xs, d=6, g=False: [_euro(x, d, g) for x in xs]   # noqa: E731
    preamble = "Date: 2026-11-28\nOperator: J. Smith\nSpecimen: CHA-14 #3\nSample rate: 20 Hz\n\n"
    files = {
        # German Excel: ';' and decimal commas, Windows-1252 degree sign, CRLF, a metadata preamble 'key;value'
        "excel-de": (_table("Datum;28.11.2026\r\nPrüfer;Müller\r\nZeit [s];Drehmoment [Nm];Winkel [°]",
                            [e(t, 3), e(T, 4), e(phi * DEG, 7)], ";", "\r\n").encode("cp1252"), []),
        # thousands separators in N mm, seconds of arc after a Latin-1 micro/dot unit: N·mm, '"'
        "thousands": (_table("Torque [N·mm];Angle [\"]", [e(T * 1e3, 2, True), e(phi * DEG * 3600, 4)], ";")
                      .encode("cp1252"), []),
        # a spreadsheet's "Unicode text": UTF-16 with BOM, tabs, units in parentheses, a preamble
        "unicode-text": (_table("Test\tstiffness\r\nTime (s)\tTorque (Nm)\tAngle (mrad)",
                                [f(t, 3), f(T, 4), f(phi * 1e3, 7)], "\t", "\r\n").encode("utf-16"), []),
        # a DAQ's text export: runs of spaces, DIN 1313 'Torque / kNm', time first, an extra channel
        "whitespace": (_table("Time / s    Torque / kNm    Angle / urad    Input speed / rpm",
                              [f(t, 3), f(T / 1e3, 7), f(phi * 1e6, 3), f(0 * t + 1.5, 1)], "   "
                              ).encode(), []),
        # UTF-8 BOM, CRLF, quoted cells, a trailing separator on every row, N*m and minutes of arc as '
        "quoted-bom": (b"\xef\xbb\xbf" + _table('"Torque [N*m]";"Angle [\']";',
                                                [[f'"{c}"' for c in e(T, 4)], [f'"{c}"' for c in e(phi * DEG * 60, 5)]],
                                                ";", "\r\n", ";").encode(), []),
        # comments, blank lines, a key: value preamble, angle before torque, temperature and speed channels
        "rig-software": ((preamble + "# channels follow\nTemperature [°C],Angle [arcmin],Speed [rpm],Torque [N.m]\n\n"
                          + "\n".join(f"{21.5 + 0.001 * i:.3f},{a:.5f},1.5,{x:.4f}" + ("\n# marker" if i == 100 else "")
                                      for i, (a, x) in enumerate(zip(phi * DEG * 60, T))) + "\n").encode(), []),
        # names the tool does not know, units the column row does not give: --columns maps them by position
        "mapped": (_table("Kanal 1,Kanal 2,Kanal 3", [f(t, 3), f(T, 4), f(phi * DEG, 7)], ",").encode(),
                   ["--columns", "time=1:s,torque=2:Nm,twist=3:deg"]),
        # no column row at all
        "no-column-row": (_table("", [f(T, 4), f(phi * DEG, 7)], ",").lstrip("\n").encode(),
                          ["--columns", "torque=1:Nm,twist=2:deg"]),
    }
    return files


FILES = _files()


def _flags(extra: list[str]) -> TestFlags:
    columns = extra[extra.index("--columns") + 1] if "--columns" in extra else None
    return TestFlags("torsion", "output_shaft", f"{K_NM_PER_RAD} Nm/rad", columns=columns)


@pytest.mark.parametrize("name", sorted(FILES))
def test_rig_exports_read_back_the_springs_numbers(name):
    raw, extra = FILES[name]
    rec = parse_bytes(raw, f"{name}.csv", _flags(extra))
    t, T, phi = _spring()
    assert rec.n == N
    np.testing.assert_allclose(rec.load, T * 1e3, atol=0.06)             # N*mm; 4 decimals of N m or 2 of N mm
    np.testing.assert_allclose(rec.response, phi, atol=2e-9)             # rad; below the noise by 1000x
    if "Zeit" in raw.decode("cp1252", "replace") or name in ("unicode-text", "whitespace", "mapped"):
        np.testing.assert_allclose(rec.time_s, t, atol=1e-9)


def test_a_misread_file_does_not_pass_the_readback():
    """The read-back check can fail: the German file read with a point as its decimal mark is refused, and the
    same numbers in the wrong unit do not match the spring."""
    raw, _ = FILES["excel-de"]
    with pytest.raises(recording_module.InputError):
        parse_bytes(raw.replace(b";", b","), "misread.csv", _flags([]))
    wrong = parse_bytes(raw.replace("[°]".encode("cp1252"), b"[rad]"), "wrong.csv", _flags([]))
    assert not np.allclose(wrong.response, _spring()[2], atol=2e-9)


def _diagnose(tmp_path, capsys, raw: bytes, args: list[str]) -> tuple[int, str, dict | None]:
    path = tmp_path / "rec.csv"
    path.write_bytes(raw)
    out = tmp_path / "out.json"
    status = main(["diagnose", str(path), *args, "--json", str(out)])
    err = capsys.readouterr().err
    return status, err, json.loads(out.read_text()) if out.exists() else None


def _duplicated() -> bytes:
    """Every row written twice, as a rig logging faster than its sensors update does."""
    head, *rows = _good_text().rstrip("\n").split("\n")
    return ("\n".join([head] + [r for r in rows for _ in (0, 1)]) + "\n").encode()


@pytest.mark.parametrize("name", ["excel-de", "whitespace", "duplicated"])
def test_the_spring_agrees_with_its_stated_stiffness(tmp_path, capsys, name):
    raw, extra = FILES[name] if name in FILES else (_duplicated(), [])
    status, err, result = _diagnose(tmp_path, capsys, raw, FLAGS + extra)
    assert status == 0, err
    assert result["verdict"] == "agrees"


def test_the_spring_stated_20_percent_stiffer_does_not_agree(tmp_path, capsys):
    raw, extra = FILES["excel-de"]
    flags = FLAGS[:-1] + [f"{1.2 * K_NM_PER_RAD} Nm/rad"]
    status, err, result = _diagnose(tmp_path, capsys, raw, flags + extra)
    assert status == 0, err
    assert result["verdict"] != "agrees"


def _good_text() -> str:
    t, T, phi = _spring()
    return _table("Torque [Nm],Angle [deg]", [[f"{x:.4f}" for x in T], [f"{a:.7f}" for a in phi * DEG]], ",")


def _with_row(row: str, at: int = 5) -> bytes:
    lines = _good_text().split("\n")
    lines[at] = row
    return "\n".join(lines).encode()


BAD = {   # name -> (bytes, extra args, the error's key, a phrase of what is allowed)
    "unitless": (_good_text().replace("Torque [Nm],Angle [deg]", "Torque,Angle").encode(), [], "rec.csv:1",
                 "--columns torque=N:<unit>"),
    "unknown-unit": (_good_text().replace("[Nm]", "[lbf ft]").encode(), [], "rec.csv:1", "allowed: N m, Nm"),
    "unknown-angle-unit": (_good_text().replace("Angle [deg]", "Angle [deg],Input angle [degree]")
                           .replace("\n", ",0.5\n").replace("[degree],0.5", "[degree]").encode(), [], "rec.csv:1",
                           "'degree': unknown unit for 'Input angle'; allowed: rad"),
    "unknown-names": (_good_text().replace("Torque [Nm],Angle [deg]", "Kanal 1,Kanal 2").encode(), [], "rec.csv:1",
                      "--columns torque=N:<unit>"),
    "nan": (_with_row("NaN,0.1"), [], "rec.csv:6", "NaN or infinite"),
    "empty-cell": (_with_row("12.5,"), [], "rec.csv:6", "no value in column 2 (twist_rad)"),
    "too-few-fields": (_with_row("12.5"), [], "rec.csv:6", "no value in column 2"),
    "too-many-fields": (_with_row("12.5,0.1,7"), [], "rec.csv:6", "expected 2 cells"),
    "text": (_with_row("OVERLOAD,0.1"), [], "rec.csv:6", "every cell must be a number"),
    "header-only": (b"Torque [Nm],Angle [deg]\n", [], "rec.csv:2", "at least 20 rows"),
    "one-row": (b"Torque [Nm],Angle [deg]\n1.0,0.001\n", [], "rec.csv:3", "at least 20 rows"),
    "empty": (b"", [], "rec.csv:1", "expected a CSV header row"),
    "binary": (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)), [], "rec.csv:1", "text file"),
    "no-column-row": (_good_text().split("\n", 1)[1].encode(), [], "rec.csv:1", "or --columns"),
    "columns-malformed": (_good_text().encode(), ["--columns", "torque=first"], "--columns", "1-based column"),
    "columns-no-unit": (_good_text().replace("Torque [Nm]", "Torque").encode(), ["--columns", "torque=1,twist=2"],
                        "--columns", "give it: torque=1:<unit>"),
    "columns-bad-unit": (_good_text().encode(), ["--columns", "torque=1:ft,twist=2"], "--columns", "allowed: N m"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_rig_files_exit_2_in_one_line_and_write_nothing(tmp_path, capsys, name):
    raw, extra, key, allowed = BAD[name]
    status, err, result = _diagnose(tmp_path, capsys, raw, FLAGS + extra)
    assert status == 2 and result is None
    assert err.count("\n") == 1 and "Traceback" not in err and "internal error" not in err
    assert f"{key} = " in err and allowed in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec.csv"]


@pytest.mark.parametrize("target", ["directory", "missing"])
def test_a_directory_or_a_missing_file_exits_2(tmp_path, capsys, target):
    path = tmp_path / ("folder" if target == "directory" else "absent.csv")
    if target == "directory":
        path.mkdir()
    assert main(["diagnose", str(path), *FLAGS]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err


def test_a_file_beyond_the_size_limit_is_refused_before_it_is_read(tmp_path, capsys):
    """A million-row export (about 25 bytes a row) is read and refused at row MAX_ROWS + 1; one beyond MAX_BYTES is
    refused from its size alone (a sparse file: nothing is written to disk here)."""
    big = tmp_path / "big.csv"
    with open(big, "wb") as fh:
        fh.truncate(MAX_BYTES + 1)
    assert main(["diagnose", str(big), *FLAGS]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "KiB" in err


def test_rows_beyond_the_row_limit_are_refused_at_their_line(monkeypatch):
    monkeypatch.setattr(recording_module, "MAX_ROWS", 100)
    with pytest.raises(recording_module.InputError) as err:
        parse_bytes(_good_text().encode(), "long.csv", _flags([]))
    assert err.value.key == "long.csv:102" and "decimate" in err.value.allowed


def test_a_ring_export_in_german_with_a_latin1_micro_sign():
    """A ring compressed to 1 kN, deflection F/k with k = 2e4 N/mm, written as 'Kraft [kN];Weg [µm]' in
    Windows-1252 with decimal commas; and the same file read in mm instead of µm does not match."""
    F_N = np.linspace(0.0, 1000.0, 30)
    delta_mm = F_N / 2e4
    ring = TestFlags("ring_compression", "ewg_ring")
    text = _table("Kraft [kN];Weg [µm]", [[_euro(f / 1e3, 5) for f in F_N], [_euro(d * 1e3, 4) for d in delta_mm]],
                  ";")
    rec = parse_bytes(text.encode("cp1252"), "ring.csv", ring)
    np.testing.assert_allclose(rec.load, F_N, atol=5e-3)
    np.testing.assert_allclose(rec.response, delta_mm, atol=5e-8)
    assert rec.units == {"force_N": "kN", "delta_cd_mm": "µm"}
    wrong = parse_bytes(text.replace("[µm]", "[mm]").encode("cp1252"), "ring.csv", ring)
    assert not np.allclose(wrong.response, delta_mm, atol=5e-8)
