"""`diagnose --baseline fea` on a drive uses the FE tooth-mesh study's curve: a recording of that curve agrees;
the same curve with twice the lost motion is explained by lost_motion (issue 48, item 6)."""
import numpy as np
import pytest

from strainwave.compare.diagnose.drive_baseline import fea_drive_curve, predicted_drive_curve
from strainwave.compare.diagnose.pipeline import diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text
from strainwave.params import load_params


@pytest.fixture(scope="module")
def params_and_curve():
    params = load_params()
    return params, predicted_drive_curve(params)


def _recording(curve, extra_lost_motion_rad: float, seed: int = 1):
    """Two cycles +/- rated of the predicted loop, a 1e-4-of-span encoder noise, optional extra clearance."""
    rng = np.random.default_rng(seed)
    R = curve.rated_torque_Nm
    knots = np.array([0.0, 1.0, -1.0, 1.0, -1.0, 0.0]) * R
    T = np.interp(np.linspace(0, 5, 1500), np.arange(6), knots)
    d = np.sign(np.gradient(T))
    d[d == 0] = 1.0
    twist = curve.twist_rad(T, d)
    # a wider clearance: the flanks part by extra/2 either side of zero torque (the twist jumps as T changes sign)
    twist = twist + 0.5 * extra_lost_motion_rad * np.tanh(T / (0.01 * R))
    twist = twist + 1e-4 * np.ptp(twist) * rng.standard_normal(len(T))
    text = format_recording(RecordingKind.TORSION, "gear", 1e3 * T, twist)
    return parse_text(text)


def test_the_curve_is_taken_out_of_a_recording_of_it(params_and_curve):
    """Cheap: the corrected recording of the predicted loop is its secant line (to the noise), while the raw
    recording departs from any line by the stiffening and the loop."""
    from strainwave.compare.diagnose.drive_baseline import curve_baseline
    params, curve = params_and_curve
    rec = _recording(curve, 0.0)
    base, corrected = curve_baseline(rec, params)
    line = base.compliance * rec.load
    noise = 1e-4 * np.ptp(rec.response)
    assert np.sqrt(np.mean((corrected.response - line) ** 2)) < 3.0 * noise
    raw = rec.response - np.polyval(np.polyfit(rec.load, rec.response, 1), rec.load)
    assert np.sqrt(np.mean(raw ** 2)) > 30.0 * noise


@pytest.fixture(scope="module")
def params_and_fe_curve():
    params = load_params()
    return (params, *fea_drive_curve(params))         # the FE study on quick meshes, ~13 CPU-s


@pytest.mark.heavy
def test_the_fe_curve_is_a_real_drives_shape_and_its_own_baseline(params_and_fe_curve):
    """The FE study's curve, not the closed form's: it stiffens (K1 < K3), flank friction dissipates (the loop
    runs clockwise, its area positive), and diagnose's baseline is built from it with its GCI."""
    from strainwave.compare.diagnose.drive_baseline import curve_baseline
    params, curve, unc = params_and_fe_curve
    assert "FE study tooth-mesh" in curve.source and 0.0 < unc < 0.05
    assert curve.K1_Nm_per_rad < curve.K3_Nm_per_rad and curve.lost_motion_rad > 0.0
    T, th = curve.loop_torque_Nm, curve.loop_twist_rad
    k0 = int(np.argmax(T))
    k1 = k0 + int(np.argmin(T[k0:]))
    # clockwise: at every torque the unloading branch's twist exceeds the reloading one's (friction makes the twist
    # lag). Not the trapezoids of the history's points: at a zero torque they cross the backlash's dead band in one
    # step, as if the torque fell linearly across it (decision 073: -3.4 N mm there, the true slip's work +0.2)
    down, up = (T[k0:k1 + 1], th[k0:k1 + 1]), (T[k1:], th[k1:])
    for t in np.array([-0.9, -0.5, -0.1, -0.05, 0.05, 0.1, 0.5, 0.9]) * T[k0]:
        width = [np.interp(t, b[0][np.argsort(b[0])], b[1][np.argsort(b[0])]) for b in (down, up)]
        assert width[0] - width[1] > 0.0, t
    assert curve.K1_Nm_per_rad != pytest.approx(predicted_drive_curve(params).K1_Nm_per_rad, rel=0.05)
    base, _ = curve_baseline(_recording(curve, 0.0), params, "fea")
    assert "FE study tooth-mesh" in base.source


@pytest.mark.heavy
def test_the_predicted_curve_agrees(params_and_fe_curve):
    params, curve, _ = params_and_fe_curve
    diag, _ = diagnose(_recording(curve, 0.0), params, "fea", workers=1)
    assert diag.verdict.value == "agrees", diag.summary()


@pytest.mark.heavy
def test_twice_the_lost_motion_is_explained_as_lost_motion(params_and_fe_curve):
    params, curve, _ = params_and_fe_curve
    assert curve.lost_motion_rad > 0.0
    diag, _ = diagnose(_recording(curve, curve.lost_motion_rad), params, "fea", workers=1)
    assert diag.verdict.value == "explained", diag.summary()
    assert diag.summary().split("verdict: explained (")[1].startswith("lost_motion")


def _meta(steps_per_leg: int) -> dict:
    """A study-shaped meta (the headline loop, its knots and band) from the closed-form mesh's contact path."""
    from strainwave.analytic.mesh_drive import design_from_params, mesh_system
    from strainwave.fea.mesh_contact import solve_torque_path, torque_history
    params = load_params()
    path = solve_torque_path(mesh_system(design_from_params(params), 0.0)[0],
                             torque_history(params.gear.rated_output_torque_Nmm, steps_per_leg))
    return {"loop": {"torque_Nmm": path.torque_Nmm.tolist(), "twist_rad": path.twist_rad.tolist()},
            "loop_knots": path.knots.tolist(), "dead_band_rad": list(path.dead_band_rad)}


def test_the_study_loop_does_not_follow_the_studys_step():
    """Decision 076: `diagnose --baseline fea` reads the study's exact loop (its knots on the fixed grid, knees
    past the backlash band): 20 or 40 steps a leg read the same knees; the history's own steps (what a study
    without knots falls back to) moved T1 by 32 % and K1 by 21 % on the FE study from 20 to 40."""
    from strainwave.analytic.drive_curve import read_catalogue_numbers
    from strainwave.compare.diagnose.drive_baseline import study_loop
    rated = 1e-3 * load_params().gear.rated_output_torque_Nmm
    coarse, fine = _meta(20), _meta(40)

    def knees(meta, exact):
        T, th, band = study_loop(meta, exact)
        v = read_catalogue_numbers(1e-3 * T, th, rated, band)
        return np.array([v[k][0] for k in ("K1", "K2", "K3", "T1", "T2")])

    assert knees(coarse, True) == pytest.approx(knees(fine, True), rel=1e-6)
    without = {"loop": fine["loop"]}                       # an older study's meta: no knots, the steps as before
    assert study_loop(without)[2] == (0.0, 0.0) and len(study_loop(without)[0]) == len(fine["loop"]["torque_Nmm"])
    moved = np.abs(knees(coarse, False) / knees(fine, False) - 1.0)
    assert moved[3] > 0.3                                  # T1 on the steps follows the step: the bar above can fail
