"""Parameter files, fuzzed (issue 16 items 1-5, 9, 10): every file is accepted or refused with InputError, and
every accepted file gives finite, valid JSON from every closed form. Hypothesis draws the keys from the
schema and the values from the ones that broke the loader before plus random in-range numbers."""
import json
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.analytic.summary import analytic_summary
from strainwave.cli import main
from strainwave.errors import InputError
from strainwave.params import MAX_PARAMS_BYTES, default_dict, load_params
from strainwave.params_bounds import BOUNDS

_SCHEMA = default_dict()
_KEYS = [(s, k) for s, table in _SCHEMA.items() for k in table]

# TOML value texts that crashed the loader or the closed forms before (issue 16 reproducers).
_NASTY = ["1" + "0" * 400, "1" + "0" * 4400, "[" * 2000 + "]" * 2000, "1e-300", "5e-324", "1e-320", "1e300",
          "4.9e-324", "-1.0", "0", "inf", "nan", "true", '"x"', "[1.0, 2.0]", "{a = 1}", "9" * 30, "1e13"]


def _in_range(key: str, fraction: float) -> str:
    bound = BOUNDS[key]
    value = bound.lo + fraction * (bound.hi - bound.lo)
    text = repr(int(round(value))) if isinstance(bound.lo, int) and isinstance(bound.hi, int) else repr(float(value))
    return f"[{text}, {text}]" if key.endswith("contact_semi_axes_mm") else text


@st.composite
def _param_file(draw) -> str:
    entries: dict[str, dict[str, str]] = {}
    for _ in range(draw(st.integers(1, 3))):
        section, key = draw(st.sampled_from(_KEYS))
        dotted = f"{section}.{key}"
        if dotted in BOUNDS and draw(st.booleans()):
            # ends of each range and a log-spread interior: the corners are where the closed forms overflowed
            value = _in_range(dotted, draw(st.sampled_from([0.0, 1.0]) | st.floats(0.0, 1.0)))
        else:
            value = draw(st.sampled_from(_NASTY))
        entries.setdefault(section, {})[key] = value
    return "".join(f"[{s}]\n" + "".join(f"{k} = {v}\n" for k, v in t.items()) for s, t in entries.items())


@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=_param_file())
def test_every_parameter_file_is_accepted_with_finite_json_or_refused_with_input_error(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("p") / "params.toml"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            summary = analytic_summary(load_params(path))
        except InputError:
            return
    json.dumps(summary, allow_nan=False, default=str)   # NaN/Infinity are not JSON: raises ValueError


def test_every_numeric_key_has_a_stated_range():
    numeric = {f"{s}.{k}" for s, table in _SCHEMA.items() for k, v in table.items()
               if isinstance(v, (int, float, list)) and not isinstance(v, bool)}
    assert numeric - set(BOUNDS) == set()
    assert all(b.why for b in BOUNDS.values())
    # the shipped files lie inside every range
    load_params()


@pytest.mark.parametrize("body,key", [
    ("[material]\nyoungs_modulus_MPa = 1" + "0" * 400 + "\n", "material.youngs_modulus_MPa"),   # item 1
    ("[nosuch]\nx = 1" + "0" * 4400 + "\n", "params.toml"),                                      # item 2
    ("[material]\nx = " + "[" * 2000 + "]" * 2000 + "\n", "params.toml"),                        # item 3
    ("[material]\nfatigue_limit_MPa = 1e-300\n", "material.fatigue_limit_MPa"),                   # item 4
    ("[gear]\noutput_torque_Nmm = 5e-324\n", "gear.output_torque_Nmm"),
    ("[ewg_drive]\nflexspline_teeth = 1e300\n", "ewg_drive.flexspline_teeth"),
    ("[ewg_drive]\nface_width_mm = 1e-320\n", "ewg_drive.face_width_mm"),                         # item 5
])
def test_reproducers_exit_2_in_one_line_naming_the_key(tmp_path, capsys, body, key):
    path = tmp_path / "params.toml"
    path.write_text(body)
    assert main(["analytic", "--params", str(path), "--json"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: ") and key in err   # item 9: no warning first


def test_a_huge_value_is_echoed_clipped(tmp_path, capsys):
    """Item 10: a 1 MB string value gives a short line, not a million characters."""
    path = tmp_path / "params.toml"
    path.write_text('[ewg_drive]\ngenerator = "' + "x" * 1_000_000 + '"\n')
    assert main(["analytic", "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < 1000 and "1000002 characters" in err


def test_parameter_input_size_is_bounded(capsys, tmp_path):
    """Item 18: an endless device is refused without being read (issue 38: regular files only), and a
    regular file over the limit by its size."""
    assert main(["analytic", "--params", "/dev/zero"]) == 2
    err = capsys.readouterr().err
    assert "not a regular file" in err and err.count("\n") == 1
    big = tmp_path / "big.toml"
    with open(big, "wb") as stream:   # sparse: no disk used
        stream.truncate(MAX_PARAMS_BYTES + 1)
    assert main(["analytic", "--params", str(big)]) == 2
    err = capsys.readouterr().err
    assert f"{MAX_PARAMS_BYTES // 1024} KiB" in err and err.count("\n") == 1
