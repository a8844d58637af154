"""Every script of examples/ runs as a user runs it (cheap settings) and prints what it promises."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ENV = {**os.environ, "OMP_NUM_THREADS": "1"}


def _run(script: str, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), *args], capture_output=True, text=True,
                          timeout=600, cwd=cwd, env=ENV)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc


def test_examples_folder_holds_the_three_scripts():
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == ["diagnose_recording.py", "export_part.py",
                                                            "parametric_study.py"]


def test_parametric_study_matches_the_closed_form_and_its_trend(tmp_path):
    out = _run("parametric_study.py", "--diameters-mm", "70,80", "--mesh-size-mm", "15", cwd=tmp_path).stdout
    rows = [line.split() for line in out.splitlines() if re.match(r"\s+\d", line)]
    assert [float(r[0]) for r in rows] == [70.0, 80.0]
    fea = [float(r[1]) for r in rows]
    assert fea[1] < fea[0]                                   # a thicker shaft is stiffer
    assert all(abs(float(r[4])) < 1e-3 for r in rows)        # P2 against Saint-Venant


def test_diagnose_example_names_the_backlash(tmp_path):
    out = _run("diagnose_recording.py", str(tmp_path), cwd=tmp_path).stdout
    assert (tmp_path / "shaft_backlash.csv").is_file()
    # the verdict and the one effect it names, not merely the word somewhere in the text
    assert re.search(r"^\s+verdict: explained \(lost_motion\)$", out, re.M), out


@pytest.mark.heavy
def test_export_example_names_the_faces_in_gmsh(tmp_path):
    out = _run("export_part.py", str(tmp_path), cwd=tmp_path).stdout
    index = json.loads((tmp_path / "output-shaft.faces.json").read_text())
    assert index["unnamed"] == 0 and index["named"] == index["surfaces"] == 4
    for name in ("bore", "fixed", "loaded", "outer"):
        assert f"gmsh: physical surface '{name}'" in out
