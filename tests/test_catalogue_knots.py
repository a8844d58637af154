"""Decision 074: the catalogue's curve is the exact loop (the mesh's knots on a fixed torque grid), so what the
command reads does not follow the solve's torque step; the JSON keeps its keys."""
from dataclasses import replace

import numpy as np
import pytest

import strainwave.analytic.catalogue_predict as cp
import strainwave.analytic.drive_curve as dc
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.mesh_drive import bearing_twist_rad, mesh_system
from strainwave.fea.mesh_contact import solve_torque_path, torque_history

# the FE series terms off: they do not see the loop's step (their own tests hold them); the mesh is what moves
RULES = replace(MeshRules(), cup_zone_elements=None, cs_body_restraint=None)
ROW = "size,ratio,T1_Nm,T2_Nm,K1_e3,K2_e3,K3_e3\n14,50,2,6.9,3.4,4.7,5.7\n"
READ = ("K1_Nm_per_rad_predicted", "K2_Nm_per_rad_predicted", "K3_Nm_per_rad_predicted", "T1_Nm_predicted",
        "T2_Nm_predicted", "K1_Nm_per_rad_reader", "K2_Nm_per_rad_reader", "K3_Nm_per_rad_reader",
        "lost_motion_arcmin_reader", "lost_motion_arcmin_predicted", "loop_width_max_arcmin")
ROW_KEYS = {"size", "ratio", "ratio_number", "K_windows_Nm", "K_windows_from", "left_out", "rated_torque_Nm",
            "ratcheting_torque_Nm_predicted", "lost_motion_arcmin_reader", "hysteresis_loss_arcmin_reader",
            "hysteresis_loss_arcmin_predicted", "hysteresis_loss_arcmin_catalogue", "hysteresis_loss_within_bound",
            "hysteresis_loss_loop_amplitude_Nm", "lost_motion_arcmin_predicted", "lost_motion_arcmin_catalogue",
            "lost_motion_within_bound", "lost_motion_torque_Nm", "lost_motion_torque_from", "loop_width_max_arcmin",
            "loop_width_max_at_Nm", "loss_bounds_from"} | {f"{n}_{s}" for n in cp.NAMES
                                                             for s in ("predicted", "catalogue")} \
    | {f"{n}_reader" for n in cp.NAMES[:3]}


def _row(tmp_path, monkeypatch, steps, deviations=None) -> dict:
    monkeypatch.setattr(dc, "LOOP_STEPS_PER_LEG", steps)
    table = tmp_path / "t.csv"
    table.write_text(ROW)
    return cp.predict_table(table, RULES, deviations).to_dict()["rows"][0]


@pytest.mark.parametrize("deviations", [None, (6.0, 2)])
def test_halving_or_doubling_the_step_does_not_move_the_readings(tmp_path, monkeypatch, deviations):
    base, half, double = (_row(tmp_path, monkeypatch, n, deviations) for n in (60, 30, 120))
    for other in (half, double):
        for key in READ:
            assert other[key] == pytest.approx(base[key], rel=1e-6), key
        assert other["hysteresis_loss_arcmin_predicted"] == pytest.approx(base["hysteresis_loss_arcmin_predicted"],
                                                                          abs=1e-9)
    assert set(base) == ROW_KEYS | ({f"{n}_unit_sd" for n in cp.NAMES} if deviations else set())


def test_the_history_samples_alone_do_move_with_the_step(monkeypatch):
    """The contrast the test above can fail on: the old reading (the solve's own steps) moves T1 and T2."""
    d = RULES.design(14.0, 50.0)
    s, A = RULES.cup_flexibility_rad_per_Nmm(14.0), RULES.rated_torque_Nm(14.0)
    old = []
    for n in (30, 120):
        monkeypatch.setattr(dc, "LOOP_STEPS_PER_LEG", n)
        old.append(dc.predict_curve(d, s, A, with_te=False))
    assert max(abs(old[1].T1_Nm / old[0].T1_Nm - 1.0), abs(old[1].T2_Nm / old[0].T2_Nm - 1.0)) > 0.01


def test_the_exact_loop_is_the_solve_at_the_grid_torques():
    """From first principles: the path solve is exact at each of its torques, so solving directly on the reading
    grid gives the same loop as the knots of a coarse solve interpolated there (series and balls added)."""
    d = RULES.design(14.0, 30.0)
    s, A = RULES.cup_flexibility_rad_per_Nmm(14.0), RULES.rated_torque_Nm(14.0)
    curve = dc.predict_curve(d, s, A, with_te=False, exact=True)
    grid = torque_history(1e3 * A, dc.READ_STEPS_PER_LEG)
    direct = solve_torque_path(mesh_system(d)[0], grid).twist_rad + grid * s + bearing_twist_rad(d, grid)
    assert np.array_equal(curve.loop_torque_Nm, 1e-3 * grid)
    assert np.max(np.abs(curve.loop_twist_rad - direct)) <= 1e-9 * np.max(np.abs(direct))
    # and the comparison can fail: the loop without the balls' Hertz twist is off by more than 1 %
    no_balls = direct - bearing_twist_rad(d, grid)
    assert np.max(np.abs(curve.loop_twist_rad - no_balls)) > 1e-2 * np.max(np.abs(direct))


def test_a_drive_with_backlash_reads_its_knees_with_the_dead_band_out():
    """Decision 073's definition on the exact loop: the shipped gear has backlash, so the raw loop's first knee is
    the dead band's vertical (T1 at the first grid samples); with the band out T1 is a knee of the teeth, and the
    band stays in the lost motion."""
    import warnings
    from strainwave.analytic.mesh_drive import design_from_params
    from strainwave.compare.diagnose.drive_baseline import drive_series_flexibility_rad_per_Nmm
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = load_params()
    A = 1e-3 * p.gear.rated_output_torque_Nmm
    c = dc.predict_curve(design_from_params(p), drive_series_flexibility_rad_per_Nmm(p), A, with_te=False, exact=True)
    lo, hi = c.dead_band_rad
    assert lo < 0.0 < hi
    raw = dc.read_catalogue_numbers(c.loop_torque_Nm, c.loop_twist_rad, A)
    step = A / dc.READ_STEPS_PER_LEG
    assert raw["T1"][0] < 2.0 * step < 0.02 * A < c.T1_Nm and c.K1_Nm_per_rad > 5.0 * raw["K1"][0]
    assert c.lost_motion_rad > hi - lo
