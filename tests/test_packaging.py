"""The package builds as pip builds it (isolated setuptools from pyproject.toml) without warnings, and the
wheel holds every module and data file the sources have: strainwave.data is declared, not guessed."""
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = {"strainwave": "strainwave", "geometry": "strainwave/geometry", "fea": "strainwave/fea",
           "analytic": "strainwave/analytic", "compare": "strainwave/compare"}


@pytest.mark.heavy
def test_wheel_builds_without_warnings_and_ships_data(tmp_path):
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    for name in SOURCES:
        shutil.copytree(ROOT / name, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(tmp_path / "dist"), str(src)],
                         capture_output=True, text=True, timeout=300)
    output = run.stdout + run.stderr
    assert run.returncode == 0, output
    assert "BuildBackendWarning" not in output and "absent from the `packages`" not in output, output
    assert "SetuptoolsDeprecationWarning" not in output, output
    (wheel,) = (tmp_path / "dist").glob("strainwave-*.whl")
    shipped = set(zipfile.ZipFile(wheel).namelist())
    expected = {f"{SOURCES[top]}/{path.relative_to(ROOT / top)}"
                for top in SOURCES for path in (ROOT / top).rglob("*")
                if path.is_file() and path.suffix in (".py", ".toml", ".csv", ".json", ".js") and "__pycache__" not in path.parts}
    assert {"strainwave/data/defaults.toml", "strainwave/data/cha_torsional_stiffness.csv",
            "strainwave/compare/validate/view3d.js"} <= expected
    assert expected - shipped == set()
