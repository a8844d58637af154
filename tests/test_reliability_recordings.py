"""Recordings, fuzzed (issue 16 items 11-14, 18): every recording is parsed or refused with an InputError naming
file:line; an accepted one gives finite, valid JSON from the diagnosis."""
import json
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from strainwave.cli import main
from strainwave.compare.diagnose.pipeline import diagnose
from strainwave.compare.diagnose.recording import (MAX_ROWS, RecordingKind, format_recording, parse_bytes,
                                                   parse_text)
from strainwave.errors import InputError
from strainwave.params import load_params

_LOAD = np.linspace(0.0, 1000.0, 40)
_GOOD = format_recording(RecordingKind.TORSION, "output_shaft", _LOAD, _LOAD / 4.0e8 + 1e-10 * np.sin(np.arange(40)))
_LINES = _GOOD.splitlines()
_FIRST_ROW = next(i for i, ln in enumerate(_LINES) if not ln.startswith("#")) + 1

_HEADER_LINES = ["# baseline_stiffness_Nmm_per_rad = 1e-300", "# baseline_stiffness_Nmm_per_rad = 1" + "0" * 400,
                 "# baseline_uncertainty = 1e-300", "# [params.material]\n# youngs_modulus_MPa = 1" + "0" * 400,
                 "# [params.material]\n# youngs_modulus_MPa = 5e-324\n# shear_modulus_MPa = 5e-324",
                 "# [meta]\n# x = " + "[" * 3000 + "]" * 3000, "# [meta]\n# x = 1" + "0" * 5000, "#not toml"]
_CELLS = ["1_000", "5e-324", "1e304", "-1e304", "0", "1e-300", "nan", "1,5", "", '"7"', "1e308", "x"]


@st.composite
def _recording(draw) -> str:
    head, rows = list(_LINES[:_FIRST_ROW]), [ln.split(",") for ln in _LINES[_FIRST_ROW:]]
    for _ in range(draw(st.integers(0, 4))):   # cells anywhere in the data
        rows[draw(st.integers(0, len(rows) - 1))][draw(st.integers(0, 1))] = draw(st.sampled_from(_CELLS))
    if draw(st.booleans()):   # whole columns of tiny, huge or constant values
        scale, column = draw(st.sampled_from([5e-324, 1e-300, 1e300, 0.0])), draw(st.integers(0, 1))
        for i, row in enumerate(rows):
            row[column] = repr(scale * (i % 3 if column == 0 else 1))
    if draw(st.booleans()):   # a header line that broke the parser or the fit before
        head.insert(draw(st.integers(1, _FIRST_ROW - 1)), draw(st.sampled_from(_HEADER_LINES)))
    return "\n".join(head + [",".join(row) for row in rows]) + "\n"


@settings(max_examples=150, deadline=None)
@given(text=_recording())
def test_every_recording_is_parsed_or_refused_with_file_and_line(text):
    try:
        rec = parse_text(text, "fuzz.csv")
    except InputError as exc:
        assert str(exc.key).startswith("fuzz.csv:")
        return
    assert np.all(np.isfinite(rec.load)) and np.all(np.isfinite(rec.response))


@pytest.mark.parametrize("twist", [np.zeros(40), np.full(40, 3e-7), _LOAD / 4.0e8])
def test_accepted_odd_recordings_give_finite_json(twist):
    """Item 11: a constant or all-zero twist column wrote Infinity into --json."""
    rec = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", _LOAD, twist), "odd.csv")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            diagnosis, _ = diagnose(rec, load_params())
        except InputError as exc:     # a twist that does not follow the load: refused naming the header key
            assert str(exc.key).startswith("odd.csv: [test] baseline_stiffness") and str(exc).count("\n") == 0
            return
    json.dumps(diagnosis.to_dict(), allow_nan=False, default=str)


@pytest.mark.parametrize("insert,line,needle", [
    ("# baseline_uncertainty = 1e-300", 4, "baseline_uncertainty"),                  # item 12
    ("# baseline_stiffness_Nmm_per_rad = 1" + "0" * 400, 4, "400 digits"),
    ("# [params.material]\n# youngs_modulus_MPa = -5.0", 5, "[params.material].youngs_modulus_MPa"),   # item 13
    ("# description = \"x\"\n#not toml here", 5, "not valid TOML"),
    ("# [meta]\n# x = " + "[" * 3000 + "]" * 3000, 1, "nested too deeply"),
])
def test_header_defects_name_their_own_line(insert, line, needle):
    lines = _GOOD.splitlines()
    lines.insert(3, insert)
    with pytest.raises(InputError) as err:
        parse_text("\n".join(lines) + "\n", "rec.csv")
    assert err.value.key == f"rec.csv:{line}" and needle in str(err.value)


def test_underscored_numbers_and_subnormal_rows_are_refused():
    lines = _GOOD.splitlines()
    lines[_FIRST_ROW + 2] = "1_000," + lines[_FIRST_ROW + 2].split(",")[1]
    with pytest.raises(InputError, match="every cell must be a number"):
        parse_text("\n".join(lines), "rec.csv")
    tiny = format_recording(RecordingKind.TORSION, "output_shaft", 5e-324 * (np.arange(40) % 3), np.full(40, 5e-324))
    with pytest.raises(InputError, match="full scale"):
        parse_text(tiny, "rec.csv")


def test_recording_size_is_bounded(tmp_path, capsys):
    """Items 14, 18: more rows than MAX_ROWS and /dev/zero are refused, not read into memory."""
    rows = "\n".join(f"{i % 1000},{i * 1e-9}" for i in range(MAX_ROWS + 1))
    with pytest.raises(InputError, match="data rows"):
        parse_bytes((_GOOD.split("torque_Nmm")[0] + "torque_Nmm,twist_rad\n" + rows).encode(), "big.csv")
    assert main(["diagnose", "/dev/zero"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
