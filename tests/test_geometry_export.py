"""STEP/BREP round trips (build123d and gmsh), assemblies, previews and the export-step command."""
from __future__ import annotations

import subprocess
import warnings

import pytest

from strainwave.errors import InputError
from strainwave.geometry.export import export_part, write_brep, write_step
from strainwave.geometry.parts import build_part
from strainwave.params import load_params

# The STEP writer stores the exact B-rep (planes, cylinders, B-splines), so the re-imported volume
# must agree to the brief's 1e-6 relative; OCC's mass integration itself is ~1e-9 on these shapes.
ROUND_TRIP = 1e-6


@pytest.fixture(scope="module")
def params():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = load_params()
        return p.with_value("flexspline_cup.teeth", 40).with_value("flexspline_cup.module_mm", 4.0)


# B-spline flanks are covered by the toothed cup; the ring goes smooth to keep the test fast
CASES = [("output-shaft", 2.0, True), ("wg-bearing-ring", 0.5, True), ("ewg-flexspline-ring", None, False),
         ("ewg", None, True), ("flexspline-cup", 0.5, True)]


def _gmsh_volumes(path):
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(path))
        gmsh.model.occ.synchronize()
        return sorted(gmsh.model.occ.getMass(3, tag) for _, tag in gmsh.model.getEntities(3))
    finally:
        gmsh.finalize()


@pytest.mark.parametrize("name,crack,teeth", CASES)
def test_step_round_trip(params, tmp_path, name, crack, teeth):
    from build123d import import_step

    part = build_part(name, params, crack_depth_mm=crack, teeth=teeth)
    path = write_step(part, tmp_path / f"{name}.step")
    n_solids = len(part.solid.solids())          # one per part; the roller EWG is two rollers
    back = import_step(path)
    assert len(back.solids()) == n_solids and all(s.is_valid for s in back.solids())
    assert sum(s.volume for s in back.solids()) == pytest.approx(part.volume_mm3, rel=ROUND_TRIP)
    vols = _gmsh_volumes(path)
    assert len(vols) == n_solids
    assert sum(vols) == pytest.approx(part.volume_mm3, rel=ROUND_TRIP)
    assert not list(tmp_path.glob(".*tmp"))      # no temporary left behind


def test_brep_round_trip(params, tmp_path):
    from build123d import import_brep

    part = build_part("output-shaft", params, crack_depth_mm=1.0)
    back = import_brep(write_brep(part, tmp_path / "shaft.brep"))
    assert back.volume == pytest.approx(part.volume_mm3, rel=1e-12)   # native format: bit-exact geometry
    assert len(back.faces()) == len(part.solid.faces())


def test_assembly_exports_both_drives_with_part_names(params, tmp_path):
    from build123d import import_step

    written = export_part("assembly", params, tmp_path / "gear.step", teeth=False)
    assert [p.name for p in written] == ["gear.step", "gear-ewg-drive.step"]
    cup_gear, ewg_drive = (import_step(p) for p in written)
    assert len(cup_gear.solids()) == 3 and len(ewg_drive.solids()) == 3   # cup, ring, shaft | ring, 2 rollers
    text = written[0].read_text(errors="ignore")
    for label in ("flexspline-cup", "wg-bearing-ring", "output-shaft"):
        assert label in text
    assert "MILLI" in text                                                # length unit mm
    # the shaft hangs below the hub: the assembly spans -L_s .. L
    bb = cup_gear.bounding_box()
    assert bb.min.Z == pytest.approx(-params.output_shaft.length_mm, abs=1e-6)
    assert bb.max.Z == pytest.approx(params.flexspline_cup.length_mm, abs=1e-6)


def test_preview_is_not_blank_and_shows_the_crack(params, tmp_path):
    import matplotlib.image as mpimg

    part = build_part("wg-bearing-ring", params, crack_depth_mm=0.5)
    from strainwave.geometry.preview import render_preview
    img = mpimg.imread(render_preview(part, tmp_path / "ring.png"))[..., :3]
    h, w, _ = img.shape
    non_white = (img.min(axis=2) < 0.95).mean()
    assert non_white > 0.05                                   # the part covers a real share of the image
    red = (img[..., 0] > 0.7) & (img[..., 1] < 0.3) & (img[..., 2] < 0.3)
    assert red[:, w // 2:].sum() > 50                         # crack faces visible in the close-up half


def test_failed_export_leaves_no_file(params, tmp_path):
    out = tmp_path / "bad.step"
    with pytest.raises(InputError):
        export_part("output-shaft", params, out, crack_depth_mm=50.0)
    assert list(tmp_path.iterdir()) == []


def _cli(strainwave_cmd, tmp_path, *args):
    # G consistent with E and nu, so that the only stderr line is the error itself
    cfg = tmp_path / "p.toml"
    cfg.write_text("[material]\nshear_modulus_MPa = 80769.23\n")
    return subprocess.run([*strainwave_cmd, "export-step", "--params", str(cfg), *args],
                          capture_output=True, text=True, timeout=120)


def test_cli_export_step(strainwave_cmd, tmp_path):
    out = tmp_path / "shaft.step"
    png = tmp_path / "shaft.png"
    run = _cli(strainwave_cmd, tmp_path, "--part", "output-shaft", "--crack-depth-mm", "1.0",
               "-o", str(out), "--png", str(png))
    assert run.returncode == 0, run.stderr
    assert out.stat().st_size > 1000 and png.stat().st_size > 1000
    assert f"wrote {out}" in run.stdout


def test_cli_bad_crack_is_one_line_exit_2(strainwave_cmd, tmp_path):
    out = tmp_path / "shaft.step"
    run = _cli(strainwave_cmd, tmp_path, "--part", "output-shaft", "--crack-depth-mm", "20", "-o", str(out))
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "crack_depth_mm" in lines[0] and "Traceback" not in run.stderr
    assert not out.exists()
