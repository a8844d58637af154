"""One sweep point without a cluster: the closed forms put beside FEA quantities, caching, refused points."""
import json
import math

import pytest

from strainwave.compare.sweep.task import PointSpec, analytic_beside, closed_form_probe, point_key, run_point
from strainwave.params import default_dict, load_params

# the default output shaft: D = 70 mm, d = 45 mm, L = 200 mm, mu = 8e4 MPa
D, d, L, MU = 70.0, 45.0, 200.0, 8.0e4


@pytest.fixture(scope="module")
def params():
    with pytest.warns(UserWarning):     # the default's E, nu, mu disagree by 0.96 % (formula audit 18)
        return load_params()


def test_shaft_flexibility_beside_fea(params):
    beside = analytic_beside("shaft-torsion", params, ["flexibility_rad_per_Nmm", "not_a_closed_form"])
    assert list(beside) == ["flexibility_rad_per_Nmm"]
    entry = beside["flexibility_rad_per_Nmm"]
    assert entry["key"] == "checks.shaft.flexibility"
    # Seed 000 lambda_so0 as printed (solid bar, 0.1 for pi/32), and validate's asserted form: with the bore and
    # G = E/2(1+nu) as the FEA (the sweep stands validate's closed form beside the FEA); 1e-12: float rounding only
    G = params.material.youngs_modulus_MPa / (2 * (1 + params.material.poisson_ratio))
    assert entry["published"] == pytest.approx(L / (0.1 * MU * D ** 4), rel=1e-12)
    assert entry["corrected"] == pytest.approx(32 * L / (math.pi * G * (D ** 4 - d ** 4)), rel=1e-12)


def test_cup_crack_closed_forms_use_unit_load_factors(params):
    name = "delta_flexibility_rad_per_Nmm"
    a = params.crack_depth_mm("flexspline_cup.root_crack_depth_mm")
    static = analytic_beside("cup-torsion", params, [name], crack_depth_mm=a)[name]
    assert analytic_beside("cup-torsion", params, [name])[name]["corrected"] is None   # uncracked: no crack form
    from strainwave.analytic.summary import analytic_summary
    loaded = analytic_summary(params)["checks"]["cup.crack_compliance"]
    # published K_u K_d a^2/(2 pi E r_m^4 delta) with K_u K_d = 1.32 removed; corrected (validate's, both tips of
    # the through crack) is that same a^2/(2 pi ...) form midway between plane stress and plane strain (issue 50)
    nu = params.material.poisson_ratio
    assert static["published"] == pytest.approx(loaded["published"] / 1.32, rel=1e-9)
    assert static["corrected"] == pytest.approx((1 - nu ** 2 / 2) * loaded["published"] / 1.32, rel=1e-9)


def test_ring_closed_forms_scaled_to_the_fea_force(params):
    from strainwave.analytic.summary import analytic_summary
    names = ["delta_cd_mm", "sigma_D_outer_MPa"]
    force = analytic_summary(params)["checks"]["ring.delta_cd"]["force_N"]     # the thin-ring force for W0
    at_reference = analytic_beside("ring-compression", params, names, force)
    # a closed form given at a force has no value at a point that states none (never a default force)
    assert analytic_beside("ring-compression", params, names)["delta_cd_mm"]["published"] is None
    # the ring states its force as its typed load; the point passes that force
    doubled = analytic_beside("ring-compression", params, names, 2 * 33.75948626096924)
    # linear elasticity: twice the force, twice the deflection (1e-6: the force is typed rounded); the stresses,
    # which the study reports at the prescribed W0 as validate compares them, do not move with the force
    assert at_reference["delta_cd_mm"]["published"] == pytest.approx(2.0, rel=1e-12)   # W0 = 1 mm -> 2 W0
    assert doubled["delta_cd_mm"]["published"] == pytest.approx(4.0, rel=1e-6)
    assert doubled["sigma_D_outer_MPa"]["corrected"] == at_reference["sigma_D_outer_MPa"]["corrected"]


def test_point_is_cached_and_refusals_are_recorded(tmp_path):
    base = default_dict()
    spec = PointSpec("shaft-torsion", (("output_shaft.inner_diameter_mm", 50.0),), base)
    key = point_key(spec, closed_form_probe)
    first = run_point(spec, key, str(tmp_path), closed_form_probe)
    assert first["status"] == "ok" and first["cached"] is False
    value = first["fea"]["probe_shaft_compliance_rad_per_Nmm"]["value"]
    assert value == pytest.approx(32 * L / (math.pi * MU * (D ** 4 - 50.0 ** 4)), rel=1e-12)
    again = run_point(spec, key, str(tmp_path), closed_form_probe)
    assert again["cached"] is True and again["computed_at"] == first["computed_at"]

    bad = PointSpec("shaft-torsion", (("output_shaft.crack_depth_mm", 12.5),), base)   # the wall is (70 - 45)/2 = 12.5 mm
    record = run_point(bad, point_key(bad, closed_form_probe), str(tmp_path), closed_form_probe)
    assert record["status"] == "failed" and record["fea"] == {}
    assert "output_shaft.crack_depth_mm = 12.5" in record["error"] and "output_shaft wall" in record["error"]
    stored = json.loads((tmp_path / f"{point_key(bad, closed_form_probe)}.json").read_text())
    assert stored["error"] == record["error"]   # a deterministic refusal is cached like a result


def _flexibility_in(unit):
    def task(study, params, quick):
        return {"quantities": {"flexibility_rad_per_Nmm": {"value": 1.3e-9, "unit": unit, "uncertainty": None}},
                "mesh": None}
    return task


def test_closed_forms_only_beside_quantities_in_the_same_unit(tmp_path):
    spec = PointSpec("shaft-torsion", (("output_shaft.length_mm", 200.0),), default_dict())
    same = run_point(spec, "same", str(tmp_path), _flexibility_in("rad/(N mm)"))     # spelling differs only
    entry = same["analytic"]["flexibility_rad_per_Nmm"]
    G = 2.1e5 / (2 * 1.3)     # validate's asserted form: G = E/2(1+nu) as the FEA
    assert entry["corrected"] == pytest.approx(32 * L / (math.pi * G * (D ** 4 - d ** 4)), rel=1e-12)
    other = run_point(spec, "other", str(tmp_path), _flexibility_in("deg/(N*m)"))
    assert other["analytic"]["flexibility_rad_per_Nmm"]["corrected"] is None
    assert any("not compared" in w for w in other["warnings"])


@pytest.mark.heavy
def test_uncracked_shaft_point_imports_no_build123d(tmp_path):
    """A worker solving uncracked shaft points never pays build123d's import (~2.3 s of its start): the shaft
    it meshes is a bare OCC solid. Run in a fresh interpreter, since this one may have imported it already."""
    import subprocess
    import sys
    import textwrap

    script = textwrap.dedent(f"""
        import sys, warnings
        warnings.simplefilter("ignore")
        from strainwave.compare.sweep.task import PointSpec, point_key, run_point
        from strainwave.params import load_params
        spec = PointSpec("shaft-torsion", (("output_shaft.length_mm", 60.0),), load_params().to_dict(), True)
        record = run_point(spec, point_key(spec, None), {str(tmp_path)!r})
        print(record["status"], "build123d" in sys.modules)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.stdout.split() == ["ok", "False"], done.stderr
