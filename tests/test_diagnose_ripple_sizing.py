"""`size-crack` on a stiffness ripple at twice the input angle: the flexspline's breathing-ripple curve (study
cup-surface-crack, in the diagnosis's amplitude terms) sizes a tooth-root crack or says that none can hold it, and
names the components that cannot. Synthetic curves here (closed forms), no FEA run."""
import math
from types import SimpleNamespace

import pytest

from strainwave.compare.diagnose import breathing_crack as bc
from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.crack_life import CrackLifeReport
from strainwave.compare.diagnose.crack_sizing import DeltaCurve, size_diagnosis
from strainwave.compare.diagnose.diagnosis import RankedEffect

DEPTHS = (0.1, 0.2, 0.4)        # mm, a tooth-root sweep's depths
LAMBDA = 1.0 / 4.0e7            # rad/(N*mm): a gear of K_HD = 40 kN*m/rad
CURVE_A, CURVE_P = 0.9, 1.5     # a ripple curve A a^P (% of K_HD, a in mm), inverse a = (r / A)^(1/P)


def _diagnosis(ripple: float, se: float, specimen: str = "gear"):
    effect = RankedEffect("stiffness_ripple", ("flexspline",), {bc.RIPPLE: (ripple, "%")}, 500.0, 1e-6,
                          errors={bc.RIPPLE: se})
    return SimpleNamespace(named=("stiffness_ripple",), effects=(effect,), specimen=specimen,
                           baseline=Baseline(LAMBDA, "rad/(N*mm)", 0.3, "given", {}))


def _power_curve(scale: float = 1.0) -> DeltaCurve:
    ripple = tuple(scale * CURVE_A * a ** CURVE_P for a in DEPTHS)
    return DeltaCurve(bc.TOOTH_ROOT, bc.RIPPLE_UNIT, DEPTHS, ripple, tuple(0.01 * r for r in ripple), 0.9, "power law")


def _tooth_root_curve() -> DeltaCurve:
    """A real tooth-root crack's size: delta lambda_f ~1e-16..1e-15 rad/(N*mm) open, a third of it shut."""
    open_ = [(d, 0.05 * d) for d in (8e-17, 3e-16, 1.3e-15)]
    shut = [(d / 3.0, 0.05 * d / 3.0) for d, _ in open_]
    return bc.ripple_curve(DEPTHS, open_, shut, LAMBDA, 0.9, "synthetic")


def test_the_ripple_curve_is_half_the_swing_between_the_open_and_the_shut_crack():
    """For delta << lambda the amplitude is 50 (delta_open - delta_shut) / lambda % (first order), its
    uncertainty the two GCIs' in quadrature on the same slope; the curve stays far below 1e-3 % of K_HD."""
    curve = _tooth_root_curve()
    for (d_o, u_o), r, u in zip([(8e-17, 4e-18), (3e-16, 1.5e-17), (1.3e-15, 6.5e-17)], curve.delta, curve.uncertainty):
        d_s, u_s = d_o / 3.0, u_o / 3.0
        assert r == pytest.approx(50.0 * (d_o - d_s) / LAMBDA, rel=1e-6)
        assert u == pytest.approx(50.0 * math.hypot(u_o, u_s) / LAMBDA, rel=1e-6)
    assert curve.delta[-1] < 1e-3          # far below a ripple a rig resolves (~0.1 %)
    # the check can fail: the peak-to-peak swing (twice the amplitude) is not what the diagnosis reads
    assert curve.delta[-1] != pytest.approx(100.0 * (1.3e-15 - 1.3e-15 / 3.0) / LAMBDA, rel=0.1)


def test_a_visible_ripple_is_no_tooth_root_crack_and_the_shaft_holds_none():
    """A 1.2 % ripple against a tooth-root curve of ~1e-4 %: neither the flexspline's tooth root nor the shaft
    can hold such a crack, and the record says so, component by component."""
    record = bc.size_ripple(_diagnosis(1.2, 0.05), ("shaft", "cup"), _tooth_root_curve)
    assert record["effect"] == "stiffness_ripple" and record["unit"] == bc.RIPPLE_UNIT
    sizes = {s["component"]: s for s in record["sizes"]}
    assert set(sizes) == {bc.TOOTH_ROOT, "shaft"}
    assert not sizes[bc.TOOTH_ROOT]["possible"] and "exceeds" in sizes[bc.TOOTH_ROOT]["reason"]
    assert not sizes["shaft"]["possible"]
    text = "\n".join(record["lines"])
    assert f"{bc.TOOTH_ROOT}: cannot hold such a crack" in text and "shaft: cannot hold such a crack" in text
    assert "no tooth-root crack in the wall can produce this ripple" in text


def test_a_ripple_on_the_curve_is_sized_within_its_interval():
    """A ripple the curve reaches is sized at the curve's closed-form inverse; on a curve twice as steep the
    same ripple is a shallower crack, outside that interval (the check can fail)."""
    ripple, se = 0.2, 0.004
    truth = (ripple / CURVE_A) ** (1 / CURVE_P)
    record = bc.size_ripple(_diagnosis(ripple, se), ("shaft", "cup"), _power_curve)
    size = record["_sizes"][0]
    assert size.component == bc.TOOTH_ROOT and size.possible
    assert size.depth_mm == pytest.approx(truth, rel=1e-6) and size.low_mm <= truth <= size.high_mm
    steep = bc.size_ripple(_diagnosis(ripple, se), ("shaft", "cup"), lambda: _power_curve(2.0))["_sizes"][0]
    assert not steep.low_mm <= truth <= steep.high_mm
    # an output shaft alone has no tooth root: nothing is read off the flexspline's curve
    shaft_only = bc.size_ripple(_diagnosis(ripple, se, "output_shaft"), ("shaft",), _power_curve)
    assert [s.component for s in shaft_only["_sizes"]] == ["shaft"]


def test_an_unresolved_ripple_sizes_nothing_and_solves_nothing():
    calls = []
    record = bc.size_ripple(_diagnosis(0.01, 0.02), ("shaft", "cup"), lambda: calls.append(1))
    assert record["sizes"] == [] and not calls and "not resolved" in record["lines"][0]


def test_size_crack_reports_the_ripple_through_the_flexspline_curve_solved_once_and_cached(params, tmp_path,
                                                                                          monkeypatch):
    """size_diagnosis on a ripple verdict runs study cup-surface-crack once (stubbed here with its result's
    shape) and reads it back from the cache the next time; the report names the ripple, not a compliance change."""
    from strainwave.analytic.seed000 import seed000_summary
    from strainwave.fea import studies
    from strainwave.fea.surface_crack import delta_name
    runs = []
    open_ = {a: d for a, d in zip(DEPTHS, (8e-17, 3e-16, 1.3e-15))}

    def run_study(study, p, **kw):
        runs.append(study)
        q = {delta_name(s, a): SimpleNamespace(value=d * f, uncertainty=0.05 * d * f)
             for a, d in open_.items() for s, f in (("major", 1.0), ("minor", 1.0 / 3.0))}
        return SimpleNamespace(quantities=q, meta={"cracks": {f"{a:g}": {} for a in DEPTHS}, "wall_mm": 0.9})

    monkeypatch.setattr(studies, "run_study", run_study)
    diag = _diagnosis(1.2, 0.05)
    first = size_diagnosis(diag, params, cache_dir=tmp_path)
    second = size_diagnosis(diag, params, cache_dir=tmp_path)
    assert runs == ["cup-surface-crack"]
    assert first["sizes"] == second["sizes"]
    lam = 1.0 / seed000_summary(params)["K_HD"]["corrected"]
    assert first["_curves"][0].delta[-1] == pytest.approx(50.0 * (1.3e-15 * 2.0 / 3.0) / lam, rel=1e-3)
    report = CrackLifeReport("rig.csv", "explained", diag.named, first, []).summary()
    assert "measured stiffness ripple at twice the input angle (amplitude) 1.2" in report
    assert "shaft: cannot hold such a crack" in report
