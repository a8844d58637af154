"""STEP/BREP round trips (build123d and gmsh), assemblies, previews and the export-step command."""
from __future__ import annotations

import re
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
        return p.with_values({"flexspline_cup.teeth": 40, "flexspline_cup.module_mm": 4.0})


# B-spline flanks are covered by the toothed cup; the ring goes smooth to keep the test fast
CASES = [("output-shaft", 2.0, True), ("wg-bearing-ring", 0.5, True), ("ewg-flexspline-ring", None, False),
         ("ewg", None, True), ("flexspline-cup", 0.5, True), ("wg-cam", None, True)]


def _gmsh_import(path):
    """What gmsh sees in a STEP file: volumes, names of the volumes, (centre, area) of every surface."""
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(path))
        gmsh.model.occ.synchronize()
        volumes = sorted(gmsh.model.occ.getMass(3, tag) for _, tag in gmsh.model.getEntities(3))
        names = sorted(gmsh.model.getEntityName(3, tag) for _, tag in gmsh.model.getEntities(3))
        surfaces = [(gmsh.model.occ.getCenterOfMass(2, tag), gmsh.model.occ.getMass(2, tag))
                    for _, tag in gmsh.model.getEntities(2)]
        return volumes, names, surfaces
    finally:
        gmsh.finalize()


def _gmsh_volumes(path):
    return _gmsh_import(path)[0]


def _named_faces_come_back(path, expected: dict[str, int], size_mm: float):
    """Every named face is read back by OCC's STEP reader with its name, and is one of gmsh's surfaces.

    gmsh 4.15's importShapes reads product names (volumes) but not face names, so on the gmsh side each
    named face is found by its centre and area (as the mesher matches faces)."""
    from collections import Counter

    from strainwave.geometry.step_xcaf import read_step_face_names

    back = read_step_face_names(path)
    # a face in two sets carries both names joined by '+' (the cup's tooth flanks are also 'loaded')
    assert Counter(group for name, _, _ in back for group in name.split("+")) == Counter(expected)
    _, _, surfaces = _gmsh_import(path)
    for name, centre, area in back:
        hits = [s for s in surfaces if abs(s[1] - area) <= 1e-6 * area
                and max(abs(a - b) for a, b in zip(s[0], centre)) <= 1e-6 * size_mm]
        assert len(hits) == 1, (name, centre, area)


@pytest.mark.parametrize("name,crack,teeth", CASES)
def test_step_round_trip(params, tmp_path, name, crack, teeth):
    from build123d import import_step

    part = build_part(name, params, crack_depth_mm=crack, teeth=teeth)
    path = write_step(part, tmp_path / f"{name}.step")
    n_solids = len(part.solid.solids())          # one per part; the roller EWG is two rollers
    back = import_step(path)
    assert len(back.solids()) == n_solids and all(s.is_valid for s in back.solids())
    assert sum(s.volume for s in back.solids()) == pytest.approx(part.volume_mm3, rel=ROUND_TRIP)
    vols, names, _ = _gmsh_import(path)
    assert len(vols) == n_solids
    assert sum(vols) == pytest.approx(part.volume_mm3, rel=ROUND_TRIP)
    if n_solids == 1:                            # the product name reaches gmsh (a two-roller EWG is a compound)
        assert names[0].endswith(name)
    assert not list(tmp_path.glob(".*tmp"))      # no temporary left behind
    # every named face of the part is a named STEP face (fixed, loaded, bore, contact, crack_face, ...)
    expected = {group: len(refs) for group, refs in part.named_faces.items()}
    if crack is not None:
        assert expected["crack_face"] >= 1 and expected["crack_front"] >= 1
    text = path.read_text(errors="ignore")
    assert "COLOUR_RGB" in text
    assert all(re.search(rf"ADVANCED_FACE\('([a-z_]+\+)?{group}(\+[a-z_]+)?'", text) for group in expected)
    _named_faces_come_back(path, expected, part.solid.bounding_box().diagonal)


def _spy_on_read_back_naming(monkeypatch):
    """Count the files whose names had to be put on by reading the written file back."""
    from strainwave.geometry import step_xcaf

    calls = []
    original = step_xcaf._name_faces

    def spy(path, placed):
        calls.append(path)
        return original(path, placed)
    monkeypatch.setattr(step_xcaf, "_name_faces", spy)
    return calls


@pytest.mark.heavy
def test_toothed_cup_faces_are_named_in_the_writers_model(params, tmp_path, monkeypatch):
    """The teeth of the cup are moved into place (their faces carry a location) and are still named by
    the writer's own map, without reading the file back; the names are the read-back ones."""
    from collections import Counter

    from strainwave.geometry.step_xcaf import read_step_face_names

    calls = _spy_on_read_back_naming(monkeypatch)
    part = build_part("flexspline-cup", params, teeth=True)
    path = write_step(part, tmp_path / "cup.step")
    assert calls == []
    back = read_step_face_names(path)
    assert len(back) == len(part.solid.faces())   # no face left without a name (tooth ends, closed end)
    assert Counter(group for name, _, _ in back for group in name.split("+")) == \
        Counter({group: len(refs) for group, refs in part.named_faces.items()})
    # each name sits on the face it was given to: centre and area as recorded by the part
    named_at = {(tuple(round(c, 6) for c in centre), round(area, 6)): name.split("+") for name, centre, area in back}
    for group, refs in part.named_faces.items():
        for ref in refs:
            assert group in named_at[(tuple(round(c, 6) for c in ref.center_mm), round(ref.area_mm2, 6))]


def _ring_sharing_one_shape():
    """An extruded ring whose top is a located copy of its bottom (one TShape), top and bottom named."""
    from build123d import Face, Wire, extrude

    from strainwave.geometry.part import FaceRef, Part, PartName

    solid = extrude(Face(Wire.make_circle(10.0)) - Face(Wire.make_circle(5.0)), 3.0).solids()[0]
    flat = [f for f in solid.faces() if abs(f.normal_at(f.center()).Z) > 0.5]
    assert len(flat) == 2
    bottom, top = sorted(flat, key=lambda f: f.center().Z)

    def ref(face):
        c = face.center()
        return (FaceRef((c.X, c.Y, c.Z), float(face.area)),)
    return Part(PartName.WG_BEARING_RING, solid, {"bottom": ref(bottom), "top": ref(top)})


@pytest.mark.parametrize("copy_first", [True, False])
def test_faces_sharing_one_shape_are_each_named(tmp_path, monkeypatch, copy_first):
    """The writer's map cannot tell a located copy from its original: the writer copies such a solid (one
    TShape per face) and names it in memory; without that copy the names go on through the read-back.
    Either way each name sits on its own face."""
    from strainwave.geometry import step_xcaf

    calls = _spy_on_read_back_naming(monkeypatch)
    part = _ring_sharing_one_shape()
    assert step_xcaf._shares_face_shapes(part.solid)
    if not copy_first:
        monkeypatch.setattr(step_xcaf, "_unshared", lambda item: item)
    path = write_step(part, tmp_path / "ring.step")
    assert len(calls) == (0 if copy_first else 1)
    back = sorted(step_xcaf.read_step_face_names(path), key=lambda item: item[1][2])
    assert [(name, round(centre[2], 9)) for name, centre, _ in back] == [("bottom", 0.0), ("top", 3.0)]


def test_brep_round_trip(params, tmp_path):
    from build123d import import_brep

    part = build_part("output-shaft", params, crack_depth_mm=1.0)
    back = import_brep(write_brep(part, tmp_path / "shaft.brep"))
    assert back.volume == pytest.approx(part.volume_mm3, rel=1e-12)   # native format: bit-exact geometry
    assert len(back.faces()) == len(part.solid.faces())


def test_assembly_exports_both_drives_with_part_names(params, tmp_path):
    from build123d import import_step

    written = export_part("assembly", params, tmp_path / "gear.step", teeth=False)
    # each STEP file with its face index (gmsh reads no STEP face names: geometry/face_names.py)
    assert [p.name for p in written] == ["gear.step", "gear.faces.json", "gear-ewg-drive.step",
                                         "gear-ewg-drive.faces.json"]
    written = [p for p in written if p.suffix == ".step"]
    cup_gear, ewg_drive = (import_step(p) for p in written)
    # cup, circular spline, cam, inner ring, balls, outer ring, shaft | ring, 2 rollers
    assert len(cup_gear.solids()) == 6 + params.wave_generator.ball_count and len(ewg_drive.solids()) == 3
    text = written[0].read_text(errors="ignore")
    for label in ("flexspline-cup", "circular-spline", "wg-cam", "wg-bearing-ring", "wg-bearing-balls",
                  "wg-bearing-outer-ring", "output-shaft"):
        assert label in text
    assert "MILLI" in text                                                # length unit mm
    # every part's named faces are named in its drive's file (a face in two sets counts in both)
    from collections import Counter

    from strainwave.geometry.export import cup_gear_assembly, ewg_drive_assembly
    from strainwave.geometry.step_xcaf import read_step_face_names
    for path, placed in zip(written, (cup_gear_assembly(params, teeth=False), ewg_drive_assembly(params, teeth=False))):
        expected = Counter()
        for item in placed:
            expected.update({group: len(refs) for group, refs in item.part.named_faces.items()})
        back = Counter(group for name, _, _ in read_step_face_names(path) for group in name.split("+"))
        assert back == expected, path.name
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


@pytest.mark.heavy
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
    assert len(lines) == 1 and "--crack-depth-mm = 20.0" in lines[0] and "Traceback" not in run.stderr   # as given
    assert not out.exists()


def test_assembly_png_draws_every_part_of_both_drives(params, tmp_path):
    """The preview of ``--part assembly`` shows the whole assembly, not only the cup: the bearing rings
    (orange), the shaft (blue) and the cam (green) in the left panel and the EWG rollers (green) in the right one."""
    import matplotlib.image as mpimg
    import numpy as np

    written = export_part("assembly", params, tmp_path / "gear.step", teeth=False, png=tmp_path / "gear.png")
    assert [p.name for p in written] == ["gear.step", "gear.faces.json", "gear-ewg-drive.step",
                                         "gear-ewg-drive.faces.json", "gear.png"]
    img = mpimg.imread(written[-1])[..., :3]
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    w = img.shape[1]
    orange = (r - b > 0.25) & (r > g)                 # wg-bearing-ring (0.85, 0.62, 0.30), shaded
    blue = (b - r > 0.08) & (b > g)                   # output-shaft (0.45, 0.55, 0.70), shaded darker
    green = (g - r > 0.1) & (g - b > 0.1)             # ewg (0.55, 0.75, 0.50)
    assert orange[:, : w // 2].sum() > 500 and blue[:, : w // 2].sum() > 500
    assert green[:, w // 2:].sum() > 500 and green[:, : w // 2].sum() > 500    # the EWG | the cup gear's cam
    assert np.mean(img.min(axis=2)[:, w // 2:] < 0.95) > 0.03   # the EWG drive panel is not blank
