"""Bad input on the command line or in a parameter file: exit 2 and one line, never a traceback or a hang."""
import subprocess

from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.cli import main
from strainwave.params import default_dict


def _run(strainwave_cmd, *args, timeout=60):
    return subprocess.run([*strainwave_cmd, *args], capture_output=True, text=True, timeout=timeout)


def test_help_everywhere(strainwave_cmd):
    for sub in ([], ["analytic"], ["export-step"], ["solve"], ["validate"], ["diagnose"], ["sweep"],
                ["benchmark-diagnose"]):
        out = _run(strainwave_cmd, *sub, "--help")
        assert out.returncode == 0 and "usage: strainwave" in out.stdout


def test_bad_flag_is_one_line_exit_2(strainwave_cmd):
    out = _run(strainwave_cmd, "solve", "shaft-torsion", "--mesh-size-mm", "-3")
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "--mesh-size-mm" in out.stderr and "Traceback" not in out.stderr


def test_malformed_toml_names_the_file(strainwave_cmd, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[output_shaft\nouter_diameter_mm = 3\n")
    out = _run(strainwave_cmd, "analytic", "--params", str(bad))
    assert out.returncode == 2 and "bad.toml" in out.stderr and "Traceback" not in out.stderr


def test_binary_file_is_refused(strainwave_cmd, tmp_path):
    bad = tmp_path / "bin.toml"
    bad.write_bytes(b"\xff\xfe\x00\x01garbage")
    out = _run(strainwave_cmd, "analytic", "--params", str(bad))
    assert out.returncode == 2 and "UTF-8" in out.stderr


_SCHEMA = default_dict()
_keys = st.sampled_from([(s, k) for s, table in _SCHEMA.items() for k in table])
_bad_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 0), st.text(max_size=8),
    st.booleans(), st.lists(st.floats(-5, 5), max_size=3), st.just(-1e-9), st.just(1e300))


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return {float("inf"): "inf", float("-inf"): "-inf"}.get(v, "nan" if v != v else repr(v))
    if isinstance(v, str):
        return '"' + v.encode("unicode_escape").decode().replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=_keys, value=_bad_values, junk=st.sampled_from(["", "[nosuch]\nx = 1\n", "[gear]\nnope = 2\n", "= =\n"]))
def test_random_bad_parameter_files_exit_2_with_one_line(tmp_path_factory, capsys, key, value, junk):
    section, name = key
    path = tmp_path_factory.mktemp("p") / "params.toml"
    path.write_text(f"{junk}[{section}]\n{name} = {_toml_value(value)}\n" if not junk.startswith("[gear]")
                    else f"[{section}]\n{name} = {_toml_value(value)}\n{junk}")
    status = main(["analytic", "--params", str(path), "--json"])
    captured = capsys.readouterr()
    errors = [line for line in captured.err.splitlines() if line.startswith("error:")]
    if status == 0:
        # Some random values are legal (e.g. a large positive length): then nothing may be printed as an error.
        assert not errors
    else:
        assert status == 2, captured.err
        assert len(errors) == 1 and "Traceback" not in captured.err
        assert "internal error" not in errors[0]
