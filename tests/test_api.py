"""The Python face (issue 40): `import strainwave as sw` is instant, names a documented API lazily, and a GCI of
three identical meshes is refused, never reported as 0 %."""
from __future__ import annotations

import subprocess
import sys
from importlib.metadata import version

import pytest

import strainwave as sw
from conftest import STRAINWAVE
from strainwave.errors import InputError


def test_import_loads_no_heavy_library():
    code = ("import sys, strainwave as sw; sw.__all__; "
            "print(sorted(m for m in ('numpy', 'gmsh', 'pyvista', 'skfem', 'dask', 'build123d') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stdout + out.stderr


def test_every_public_name_is_documented_and_reachable():
    assert sw.__version__ == version("strainwave")
    expected = {"__version__", "load_params", "build_part", "export_part", "run_study", "validate", "diagnose", "sweep"}
    assert set(sw.__all__) == expected
    for name in expected - {"__version__"}:
        func = getattr(sw, name)
        assert callable(func) and func.__doc__ and len(func.__doc__) > 60, name
    assert set(sw.__all__) <= set(dir(sw))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        sw.nope  # noqa: B018


def test_load_params_takes_section_overrides(params):
    changed = sw.load_params(overrides={"gear": {"rated_output_torque_Nmm": 5e5}})
    assert changed.gear.rated_output_torque_Nmm == 5e5 != params.gear.rated_output_torque_Nmm
    with pytest.raises(InputError):
        sw.load_params(overrides={"gear": {"rated_output_torque_Nmm": -1.0}})


@pytest.mark.heavy
def test_three_identical_meshes_are_refused_not_a_zero_gci(params, tmp_path):
    # h = 30 mm on the shaft: its 45/70 mm walls cap gmsh's size, so all three meshes come out the same
    with pytest.raises(InputError, match="three meshes came out identical"):
        sw.run_study("shaft-torsion", params, mesh_size_mm=30.0, order=1)
    proc = subprocess.run([STRAINWAVE, "solve", "shaft-torsion", "--mesh-size-mm", "30", "--order", "1"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith("error: --mesh-size-mm = 30.0: shaft-torsion: the three")


def test_a_default_size_too_coarse_for_the_part_is_refined_not_reported_as_zero(tmp_path):
    # issue 40's README case: a 60 mm shaft with --quick; its walls cap gmsh's size, so the default's three
    # meshes came out the same and the GCI read "0 %, p = inf"
    short = tmp_path / "short.toml"
    short.write_text("[output_shaft]\nlength_mm = 60\ninner_diameter_mm = 40\n")
    said = []
    result = sw.run_study("shaft-torsion", sw.load_params(short), quick=True, progress=said.append)
    conv = result["flexibility_rad_per_Nmm"].convergence
    assert len(set(conv.values)) == 3 and conv.gci_fine > 0
    assert min(conv.h_mm) == pytest.approx(15.0 / 1.96)           # the quick default (wall = 15 mm) / 1.4^2
    assert any("came out identical" in line for line in said)
