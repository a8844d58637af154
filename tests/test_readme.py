"""The README's examples are run, so they cannot drift from the code: the Python API block, the entry
points it lists, and the worked parameter file."""
import contextlib
import importlib
import io
import re
import tomllib
import warnings
from pathlib import Path

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")


def test_first_lines_are_the_two_commands():
    block = README.split("```sh", 1)[1].split("```", 1)[0]
    assert [line.split("#")[0].strip() for line in block.strip().splitlines()] == ["make validate", "make test"]


def test_api_example_runs():
    code = README.split("<!-- api-example", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    assert 3 <= len(code.strip().splitlines()) <= 5                 # "a five-line example"
    out = io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stdout(out):
        warnings.simplefilter("ignore")
        exec(compile(code, "README.md", "exec"), {})
    volume, faces = re.fullmatch(r"(\d+) mm\^3, faces: (.+)\n", out.getvalue()).groups()
    # a 60 mm hollow shaft, D 70, d 45, minus the crack slot: within 1 % of the tube
    tube = 3.141592653589793 / 4 * (70.0 ** 2 - 45.0 ** 2) * 60.0
    assert abs(int(volume) / tube - 1) < 0.01
    assert {"fixed", "loaded", "crack_face", "crack_front"} <= set(faces.split(", "))


def test_listed_entry_points_exist():
    listed = re.findall(r"^- `(strainwave(?:\.\w+)+)\.(\w+)\(", README, flags=re.M)
    assert {name for _, name in listed} == {"load_params", "build_part", "run_study", "run_validate", "diagnose_file",
                                          "diagnose"}
    for module, name in listed:
        assert callable(getattr(importlib.import_module(module), name)), (module, name)


def test_worked_parameter_file_loads():
    from strainwave.params import load_params

    toml = README.split("```toml", 1)[1].split("```", 1)[0]
    overrides = tomllib.loads(toml)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params(overrides=overrides)
    assert params.output_shaft.length_mm == 60.0 and params.output_shaft.inner_diameter_mm == 50.0


def test_every_readme_command_parses_and_names_files_that_ship():
    """Issue 52: each `strainwave ...` line of the Commands block is a valid command line as written, and the
    inputs it reads that no earlier line makes (the sample recording) ship with the repository."""
    import shlex

    from strainwave.cli import build_parser

    root = Path(__file__).resolve().parents[1]
    block = README.split("## Commands", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    commands = [shlex.split(line.split("#")[0]) for line in block.splitlines() if line.startswith("strainwave ")]
    assert len(commands) >= 10
    for argv in commands:
        args = build_parser().parse_args(argv[1:argv.index(">")] if ">" in argv else argv[1:])
        for name in ("recording", "table"):    # a sample recording, a stiffness table
            shipped = getattr(args, name, None)
            if shipped is not None:
                assert (root / shipped).is_file(), shipped
    assert any(getattr(build_parser().parse_args(a[1:]), "inp", None) for a in commands if ">" not in a)
