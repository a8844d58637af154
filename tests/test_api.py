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


def test_three_identical_meshes_are_refused_not_a_zero_gci(params, tmp_path):
    # h = 30 mm on the shaft: its 45/70 mm walls cap gmsh's size, so all three meshes come out the same
    with pytest.raises(InputError, match="three meshes came out identical"):
        sw.run_study("shaft-torsion", params, mesh_size_mm=30.0, order=1)
    proc = subprocess.run([STRAINWAVE, "solve", "shaft-torsion", "--mesh-size-mm", "30", "--order", "1"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith("error: --mesh-size-mm = 30.0: shaft-torsion: the three")
