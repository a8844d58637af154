"""The report's parts on their own (no FEA): GCI table flags, rated loads, failing-check lines, render set-up,
and the rated-load lines of ``strainwave solve`` on a coarse shaft."""
from __future__ import annotations

import math
import os
import subprocess
import sys

import pytest

from strainwave.compare.validate.gci_table import asymptotic_flags, formal_order, gci_rows
from strainwave.compare.validate.report_text import failing_line
from strainwave.fea.convergence import grid_convergence
from strainwave.fea.refinement import CRACK_FORMAL_ORDER
from strainwave.params import load_params

H = (1.0, 1.4, 1.96)


def _series(f_exact: float, c: float, p: float):
    return [f_exact + c * h ** p for h in H]


def test_a_clean_second_order_series_is_asymptotic_for_p2_stresses_only():
    conv = grid_convergence(H, _series(10.0, 0.1, 2.0), formal_order=2.0)
    assert conv.observed_order == pytest.approx(2.0, abs=1e-6)
    assert asymptotic_flags(conv) == () and conv.basis == "observed p = 2, Fs = 1.25"
    # the same p is above what P1 stresses (formal order 1) can reach: error cancellation, flagged, formal p, Fs 3
    p1 = grid_convergence(H, _series(10.0, 0.1, 2.0), formal_order=1.0)
    assert asymptotic_flags(p1) == ("p outside formal 1 +-10 %",) and p1.basis == "formal p = 1, Fs = 3"


def test_a_refused_gci_is_flagged_with_its_own_reason():
    from strainwave.fea.convergence import Convergence
    same = Convergence.refusal(H, [2.0, 2.0, 2.0], "three identical values (2.0) ...")
    step = Convergence.refusal(H, [1.0, 1.1, 1.3], "follows the torque step, not the mesh")
    assert asymptotic_flags(same) == ("identical values: GCI refused",)
    assert asymptotic_flags(step) == ("GCI refused: follows the torque step, not the mesh",)
    assert math.isnan(step.gci_fine) and step.values == (1.0, 1.1, 1.3)


@pytest.mark.parametrize("values, flag, order_used", [
    ([1.0, 1.02, 0.99], "non-monotone", 4.0),          # the differences change sign
    (_series(5.0, 0.3, 0.5), "p outside formal 4 +-10 %", 0.5),   # slower than formal: its own 0.5
    (_series(5.0, 0.3, 6.0), "p outside formal 4 +-10 %", 4.0),
    ([1.0, 1.03, 1.04], "diverging", 0.5),             # p < 0: never below 0.5
])
def test_non_asymptotic_series_are_flagged(values, flag, order_used):
    conv = grid_convergence(H, values, formal_order=4.0)
    assert flag in asymptotic_flags(conv)
    # Fs 3 with min(max(0.5, p_observed), p_formal) (Oberkampf & Roy)
    assert conv.safety_factor == 3.0 and conv.order_used == pytest.approx(order_used)


def test_a_crack_delta_shows_its_observed_order_beside_the_formal_one_it_uses():
    conv = grid_convergence(H, _series(1.0, 0.05, 1.7), formal_order=CRACK_FORMAL_ORDER)
    assert conv.observed_order == pytest.approx(1.7, rel=1e-6) and conv.order_used == 1.0
    assert asymptotic_flags(conv) == ("p outside formal 1 +-10 %",)


def test_non_monotone_series_keeps_the_fine_value_and_says_so():
    conv = grid_convergence(H, [2.0, 2.1, 1.9])
    assert set(asymptotic_flags(conv)) >= {"non-monotone", "f_ext = f1"}


def test_formal_orders_follow_the_quantity_kind():
    assert formal_order("flexibility_rad_per_Nmm", "rad/(N*mm)", 2) == (4.0, "energy")
    assert formal_order("delta_flexibility_rad_per_Nmm", "rad/(N*mm)", 2) == (1.0, "crack compliance")
    assert formal_order("sigma_D_outer_MPa", "MPa", 2) == (2.0, "stress")
    assert formal_order("delta_cd_mm", "mm", 2) == (3.0, "displacement")


def test_gci_rows_read_every_convergence_record_of_the_book():
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.runner import Case, CaseOutcome
    from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support

    q = {"a_mm": Quantity("a_mm", 1.0, "mm", grid_convergence(H, _series(1.0, 0.01, 3.0), formal_order=3.0)),
         "b_MPa": Quantity("b_MPa", 2.0, "MPa", grid_convergence(H, [2.0, 2.1, 1.9])),
         "none": Quantity("none", 3.0, "1")}
    result = StudyResult("ring-compression", q, MeshQuality(1, 1, 1, 2, 1.0, 1.0),
                         Load("diametral force F", 1.0, "N", ("contact",), "stand-in"), (Support(("A",), "stand-in"),))
    book = FeaBook({"ring": CaseOutcome(Case("ring", "ring-compression", None), result, 0.0, False)})
    rows = {r.quantity: r for r in gci_rows(book, order=2)}
    assert set(rows) == {"a_mm", "b_MPa"}            # a quantity without three meshes has no row
    assert rows["a_mm"].asymptotic and rows["a_mm"].r21 == pytest.approx(1.4)
    assert not rows["b_MPa"].asymptotic and "non-monotone" in rows["b_MPa"].flags


def test_rated_loads_follow_seed_000_from_the_rated_torque():
    from strainwave.rated_stress import rated_load

    params = load_params()
    g, d1 = params.gear, params.flexspline_cup.pitch_diameter_mm
    torque = rated_load("cup-torsion", params, g.output_torque_Nmm)
    assert torque.scale == g.rated_output_torque_Nmm / g.output_torque_Nmm
    # seed 000: F_r = 1.15 k_r T / d1 = 1.15 * 0.35 * 1e6 / 160 = 2515.625 N at the default rated torque
    bearing = rated_load("bearing-ring", params, 2.515625)
    assert bearing.rated == pytest.approx(1.15 * g.force_coefficient * g.rated_output_torque_Nmm / d1)
    assert bearing.rated == pytest.approx(2515.625) and bearing.scale == pytest.approx(1000.0)
    with pytest.raises(ValueError):
        rated_load("ring-compression", params, 30.0)      # its rated load needs the FEA's force for W0
    with pytest.raises(ValueError):
        rated_load("shaft-torsion", params, -1.0)


def test_rated_torque_is_a_validated_parameter():
    from strainwave.errors import InputError

    with pytest.raises(InputError, match="rated_output_torque_Nmm"):
        load_params(overrides={"gear": {"rated_output_torque_Nmm": 0.0}})


def _check(**over) -> dict:
    c = {"id": "cup.crack_compliance", "unit": "rad/(N*mm)", "fea": 2.595e-15, "fea_uncertainty": 2.38e-16,
         "analytic": {"published": 1.096e-14, "corrected": 5.48e-15}, "asserts": "corrected",
         "rel_error": {"published": -0.763, "corrected": -0.527}, "relation": "equal",
         "tolerance": {"relative": 0.275, "reason": "3 x GCI (9.18 %)"}, "verdict": "neither", "passed": False,
         "reason_not_evaluated": ""}
    c.update(over)
    return c


def test_a_failing_check_line_gives_the_numbers_and_the_reason():
    line = failing_line(_check())
    for text in ("2.595e-15 +/- 2.4e-16", "5.48e-15", "-52.7 %", "27.5 %", "3 x GCI (9.18 %)", "published 1.096e-14",
                 "Reason:", "neither form"):
        assert text in line, text
    assert failing_line(_check(verdict="not evaluated", reason_not_evaluated="case cup failed")) == \
        "not evaluated: case cup failed"


def test_plotters_leave_pyvista_and_the_environment_as_they_were():
    import pyvista as pv

    from strainwave.render import RenderSettings, off_screen_plotter

    env, flag = dict(os.environ), pv.OFF_SCREEN
    plotter = off_screen_plotter(RenderSettings((64, 48), shape=(1, 2)))
    try:
        assert plotter.off_screen and tuple(plotter.window_size) == (64, 48)
    finally:
        plotter.close()
    assert dict(os.environ) == env and pv.OFF_SCREEN == flag
    with pytest.raises(ValueError):
        RenderSettings((8, 8))


def test_solve_prints_the_peak_stress_and_safety_factor_at_the_rated_load():
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-m", "strainwave", "solve", "shaft-torsion", "--mesh-size-mm", "15"],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = proc.stdout
    assert "at the rated load: output torque T = 1e+06 N*mm" in out and "fields x 1000" in out
    peak = float(out.split("peak von Mises ")[1].split(" MPa")[0])
    # where: the outer fibre (r = 35 mm) at the clamped end, the named faces 'fixed' and 'outer'
    assert "mm on 'fixed', 'outer';" in out
    factor = float(out.split("fatigue limit 625 MPa: ")[1].split(" ")[0])
    # Saint-Venant at the rated torque: tau = T r_o / J on the outer fibre, von Mises sqrt(3) tau = 31.0 MPa; the
    # clamped end adds a few per cent on this coarse mesh (the peak sits there)
    r_o, r_i = 35.0, 22.5
    tau = 1e6 * r_o / (math.pi / 2 * (r_o ** 4 - r_i ** 4))
    assert peak == pytest.approx(math.sqrt(3) * tau, rel=0.08)
    assert factor == pytest.approx(625.0 / peak, rel=2e-3)


def test_convergence_plot_keeps_the_fea_on_its_own_scale_and_the_closed_forms_beside_it():
    from strainwave.compare.validate.plots import convergence_figure

    # the bearing case of the issue: FEA points near 0.05e-5 against a closed form at 1.59e-5
    values = [5.0e-7, 5.1e-7, 5.3e-7]
    fig = convergence_figure(title="t", unit="mm/N", h_mm=H, values=values, extrapolated=4.9e-7, gci_fine=0.02,
                             observed_order=2.0, analytic={"published": 1.59e-5, "corrected": 5.2e-7})
    fea_ax, cmp_ax = fig.axes[:2]
    low, high = fea_ax.get_ylim()
    assert high - low < 10 * (max(values) - min(values))          # not stretched to 1.59e-5
    assert cmp_ax.get_xlim()[1] >= 1.59e-5                          # the closed forms are on the second panel
    labels = " ".join(t.get_text() for t in cmp_ax.texts)
    assert "1.59e-05" in labels and "5.2e-07" in labels             # ... with their numbers


def test_rated_stress_sentence_and_row_name_every_number():
    from strainwave.compare.validate.report_text import rated_row, rated_sentence

    s = {"load": {"name": "output torque T", "unit": "N*mm", "rated": 1e6, "scale": 1000.0},
         "load_text": "output torque T = 1e+06 N*mm (chosen)", "peak_von_mises_MPa": 31.34,
         "peak_location_mm": [35.0, -8.6e-15, 0.0], "peak_on": ["fixed"], "peak_displacement_mm": 0.0443,
         "fatigue_limit_MPa": 625.0,
         "safety_factor": 19.94, "note": "material only"}
    assert rated_sentence(s) == ("at output torque T = 1e+06 N*mm (1000 N m): peak von Mises 31.34 MPa at (35, 0, 0) mm on "
                                 "'fixed', peak displacement 0.0443 mm, safety factor 19.9 against sigma_-1 = 625 MPa")
    row = rated_row("shaft", s)
    assert row[3] == "(35, 0, 0) on fixed" and row[6] == "19.9" and "fields x 1000" in row[1]
    assert not any("|" in cell for cell in row)   # a Markdown table cell


def test_convergence_plot_says_when_the_meshes_are_not_asymptotic():
    from strainwave.compare.validate.plots import convergence_figure

    conv = grid_convergence(H, [2.0633, 2.0385, 2.0400])          # ring.tooth_influence in --quick: non-monotone
    flags = asymptotic_flags(conv)
    fig = convergence_figure(title="t", unit="1", h_mm=H, values=conv.values, extrapolated=conv.extrapolated,
                             gci_fine=conv.gci_fine, observed_order=conv.observed_order, analytic={}, flags=flags)
    assert "not asymptotic: non-monotone" in fig.axes[0].get_title()
    clean = convergence_figure(title="t", unit="1", h_mm=H, values=_series(1.0, 0.01, 2.0), extrapolated=1.0,
                               gci_fine=0.01, observed_order=2.0, analytic={}, flags=())
    assert "not asymptotic" not in clean.axes[0].get_title()


def test_stress_pictures_are_shown_full_width_so_their_printed_numbers_stay_legible():
    from strainwave.compare.validate.report_html import _figure

    wide = _figure({"path": "images/ring_von_mises.png", "caption": "c", "kind": "stress", "component": "ring"})
    half = _figure({"path": "images/x.png", "caption": "c", "kind": "convergence", "component": "ring"})
    assert '<figure class="wide">' in wide and 'class="wide"' not in half


def test_shaft_crack_note_says_how_much_the_fit_matters_and_flags_a_depth_outside_the_confirmed_range():
    import warnings

    from strainwave.compare.validate.torsion_checks import shaft_form_note
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # the seed's E/nu/mu 0.96 % warning
        params = load_params()
    sh = params.output_shaft
    t = 0.5 * (sh.outer_diameter_mm - sh.inner_diameter_mm)
    shallow = shaft_form_note(params, 0.008 * t)
    assert "about 1: this depth hardly tests the fit" in shallow and "inside the form's confirmed range" in shallow
    deep = shaft_form_note(params, 0.8 * t)
    assert "outside its confirmed range" in deep and "about 1" not in deep


def test_sweep_rows_say_where_the_corrected_form_is_outside_its_range():
    from strainwave.compare.validate.report_text import SWEEP_COLUMNS, sweep_rows
    sweep = {"depths_mm": [1.0, 9.0], "fea": [1e-12, 1e-10], "fea_uncertainty": [1e-14, 1e-12],
             "resolved": [True, True], "analytic": {"published": [1e-12, 1e-10], "corrected": [1e-12, 1e-10]},
             "range_notes": ["", "thick-tube form used outside its confirmed range (d_i/d = 0.643, a/t = 0.8)"]}
    rows = sweep_rows(sweep)
    assert len(rows[0]) == len(SWEEP_COLUMNS)
    assert rows[0][-1] == "confirmed" and rows[1][-1].startswith("OUTSIDE: thick-tube form")
    assert sweep_rows({**sweep, "range_notes": []})[0][-1] == "-"
