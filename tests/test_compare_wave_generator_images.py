"""The wave-generator studies' pictures (the cup on the wave generator, the bearing ring on the cam, the surface
crack's opening at the major and minor axes) from fields solved on coarse meshes, and the study fact that keeps
their peaks out of the design verdict (``StudyFacts.outside_design``)."""
from __future__ import annotations

import warnings

import numpy as np
import pytest
from PIL import Image

from strainwave.compare.validate.fea_book import FeaBook
from strainwave.compare.validate.plan import Plan, make_plan
from strainwave.compare.validate.runner import Case, CaseOutcome
from strainwave.fea.result import CrackRecord, Load, MeshQuality, StudyResult, Support

PICTURED = ("cup-wave-generator", "wg-bearing", "cup-surface-crack")


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


def _outcome(case: Case, fields: tuple, load: Load, crack: CrackRecord | None = None) -> CaseOutcome:
    mesh = MeshQuality(100, 200, 600, 2, 0.5, 0.8)
    result = StudyResult(case.study, {}, mesh, load, (Support(("held",), "stand-in"),), crack, fields=fields)
    return CaseOutcome(case, result, 0.1, False)


def _non_blank(path) -> bool:
    return float(np.asarray(Image.open(path).convert("RGB"), dtype=float).std()) > 5.0


def test_the_wave_generator_studies_are_pictured_not_design_factors(params):
    """Every study that declares ``outside_design`` is drawn in its component's section and is in none of the
    design cases, and the component titles and previews stay the design studies'."""
    from strainwave.compare.validate.artifacts import COMPONENT_TITLES
    from strainwave.compare.validate.pipeline import _preview_of

    plan = make_plan(params, quick=True)
    pictured = {c.study: component for component, c in plan.pictured()}
    assert pictured == {"cup-wave-generator": "cup", "wg-bearing": "bearing", "cup-surface-crack": "cup"}
    reported = [component for component, _ in plan.reported()]
    assert not {c.study for _, c in plan.reported()} & set(PICTURED)
    assert len(reported) == len(set(reported))          # one design field per component
    assert COMPONENT_TITLES["cup"] == "flexspline cup" and COMPONENT_TITLES["bearing"] == "bearing inner ring"
    assert _preview_of()["wg-bearing-ring"] == "bearing"


def _cup_stand_in(path):
    """A twisted tube standing in for the cup-torsion field (its design stress)."""
    import pyvista as pv
    tube = pv.CylinderStructured(radius=np.linspace(78.0, 80.0, 3), height=100, theta_resolution=36,
                                 z_resolution=12).cast_to_unstructured_grid()
    p = tube.points
    twist = 1e-6 * (p[:, 2] + 50)
    tube.point_data["displacement_mm"] = np.column_stack([-p[:, 1] * twist, p[:, 0] * twist, 0 * twist])
    tube.point_data["von_mises_MPa"] = 5.0 + 0.01 * p[:, 2] ** 2
    tube.save(path)
    return path


@pytest.fixture(scope="module")
def crack_block(params, tmp_path_factory):
    """The surface crack's major and minor fields on a coarse block (global t/2, front t/8)."""
    from strainwave.analytic import surface_crack as sc
    from strainwave.fea.surface_crack import ASPECT, FIELDS_STATES, _write_fields, block_for, solve_block

    out = tmp_path_factory.mktemp("crack")
    loads = sc.study_loads(params)
    m, t = params.material, params.flexspline_cup.wall_thickness_mm
    block = block_for(t, 0.2 * t, ASPECT, m.youngs_modulus_MPa, m.poisson_ratio, loads["per_torque_MPa_per_Nmm"],
                      [s for s in loads["states"] if s[0] in FIELDS_STATES])
    solved = solve_block(block, 0.5 * t, 0.125 * t, fields_of=FIELDS_STATES)
    return out, block, _write_fields(out / "cup-surface-crack.vtu", block, solved, m)


def test_the_surface_crack_block_is_drawn_but_stays_out_of_the_design_verdict(params, crack_block):
    """With the cup's design case and the surface-crack block both solved, the cup's design stress and factor
    are the cup's, the block is drawn (stress and opening), and its opening is the field's own 2 u_z: wide open
    at the major axis, mostly shut at the minor axis."""
    from strainwave.compare.validate.artifacts import make_images
    from strainwave.compare.validate.check_set import CheckSet
    from strainwave.compare.validate.images import crack_face_opening
    from strainwave.compare.validate.pipeline import _design

    out, block, (major, minor) = crack_block
    T = params.gear.rated_output_torque_Nmm
    cup = Case("cup-a1", "cup-torsion", 1.0)
    crack = Case("cup-surface-crack", "cup-surface-crack")
    book = FeaBook({
        cup.label: _outcome(cup, (_cup_stand_in(out / "cup.vtu"),), Load("output torque T", 1000.0, "N*mm",
                                                                           ("loaded",), "stand-in")),
        crack.label: _outcome(crack, (major, minor), Load("output torque T", T, "N*mm", ("far",), "stand-in"),
                              CrackRecord(block.a_mm, "surface crack"))})
    plan = Plan({"cup": cup}, {}, (crack,))
    made = make_images(out, book, plan, CheckSet((), {}), {}, progress=lambda m: None, params=params)
    assert set(made.stresses) == {"cup"} and made.stresses["cup"].study == "cup-torsion"
    _, verdict = _design(params, book, plan, made.stresses)
    # the cup's factor is its own field's peak; the block gives none (the method's other factors, issue 49, are
    # not evaluated here: their cases did not run)
    assert [f.stress_MPa for f in verdict.factors if f.component == "cup"] == [made.stresses["cup"].peaks.peak_von_mises_MPa]
    assert not any("surface" in f.component or "crack" in f.component for f in verdict.factors)
    shown = {i.path.name: i for i in made.images}
    for name, kind in (("cup-surface-crack_von_mises.png", "stress"), ("cup-surface-crack_opening.png",
                                                                       "crack-opening")):
        assert shown[name].kind == kind and shown[name].component == "cup" and _non_blank(out / shown[name].path)
    assert "no design factor: a block of the band wall" in shown["cup-surface-crack_von_mises.png"].caption
    import jsonschema
    from strainwave.compare.validate.results import load_schema
    image_schema = {**load_schema()["$defs"]["image"], "$defs": load_schema()["$defs"]}
    for image in made.images:   # results.json's images entry takes the new kind
        jsonschema.validate(image.to_dict(), image_schema)
    faces = {s: crack_face_opening(v)[0] for s, v in (("major", major), ("minor", minor))}
    opening = {s: np.asarray(f.point_data["opening_um"]) for s, f in faces.items()}
    inside = {s: opening[s][np.asarray(f.point_data["on_front"]) == 0] for s, f in faces.items()}
    import pyvista as pv
    grid = pv.read(major)
    x, u = np.asarray(grid.points), np.asarray(grid.point_data["displacement_mm"])
    face = (np.abs(x[:, 2]) < 1e-6) & (np.hypot(x[:, 0] / block.c_mm, x[:, 1] / block.a_mm) < 1.0 - 1e-6)
    assert opening["major"].max() == pytest.approx(2e3 * u[face, 2].max(), rel=1e-5)
    # the study's own contact sets: none shut at the major axis, most shut at the minor axis (fea/surface_crack)
    assert np.all(inside["major"] > 1e-3 * opening["major"].max())
    assert np.mean(inside["minor"] > 1e-3 * opening["major"].max()) < 0.5
    caption = shown["cup-surface-crack_opening.png"].caption
    assert f"major: opening up to {opening['major'].max():.3g} um" in caption and "minor:" in caption


def test_the_cup_on_the_wave_generator_and_the_ring_on_the_cam_are_drawn(params, tmp_path):
    """Both pictures are made from their studies' own writers, at the load each study solved (its rated load:
    scale 1), and say they are no design factor."""
    from strainwave.analytic.study_loads import wg_bearing_load
    import pyvista as pv

    from strainwave.compare.validate import images

    from strainwave.compare.validate.artifacts import NO_DESIGN_LINE, _pictured_stress, _signed_picture
    from strainwave.fea import wg_band as wb
    from strainwave.fea.assembly import Lame
    from strainwave.fea.fields import field_info
    from strainwave.fea.wg_bearing import setup_from, solve_plain, write_fields
    from strainwave.rated_stress import stress_at_rated
    from strainwave.registry import STUDIES

    m, load = params.material, wg_bearing_load(params)
    s = setup_from(params, **load)
    ring = write_fields(tmp_path / "wg-bearing.vtu", s, solve_plain(s, 5.0, 1.96, 1.0), m)
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)
    tube = wb.tube_mesh(wb.tube_geometry(params), 4)
    state = wb.insert(tube, lame, params.gear.radial_deformation_mm, contact=False, nonlinear=False)
    cup = wb.write_fields(tmp_path / "cup-wave-generator.vtu", tube, state.u, lame, False,
                          field_info("cup-wave-generator", "prescribed insertion", m))
    T = params.gear.rated_output_torque_Nmm
    cases = {Case("wg-bearing", "wg-bearing"): (ring, Load("F_r", load["force_N"], "N", ("race",), "balls")),
             Case("cup-wave-generator", "cup-wave-generator"): (cup, Load("T", T, "N*mm", ("band",), "shear"))}
    book = FeaBook({c.label: _outcome(c, (vtu,), ld) for c, (vtu, ld) in cases.items()})
    for case, (vtu, _) in cases.items():
        at = stress_at_rated(case.study, params, book.result(case.label), vtu, cracked=False)
        assert at.load.scale == pytest.approx(1.0, rel=1e-12)
        target = tmp_path / f"{case.label}.png"
        caption = _pictured_stress(images, target, book, case, params)
        why = f"no design factor: {STUDIES[case.study].facts().outside_design}"
        assert NO_DESIGN_LINE not in caption and why in caption and _non_blank(target)
        assert f"peak {at.peaks.peak_von_mises_MPa:.4g} MPa" in caption
        # the signed picture: its hoop stress read back (pyvista), the cam's bending in tension and in compression
        signed = _signed_picture(images, tmp_path / f"{case.label}_signed.png", book, case, params)
        hoop = np.asarray(pv.read(vtu).point_data["hoop_stress_MPa"])
        assert hoop.max() > 0 > hoop.min() and _non_blank(tmp_path / f"{case.label}_signed.png")
        assert f"tension up to {hoop.max():.4g} MPa" in signed and f"compression down to {hoop.min():.4g}" in signed


def test_a_field_named_uncracked_carries_no_crack_even_when_the_study_swept_cracks():
    """wg-bearing sweeps its own race cracks (its result has a crack depth) but writes the uncracked ring: its
    stress summary must not take a crack-tip zone from it; a cracked solve's single field still carries its crack."""
    from pathlib import Path

    from strainwave.rated_stress import stress_field_of
    assert stress_field_of("wg-bearing", (Path("f/wg-bearing_uncracked.vtu"),), 1.0) == \
        (Path("f/wg-bearing_uncracked.vtu"), False)
    assert stress_field_of("cup-surface-crack", (Path("f/c_major.vtu"), Path("f/c_minor.vtu")), 0.4) == \
        (Path("f/c_major.vtu"), True)
    assert stress_field_of("cup-torsion", (Path("f/cup.vtu"),), 0.5) == (Path("f/cup.vtu"), True)
