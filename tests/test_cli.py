"""Bad input on the command line or in a parameter file: exit 2 and one line, never a traceback or a hang."""
import subprocess

from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.cli import main
from strainwave.params import default_dict


def _run(strainwave_cmd, *args, timeout=60):
    return subprocess.run([*strainwave_cmd, *args], capture_output=True, text=True, timeout=timeout)


def test_help_everywhere(strainwave_cmd):
    for sub in ([], ["analytic"], ["export-step"], ["solve"], ["validate"], ["diagnose"], ["sweep"],
                ["benchmark-diagnose"], ["compare"]):
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


# ---- conventions every subcommand shares (issue 14) ----------------------------------------------

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import tomllib  # noqa: E402
from importlib.metadata import version  # noqa: E402

import pytest  # noqa: E402

from strainwave.cli import build_parser  # noqa: E402

_MATERIAL_WARNING = "E/(2(1+nu))"


def _subparsers():
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


SUBCOMMANDS = sorted(_subparsers())


def test_version_and_python_dash_m(strainwave_cmd):
    want = f"strainwave {version('strainwave')}"
    script = _run(strainwave_cmd, "--version")
    module = subprocess.run([sys.executable, "-m", "strainwave", "--version"], capture_output=True, text=True,
                            timeout=60)
    assert script.returncode == 0 and script.stdout.strip() == want
    assert module.returncode == 0 and module.stdout.strip() == want
    bad = subprocess.run([sys.executable, "-m", "strainwave", "solve", "no-such-study"], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and bad.stderr.startswith("error:")


@settings(max_examples=40, deadline=None)
@given(sub=st.sampled_from(SUBCOMMANDS), flags=st.lists(st.sampled_from(["-q", "-v", "--debug"]), unique=True),
       after=st.lists(st.booleans(), min_size=3, max_size=3))
def test_common_flags_before_or_after_the_subcommand(sub, flags, after):
    if "-q" in flags and "-v" in flags:
        flags = [f for f in flags if f != "-v"]
    required = {"export-step": ["--part", "ewg", "-o", "x.step"], "solve": ["shaft-torsion"],
                "diagnose": ["r.csv"], "size-crack": ["r.csv"], "sweep": ["shaft-torsion"],
                "compare": ["run-a", "run-b"], "catalogue": ["t.csv"]}.get(sub, [])
    before = [f for f, a in zip(flags, after) if not a]
    behind = [f for f, a in zip(flags, after) if a]
    args = build_parser().parse_args([*before, sub, *required, *behind])
    assert args.command == sub
    assert args.quiet == ("-q" in flags) and args.verbose == ("-v" in flags) and args.debug == ("--debug" in flags)


@pytest.mark.parametrize("sub", SUBCOMMANDS)
def test_every_option_has_help_with_units_and_default(sub):
    parser = _subparsers()[sub]
    text = parser.format_help()
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        assert action.help and len(action.help) > 8, (sub, action.dest)
        if action.dest.endswith("_mm"):
            assert " mm" in action.help, (sub, action.dest)
        if action.option_strings and action.default not in (None, False, argparse.SUPPRESS, []):
            assert f"(default: {action.default}" in " ".join(text.split()), (sub, action.dest)
        # each default said once (issue 52: "(default: ...) (default: 5.21e-13)")
        assert parser._get_formatter()._expand_help(action).count("(default") <= 1, (sub, action.dest)
    if sub == "solve":
        assert "FINEST of the three meshes" in " ".join(text.split())


@pytest.mark.parametrize("sub", SUBCOMMANDS)
def test_json_means_the_same_everywhere(sub):
    json_action = next(a for a in _subparsers()[sub]._actions if "--json" in a.option_strings)
    assert (json_action.nargs, json_action.const, json_action.default) == ("?", "-", None)


def test_json_to_stdout_or_file(capsys, tmp_path):
    assert main(["analytic", "--json"]) == 0
    on_stdout = json.loads(capsys.readouterr().out)
    out = tmp_path / "a.json"
    assert main(["analytic", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert json.loads(out.read_text()) == on_stdout and "SEED 000" in printed   # text still printed


def test_export_step_json_lists_written_files(capsys, tmp_path):
    out = tmp_path / "s.step"
    assert main(["export-step", "--part", "wg-bearing-ring", "-o", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"written": [str(out), str(tmp_path / "s.faces.json")]}


@pytest.mark.parametrize("argv, shown", [
    (["analytic"], True), (["-q", "analytic"], False), (["analytic", "-q"], False), (["analytic", "-v"], True),
    (["params"], True)])
def test_material_warning_through_logging(capsys, argv, shown):
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert (_MATERIAL_WARNING in err) == shown
    if shown:
        assert f"warning: material: {_MATERIAL_WARNING}" in err


def test_material_warning_not_on_export_step(capsys, tmp_path):
    assert main(["export-step", "--part", "wg-bearing-ring", "-o", str(tmp_path / "r.step")]) == 0
    assert _MATERIAL_WARNING not in capsys.readouterr().err


def test_verbose_adds_debug_detail(capsys):
    assert main(["-v", "params"]) == 0
    assert f"strainwave {version('strainwave')}: -v params" in capsys.readouterr().err
    assert main(["params"]) == 0
    assert "strainwave 0" not in capsys.readouterr().err


def test_print_default_starts_a_parameter_file(capsys, tmp_path):
    assert main(["params", "--print-default"]) == 0
    text = capsys.readouterr().out
    assert tomllib.loads(text) == default_dict()
    assert "# " in text                                   # the comments (units, sources) come along
    start = tmp_path / "mine.toml"
    start.write_text(text.replace("output_torque_Nmm = 1000.0", "output_torque_Nmm = 2500.0"))
    assert main(["params", "--params", str(start), "--json"]) == 0
    effective = json.loads(capsys.readouterr().out)
    assert effective["gear"]["output_torque_Nmm"] == 2500.0
    assert effective["material"] == default_dict()["material"]

def test_crack_deeper_than_its_own_wall_is_refused_before_any_mesh(strainwave_cmd):
    """--crack-depth-mm sets the study's own crack (the shaft's, wall (70 - 45)/2 = 12.5 mm) and is checked
    by the parameter schema before the part is built: exit 2 naming the wall, no solver progress."""
    out = _run(strainwave_cmd, "solve", "shaft-torsion", "--crack-depth-mm", "20")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "--crack-depth-mm = 20.0" in out.stderr and "12.5 mm" in out.stderr   # named as given (issue 53)
    assert "refinement" not in out.stderr and "internal error" not in out.stderr


def test_crack_on_a_study_without_a_crack_is_refused(strainwave_cmd):
    out = _run(strainwave_cmd, "solve", "ring-compression", "--crack-depth-mm", "1")
    assert out.returncode == 2 and "--crack-depth-mm" in out.stderr and "carries no crack" in out.stderr


def test_export_step_help_says_what_assembly_writes_and_cracks():
    text = " ".join(_subparsers()["export-step"].format_help().split())
    assert "FILE-ewg-drive.step" in text and "EWG drive" in text
    assert "--part assembly cracks the output shaft" in text and "circular spline" in text
