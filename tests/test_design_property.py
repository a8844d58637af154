"""Issue 49 item 7: no internal error on any valid drive. Hypothesis draws geometrically consistent drives (the
bearing's rings and balls inside the flexspline's bore, a crack shallower than its ring) and runs the analytic
model, the design factors with their advice, and (heavy) the wave generator bearing study's coarse path with the
validate checks that read it. Anything but an InputError (exit 2, one line) is an internal error."""
import json
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.analytic import design_factors as df
from strainwave.analytic.summary import analytic_summary
from strainwave.errors import InputError
from strainwave.params import load_params

SECOND = "strainwave/data/second_gear.toml"


@st.composite
def drives(draw):
    """(gear file, overrides) of a drive whose bearing fits: D_w + t_o + t_i well inside the bore radius."""
    path = draw(st.sampled_from([None, SECOND]))
    d1 = 160.0 if path is None else 100.0
    bore = 0.5 * d1 - (2.24 if path is None else 1.4)
    ball = draw(st.floats(0.03, 0.12)) * bore
    outer = draw(st.floats(0.01, 0.06)) * bore
    inner = draw(st.floats(0.01, 0.15)) * bore
    over = {"wave_generator.ball_diameter_mm": ball, "wave_generator.outer_ring_thickness_mm": outer,
            "wave_generator.bearing_inner_ring_thickness_mm": inner,
            "wave_generator.bearing_crack_depth_mm": 0.1,
            "wave_generator.ball_count": draw(st.integers(8, 40)),
            "wave_generator.groove_radius_ratio": draw(st.floats(0.505, 0.58)),
            "gear.rated_output_torque_Nmm": draw(st.floats(1e4, 3e6)),
            "ewg_drive.flexspline_teeth": draw(st.integers(40, 300))}
    return path, over


def _params(path, over):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params(path).with_values(over)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(drive=drives())
def test_every_valid_drive_gets_finite_design_factors_or_a_one_line_refusal(drive):
    try:
        p = _params(*drive)
        summary = analytic_summary(p)
    except InputError as exc:
        assert "\n" not in str(exc)
        return
    json.dumps(summary, allow_nan=False)
    for f in df.closed_form_factors(p):
        row = f.row()
        assert row["n"] > 0 and row["static_n"] > 0
        if row["verdict"] != "PASS":
            assert row["advice"], f"{f.component} fails without advice"


@pytest.mark.heavy
@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(drive=drives())
def test_the_bearing_studys_coarse_path_and_its_checks_run_on_any_valid_drive(drive):
    from types import SimpleNamespace

    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.wg_bearing_checks import wg_bearing_checks
    from strainwave.fea.studies import run_study

    try:
        p = _params(*drive)
        t = p.wave_generator.bearing_inner_ring_thickness_mm
        result = run_study("wg-bearing", p, quick=True, mesh_size_mm=t / 3.0)
    except InputError:
        return
    book = FeaBook({"wg-bearing": SimpleNamespace(result=result, error=None, case=SimpleNamespace(study="wg-bearing"))})
    checks = wg_bearing_checks(book, "wg-bearing", p)
    assert len(checks) == 4 and all(c.verdict for c in checks)
