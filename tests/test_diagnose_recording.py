"""Recording parser: the documented format, spreadsheet quirks, and every defect named by file:line."""
import json
import subprocess

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_bytes, parse_text
from strainwave.errors import InputError

HEAD = '# [test]\n# kind = "torsion"\n# specimen = "output_shaft"\n'


def _rows(n=30):
    T = np.linspace(-1e6, 1e6, n)
    return "\n".join(f"{t:.6g},{t * 1.2e-9:.6g}" for t in T)


def _good(n=30):
    return HEAD + "torque_Nmm,twist_rad\n" + _rows(n) + "\n"


def _key(text, name="rec.csv"):
    with pytest.raises(InputError) as err:
        parse_text(text, name)
    return err.value.key


def test_round_trip_of_the_writer():
    T = np.linspace(0.0, 100.0, 25)
    text = format_recording(RecordingKind.RING_COMPRESSION, "ewg_ring", T, 0.05 * T, baseline_uncertainty=0.05,
                            params={"ewg_drive": {"rim_thickness_ratio": 0.2}})
    rec = parse_text(text)
    assert rec.kind is RecordingKind.RING_COMPRESSION and rec.n == 25
    assert rec.param_overrides == {"ewg_drive": {"rim_thickness_ratio": 0.2}}
    assert rec.baseline_uncertainty == 0.05
    np.testing.assert_allclose(rec.response, 0.05 * T, rtol=1e-8)   # 9 significant digits written


def test_spreadsheet_export_is_accepted():
    text = _good().replace("\n", ",\r\n")           # CRLF and a trailing comma on every line
    raw = b"\xef\xbb\xbf" + text.encode()
    rec = parse_bytes(raw, "excel.csv")
    assert rec.n == 30 and rec.load_name == "torque_Nmm"


@pytest.mark.parametrize("mutate, line", [
    (lambda t: t.replace("torque_Nmm,twist_rad", "torque_Nmm,angle_rad"), 4),     # unknown column
    (lambda t: t.replace("torque_Nmm,twist_rad", "torque_Nmm"), 4),               # missing column
    (lambda t: t.replace(_rows().split("\n")[12], "1.0,abc"), 17),                # non-numeric cell
    (lambda t: t.replace(_rows().split("\n")[5], "nan,1.0"), 10),                 # NaN
    (lambda t: t.replace(_rows().split("\n")[7], "1.0,2.0,3.0"), 12),             # too many cells
    (lambda t: t.replace('"torsion"', '"bending"'), 2),                            # unknown kind
    (lambda t: t.replace('"output_shaft"', '"ewg_ring"'), 3),                      # specimen of another kind
    (lambda t: t.replace('# specimen = "output_shaft"', "# specimen = output_shaft"), 3),  # not TOML
    (lambda t: t.replace("# [test]", "# [tset]"), 1),                              # unknown table
])
def test_defects_name_the_line(mutate, line):
    assert _key(mutate(_good())) == f"rec.csv:{line}"


def test_too_few_rows_and_binary_and_missing_header():
    assert _key(HEAD + "torque_Nmm,twist_rad\n" + _rows(19) + "\n").startswith("rec.csv:")
    with pytest.raises(InputError, match="binary"):
        parse_bytes(b"\x00\x01\x02PK\x03", "x.csv")
    assert _key("torque_Nmm,twist_rad\n" + _rows()) == "rec.csv:1"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(min_value=0, max_value=29), st.text(min_size=1, max_size=20))
def test_random_garbage_line_is_refused_at_its_line(row, garbage):
    """Replacing any data row by garbage either still parses as two numbers or names exactly that line."""
    lines = _good().split("\n")
    lines[4 + row] = garbage.replace("\n", " ").replace("\r", " ")
    text = "\n".join(lines)
    try:
        rec = parse_text(text, "g.csv")
    except InputError as exc:
        assert exc.key in (f"g.csv:{5 + row}", f"g.csv:{len(lines)}")   # the line, or "too few rows" at EOF
        return
    assert rec.n in (29, 30) and np.all(np.isfinite(rec.response))   # blank/comment lines are skipped


def _run(cmd, *args):
    return subprocess.run([*cmd, *args], capture_output=True, text=True, timeout=120)


def test_cli_bad_recording_exit_2_names_line_and_writes_nothing(strainwave_cmd, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text(_good().replace(_rows().split("\n")[12], "1.0,twelve"))
    out_json = tmp_path / "out.json"
    out = _run(strainwave_cmd, "diagnose", str(bad), "--json", str(out_json), "--plot", str(tmp_path / "p.png"))
    assert out.returncode == 2 and "bad.csv:17" in out.stderr and "Traceback" not in out.stderr
    assert out.stderr.count("\n") == 1
    assert list(tmp_path.iterdir()) == [bad]          # no half-written JSON or PNG, no temp files


def test_cli_unknown_kind_exit_2(strainwave_cmd, tmp_path):
    bad = tmp_path / "kind.csv"
    bad.write_text(_good().replace('"torsion"', '"shear"'))
    out = _run(strainwave_cmd, "diagnose", str(bad))
    assert out.returncode == 2 and "kind.csv:2" in out.stderr


def test_cli_good_recording_writes_json_with_stable_keys_and_png(strainwave_cmd, tmp_path):
    rng = np.random.default_rng(3)
    T = 1e6 * np.sin(np.linspace(0.0, 4.0 * np.pi, 400))
    from strainwave.compare.diagnose.baseline import torsion_compliance
    from strainwave.params import load_params
    c0, _ = torsion_compliance("output_shaft", load_params())
    # friction: a spring and a Coulomb slider (slip torque r) in series with the shaft; the twist lags the
    # torque and, stuck right after each reversal, still moves with it (passive, dissipative). The first
    # version jumped by 4e-4 c0 T_max at each reversal, the twist moving against the torque: a time lag
    r, slip = 5e4, np.zeros(400)
    for k in range(1, 400):
        slip[k] = min(max(slip[k - 1], T[k] - r), T[k] + r)
    twist = c0 * T + 4e-3 * c0 * (slip - T) + 1e-3 * c0 * 1e6 * rng.standard_normal(400) * 0.05
    rec = tmp_path / "r.csv"
    rec.write_text(format_recording(RecordingKind.TORSION, "output_shaft", T, twist))
    out = _run(strainwave_cmd, "diagnose", str(rec), "--json", str(tmp_path / "d.json"), "--plot",
               str(tmp_path / "d.png"))
    assert out.returncode == 0, out.stderr
    data = json.loads((tmp_path / "d.json").read_text())
    assert set(data) >= {"mismatch", "noise_std", "located", "effects", "fit", "explanation"}
    assert set(data["located"]) >= {"variable", "ranges", "branch", "description"}
    assert set(data["fit"]) >= {"rms_before", "rms_after", "bic_before", "bic_after"}
    assert data["mismatch"] is True and data["effects"][0]["id"].startswith("hysteresis")
    assert data["verdict"] == "explained" and data["named"] == ["hysteresis"] and data["ambiguous"] is False
    assert {"id", "parameters", "delta_bic"} <= set(data["effects"][0])
    assert (tmp_path / "d.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_fea_baseline_reads_the_ring_study_compliance(monkeypatch):
    """Wiring of --baseline fea: delta_cd_mm / reference_force_N of the study, GCI added to the uncertainty."""
    from strainwave.compare.diagnose import baseline as bl
    from strainwave.fea import studies
    from strainwave.fea.convergence import grid_convergence
    from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support
    from strainwave.params import load_params

    conv = grid_convergence([1.0, 1.5, 2.25], [2.0, 2.002, 2.0065])
    fake = StudyResult("ring-compression", {"delta_cd_mm": Quantity("delta_cd_mm", 2.0, "mm", conv)},
                       MeshQuality(1, 1, 1, 2, 1.0, 1.0), Load("diametral force F", 40.0, "N", ("contact",), "arcs"),
                       (Support(("A", "B"), "u_y = 0"),))
    monkeypatch.setattr(studies, "run_study", lambda study, params, **kw: fake)
    T = np.linspace(0.0, 30.0, 25)
    rec = parse_text(format_recording(RecordingKind.RING_COMPRESSION, "ewg_ring", T, 0.05 * T))
    b = bl.fea_baseline(rec, load_params())
    assert b.compliance == pytest.approx(0.05) and b.source.startswith("FEA ring-compression")
    assert b.uncertainty == pytest.approx(float(np.hypot(0.02, conv.gci_fine)))   # both relative


def test_fea_baseline_for_gear_is_refused():
    from strainwave.compare.diagnose.baseline import fea_baseline
    from strainwave.params import load_params
    rec = parse_text(_good().replace('"output_shaft"', '"gear"'))
    with pytest.raises(InputError, match="no FEA study models specimen 'gear'"):
        fea_baseline(rec, load_params())


def _locale(sep, decimal_comma, quote):
    T = np.linspace(-1e6, 1e6, 30)
    q = '"' if quote else ""
    head = sep.join(f"{q}{c}{q}" for c in ("torque_Nmm", "twist_rad", "input_angle_rad"))
    rows = []
    for i, t in enumerate(T):
        cells = [f"{t:.6g}", f"{t * 1.2e-9:.6g}", f"{0.25 * i:.4f}"]
        if decimal_comma:
            cells = [c.replace(".", ",") for c in cells]
        rows.append(sep.join(cells))
    return HEAD + head + "\n" + "\n".join(rows) + "\n", T


@pytest.mark.parametrize("sep, decimal_comma, quote", [(",", False, True), (";", True, True), (";", True, False),
                                                        ("\t", True, False), ("\t", False, True)],
                         ids=["comma-quoted", "semicolon-decimal-comma-quoted", "semicolon-decimal-comma",
                              "tab-decimal-comma", "tab-quoted"])
def test_spreadsheet_dialects_parse_to_the_same_numbers(sep, decimal_comma, quote):
    text, T = _locale(sep, decimal_comma, quote)
    rec = parse_text(text)
    np.testing.assert_allclose(rec.load, T, rtol=1e-5)          # 6 significant digits written
    np.testing.assert_allclose(rec.response, T * 1.2e-9, rtol=1e-5)
    np.testing.assert_allclose(rec.extra["input_angle_rad"], 0.25 * np.arange(30), atol=1e-9)


def test_semicolon_file_bad_cell_is_named_by_line():
    text, _ = _locale(";", True, True)
    lines = text.split("\n")
    lines[10] = lines[10].replace(";", ";zwölf;", 1).split(";zwölf;")[0] + ";zwölf;0,1"
    assert _key("\n".join(lines)) == "rec.csv:11"
    short = text.split("\n")
    short[12] = short[12].rsplit(";", 1)[0]           # a row with a cell missing
    assert _key("\n".join(short)) == "rec.csv:13"


def test_input_angle_is_torsion_only():
    text = ('# [test]\n# kind = "ring_compression"\n# specimen = "ewg_ring"\nforce_N,delta_cd_mm,input_angle_rad\n'
            + "\n".join(f"{f},{f * 1e-3},{f}" for f in range(30)) + "\n")
    assert _key(text) == "rec.csv:4"
