"""Images and checks from hand-made study results (no FEA run): the rendering and wiring on their own.

The fields are exact thin-ring / pure-torsion displacement fields written with pyvista, so what the
images and checks must show is known in advance.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv
from PIL import Image

from strainwave.analytic.summary import analytic_summary
from strainwave.compare.validate.artifacts import make_images
from strainwave.compare.validate.check_set import build_checks
from strainwave.compare.validate.fea_book import FeaBook
from strainwave.compare.validate.images import sample_circle
from strainwave.compare.validate.plan import make_plan
from strainwave.compare.validate.ring_shape import radial_displacement_mm
from strainwave.compare.validate.runner import CaseOutcome
from strainwave.fea.convergence import grid_convergence
from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support
from strainwave.params import load_params


def _ring_vtu(path: Path, r_m: float, wall: float, delta_cd: float) -> Path:
    disc = pv.Disc(inner=r_m - wall / 2, outer=r_m + wall / 2, r_res=4, c_res=360).cast_to_unstructured_grid()
    p = disc.points
    theta = np.arctan2(p[:, 1], p[:, 0])
    u_r = radial_displacement_mm(theta, delta_cd, load_angle_rad=math.pi / 2)  # loads along y, as fea/ring_*
    disc.point_data["displacement"] = np.column_stack([u_r * np.cos(theta), u_r * np.sin(theta), 0 * u_r])
    disc.point_data["von_mises"] = np.abs(np.cos(2 * theta)) * 200.0
    disc.save(path)
    return path


def _shaft_vtu(path: Path) -> Path:
    tube = pv.CylinderStructured(radius=np.linspace(22.5, 35, 4), height=200, theta_resolution=48,
                                 z_resolution=30).cast_to_unstructured_grid()
    p = tube.points
    twist = 1e-5 * (p[:, 2] + 100)
    tube.point_data["displacement"] = np.column_stack([-p[:, 1] * twist, p[:, 0] * twist, 0 * twist])
    tube.point_data["von_mises"] = np.hypot(p[:, 0], p[:, 1]) * 2 + 50 * np.exp(-(p[:, 2] / 3) ** 2)
    tube.save(path)
    return path


def _quantity(name: str, value: float, unit: str, spread: float) -> Quantity:
    conv = grid_convergence([1.0, 2.0, 4.0], [value, value * (1 + spread), value * (1 + 5 * spread)])
    return Quantity(name, value, unit, conv)


# The stand-ins state the load the real studies apply: seed 000's T on the shaft, the thin-ring force on the ring.
TORQUE = Load("output torque T", 1000.0, "N*mm", ("loaded",), "stand-in: shear traction on the end face")
CLAMPED = (Support(("fixed",), "stand-in: clamped"),)


def _outcome(case, quantities: dict, fields: tuple, load: Load = TORQUE) -> CaseOutcome:
    mesh = MeshQuality(100, 200, 600, 2, 0.5, 0.8)
    result = StudyResult(case.study, quantities, mesh, load, CLAMPED, timings_s={"solve": 0.1}, fields=fields)
    return CaseOutcome(case, result, 0.1, False)


@pytest.fixture(scope="module")
def wired(tmp_path_factory):
    out = tmp_path_factory.mktemp("artifacts")
    params = load_params()
    summary = analytic_summary(params)
    plan = make_plan(params, quick=False)   # the full plan: a shaft sweep of several depths to fit
    refs = summary["checks"]
    r_m = summary["seed003"]["geometry"]["r_m_mm"]
    delta_cd = refs["ring.delta_cd"]["corrected"]
    ring_vtu = _ring_vtu(out / "ring.vtu", r_m, summary["seed003"]["inputs"]["rim_thickness_mm"], delta_cd)
    shaft_vtu = _shaft_vtu(out / "shaft.vtu")
    outcomes = {}
    # The shaft FEA stands in with the exact hollow-shaft flexibility computed from E and nu.
    lam_exact = summary["seed000"]["lambda_so0"]["corrected_E_nu"]
    sweep = [plan.headline["shaft"]] + list(plan.sweeps["shaft"])
    for case in sweep:
        a = case.crack_depth_mm
        outcomes[case.label] = _outcome(case, {
            "flexibility_rad_per_Nmm": _quantity("flexibility_rad_per_Nmm", lam_exact, "rad/(N*mm)", 1e-5),
            "delta_flexibility_rad_per_Nmm": _quantity("delta_flexibility_rad_per_Nmm", 1e-16 * a ** 2,
                                                       "rad/(N*mm)", 1e-3)}, (shaft_vtu,))
    ring_q = {"delta_cd_mm": _quantity("delta_cd_mm", delta_cd, "mm", 1e-5),
              "delta_ab_mm": _quantity("delta_ab_mm", refs["ring.delta_ab"]["corrected"], "mm", 1e-5)}
    # the field is at the closed forms' thin-ring force for W0; the ring's rated load is the force for W0 over
    # the force solved: here 2 x that force
    f_ref = refs["ring.delta_cd"]["force_N"]
    ring_q["toothed_force_for_W0_N"] = Quantity("toothed_force_for_W0_N", 2 * f_ref, "N")
    ring_load = Load("diametral force F", f_ref, "N", ("contact",), "stand-in: arcs", (("half_angle_rad", 0.01),))
    outcomes[plan.label_of("ring-compression")] = _outcome(plan.case_of("ring-compression"), ring_q, (ring_vtu,), ring_load)
    book = FeaBook(outcomes)
    check_set = build_checks(book, plan, summary, params)
    made = make_images(out, book, plan, check_set, summary, progress=lambda m: None, params=params)
    return out, check_set, made.images, made.missing, r_m, delta_cd, made.stresses, made.views


@pytest.mark.heavy
def test_exact_fields_pass_their_checks_and_missing_studies_do_not(wired):
    _, check_set, *_ = wired
    checks = check_set.by_id()
    assert checks["shaft.flexibility"].passed and checks["shaft.flexibility"].verdict == "corrected"
    assert checks["ring.delta_cd"].passed and checks["ring.delta_ab"].passed
    assert not checks["cup.flexibility"].passed and checks["cup.flexibility"].verdict == "not evaluated"
    # a^2 data: the sweep's fitted exponent is 2 to round-off
    assert check_set.sweeps["shaft"].fit.exponent == pytest.approx(2.0, abs=1e-9)


def test_images_are_made_and_non_blank(wired):
    out, _, images, missing, *_ = wired
    kinds = {i.kind for i in images}
    assert {"stress", "closeup", "ring-shape", "convergence", "crack-sweep"} <= kinds
    for image in images:
        pixels = np.asarray(Image.open(out / image.path).convert("RGB"), dtype=float)
        assert pixels.std() > 5.0, image.path  # one colour = blank render
    # cup and bearing were not solved: their pictures are reported missing with the reason
    assert any("flexspline cup" in m.what for m in missing)


def test_mid_layer_sampling_recovers_the_thin_ring_diameter_changes(wired):
    out, _, _, _, r_m, delta_cd, _, _ = wired
    theta, u_r, _ = sample_circle(out / "ring.vtu", r_m, n=360)
    # loads on the y axis: D at +y moves in by delta_CD/2, B at +x moves out by 0.918 delta_CD/2;
    # linear interpolation over 1-degree cells of a smooth field: 0.5 % is ample
    at = lambda angle: u_r[np.argmin(np.abs(np.angle(np.exp(1j * (theta - angle)))))]
    assert at(math.pi / 2) == pytest.approx(-delta_cd / 2, rel=5e-3)
    ratio = (2 / math.pi - 0.5) / ((math.pi ** 2 - 8) / (4 * math.pi))
    assert at(0.0) == pytest.approx(ratio * delta_cd / 2, rel=5e-3)


def test_stress_pictures_are_drawn_at_the_rated_load_with_their_peaks(wired):
    out, _, images, _, _, _, stresses, _ = wired
    params = load_params()
    # the shaft field was written at seed 000's T: drawn at the rated torque, every stress scales by their ratio
    shaft = stresses["shaft"]
    assert shaft.load.scale == pytest.approx(params.gear.rated_output_torque_Nmm / params.gear.output_torque_Nmm)
    field = pv.read(str(out / "shaft.vtu"))
    k = int(np.argmax(field.point_data["von_mises"]))
    assert shaft.peaks.peak_von_mises_MPa == pytest.approx(shaft.load.scale * field.point_data["von_mises"][k])
    assert shaft.peaks.peak_location_mm == pytest.approx(tuple(field.points[k]))
    assert shaft.safety_factor == pytest.approx(params.material.fatigue_limit_MPa / shaft.peaks.peak_von_mises_MPa)
    # the ring: the force for W0 over the solved reference force (2 here)
    assert stresses["ring"].load.scale == pytest.approx(2.0)
    assert stresses["ring"].peaks.peak_von_mises_MPa == pytest.approx(2 * 200.0, rel=1e-6)
    captions = {i.component: i.caption for i in images if i.kind == "stress"}
    assert "safety factor" in captions["shaft"] and "T = 1e+06 N*mm" in captions["shaft"]
    assert "2D plane stress section" in captions["ring"]
    closeup = next(i.caption for i in images if i.kind == "closeup")    # crack tips at the rated load too
    assert "at output torque T = 1e+06 N*mm" in closeup


def test_3d_views_carry_the_scaled_surface_field(wired):
    import base64
    import json

    *_, stresses, views = wired
    assert set(views) == set(stresses)
    for component, view in views.items():
        data = json.loads(view.payload)
        points = np.frombuffer(base64.b64decode(data["positions"]), dtype=np.float32).reshape(-1, 3)
        scalars = np.frombuffer(base64.b64decode(data["scalars"]), dtype=np.float32)
        faces = np.frombuffer(base64.b64decode(data["indices"]), dtype=np.uint32).reshape(-1, 3)
        assert len(points) == len(scalars) and faces.max() < len(points) and len(faces) == view.triangles > 0
        assert np.linalg.norm(points, axis=1).max() == pytest.approx(1.0, abs=1e-6)   # fits the viewer's sphere
        # the surface carries the rated-load stress: its largest value is the field's peak (an outer node)
        peak = stresses[component].peaks.peak_von_mises_MPa
        assert data["range"] == [0.0, pytest.approx(peak)] and scalars.max() == pytest.approx(peak, rel=1e-5)
