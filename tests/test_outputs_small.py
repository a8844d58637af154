"""Issue 52's small items, each where a test can see it: a stress image's title inside its picture, the part
preview's load faces in blue, a parameter warning shown once however often a script loads parameters."""
from __future__ import annotations

import warnings

import numpy as np

from strainwave.compare.validate.images import TITLE_PT, WINDOW, title_text

# the ring image's title as the images stage writes it (compare/validate/images.py), numbers at full width
RING_TITLE = ["ring: von Mises at ring force F = 3.141e+04 N",
              "displacements x 12.5; section z = 12.34 mm",
              "peak 1234 MPa at (-12.34, 56.78, 0 mm on 'contact_b', peak displacement 0.123 mm,",
              "safety factor 0.506 vs fatigue limit 625 MPa",
              "sharp corner 2345 MPa: singular, within 0.123 mm of it, left out of the factor",
              "colours to 1033 MPa, the 99.5th percentile (white above): a local peak would leave the body one colour"]


def _rightmost_ink(text: str) -> int:
    from strainwave.render import RenderSettings, off_screen_plotter
    plotter = off_screen_plotter(RenderSettings(WINDOW, shape=(1, 1)))
    plotter.add_text(text, font_size=TITLE_PT, color="black")
    image = plotter.screenshot(None, return_img=True)
    plotter.close()
    return int(np.flatnonzero((image[..., :3] < 100).all(axis=2).any(axis=0)).max())


def test_a_stress_image_title_stays_inside_its_picture():
    wrapped = title_text(RING_TITLE)
    assert " ".join(wrapped.split()) == " ".join(" ".join(RING_TITLE).split())   # every word kept, in order
    assert _rightmost_ink(wrapped) < WINDOW[0] - 40
    # unwrapped, the last line runs into the picture's edge, where VTK clips it (the bug: "leave the body c")
    assert _rightmost_ink("\n".join(RING_TITLE)) >= WINDOW[0] - 8


def test_shaft_preview_draws_its_load_and_support_faces(params, tmp_path):
    from PIL import Image

    from strainwave.geometry.parts import build_part
    from strainwave.geometry.preview import render_preview
    png = render_preview(build_part("output-shaft", params), tmp_path / "shaft.png", size=(700, 350))
    rgb = np.asarray(Image.open(png).convert("RGB")).astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    blue = (b - r > 80) & (b - g > 50)   # the loaded end z = L in (shaded) royal blue; the grey body is not
    assert blue.sum() > 200


def test_the_parametric_example_warns_once_before_its_table():
    import subprocess
    import sys
    from pathlib import Path
    example = Path(__file__).resolve().parents[1] / "examples" / "parametric_study.py"
    code = example.read_text().replace('result = sw.run_study(', 'result = _fake(')   # the warnings, not the FEA
    code = code.replace("def main() -> None:", """def _fake(*a, **k):
    from types import SimpleNamespace
    return {"flexibility_rad_per_Nmm": SimpleNamespace(value=1.0, convergence=None)}


def main() -> None:""")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.count("MaterialWarning") == 1


def test_catalogue_units_stand_beside_the_models():
    from strainwave.analytic.rated_load import RatedLoad
    from strainwave.catalogue_units import beside, in_catalogue_units
    assert beside(1e6, "N*mm") == " (1000 N m)" and beside(5.376e8, "N*mm/rad") == " (5.376e+05 N m/rad)"
    assert in_catalogue_units(1e-3, "rad")[0] == np.degrees(1e-3) * 60 and beside(3.0, "MPa") == ""
    load = RatedLoad("shaft-torsion", "output torque T", "N*mm", 1e3, 7.8e3, "chosen")
    assert load.describe() == "output torque T = 7800 N*mm (7.8 N m) (chosen)"


def test_the_drives_stiffness_check_and_a_studys_torque_read_in_catalogue_units_too():
    """The report's check row of the drive's K_HD (N*mm/rad) carries N m/rad; a flexibility row (a part's, rad/(N*mm))
    stays as it is; a study's load line (solve, each VTU's `load`) says N m beside N*mm."""
    from strainwave.compare.validate.report_text import check_row
    from strainwave.fea.result import Load

    def row(unit, value):
        return check_row({"id": "x", "quantity": "q", "unit": unit, "fea": value, "fea_uncertainty": None,
                          "analytic": {}, "rel_error": {}, "tolerance": {"relative": None}, "passed": True,
                          "verdict": "corrected", "reason_not_evaluated": ""})
    assert row("N*mm/rad", 5.376e8)[2].endswith("(5.376e+05 N m/rad)")
    assert "N m" not in row("rad/(N*mm)", 1.2e-9)[2]
    torque = Load("output torque T", 1000.0, "N*mm", ("loaded",), "shear")
    assert torque.describe().startswith("output torque T = 1000 N*mm (1 N m) on 'loaded'")
    assert Load("force F", 10.0, "N", ("loaded",), "x").describe().startswith("force F = 10 N on")
