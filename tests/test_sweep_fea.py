"""``strainwave sweep shaft-torsion`` end to end with the real FEA study (quick meshes, 2 workers).

The uncracked hollow shaft has an exact Saint-Venant answer, so the table's numbers can be checked:
FEA uses G = E/(2(1+nu)) = 80769 MPa, the seed's closed forms mu = 8e4 MPa (formula audit 18).
"""
import json
import math

import dask
import pandas as pd
import pytest
from distributed import LocalCluster

from strainwave.compare.sweep.pipeline import run_sweep

D, L, MU, E, NU = 70.0, 60.0, 8.0e4, 2.1e5, 0.3   # a short shaft (--params) keeps the meshes small
G = E / (2 * (1 + NU))
Q = "flexibility_rad_per_Nmm"


@pytest.mark.heavy
def test_shaft_torsion_sweep_with_closed_forms_beside(tmp_path):
    out = tmp_path / "sweep"
    short = tmp_path / "short.toml"
    short.write_text(f"[output_shaft]\nlength_mm = {L}\n")
    # (a bore wider than the shaft is refused with the whole grid before any worker starts: test_sweep.py)
    vary = ["output_shaft.inner_diameter_mm=40,50"]
    # an already running 2-worker cluster reached by address: the --scheduler path (test_sweep.py's resume
    # test covers the embedded default LocalCluster)
    scratch = str(tmp_path / "scratch")   # not /tmp/dask-scratch-space (issue 16 item 26)
    with dask.config.set({"temporary-directory": scratch}), \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                         local_directory=scratch) as cluster, \
            pytest.warns(UserWarning):      # the default's E, nu and mu disagree (formula audit 18)
        outcome = run_sweep("shaft-torsion", vary=vary, scheduler=cluster.scheduler_address, params_path=short,
                            out_dir=out, quick=True, tolerance=0.05)
    assert (outcome.n_points, outcome.n_ok, outcome.n_failed, outcome.workers) == (2, 2, 0, 2)

    frame = pd.read_parquet(out / "sweep.parquet")
    assert len(frame) == 2       # one row per (point, quantity): two solved points
    for column in ("point", "status", "error", "cached", "elapsed_s", "dofs", "output_shaft.inner_diameter_mm",
                   "quantity", "unit", "fea", "fea_uncertainty", "analytic_key", "published", "published_rel_error",
                   "corrected", "corrected_rel_error"):
        assert column in frame.columns
    assert pd.read_csv(out / "sweep.csv").shape == frame.shape
    rows = frame[frame["quantity"] == Q].set_index("output_shaft.inner_diameter_mm")
    assert list(rows.index) == [40.0, 50.0]
    for d in (40.0, 50.0):
        exact = 32 * L / (math.pi * G * (D ** 4 - d ** 4))
        # quick P2 meshes of a circular tube: the GCI is ~1e-4 relative; 1e-3 leaves margin for coarse meshes
        assert rows.loc[d, "fea"] == pytest.approx(exact, rel=1e-3)
        # corrected = the closed form validate asserts (with the bore, G = E/2(1+nu), the problem the FEA
        # solves): the relative error (fea - ref)/|ref|, validate's sign, is the discretization error only
        assert rows.loc[d, "corrected"] == pytest.approx(exact, rel=1e-12)
        assert rows.loc[d, "corrected_rel_error"] == pytest.approx(0.0, abs=1e-3)
        # published (solid bar, 0.1 for pi/32) ignores the bore: 11 % (d = 40) to 30 % (d = 50) below the FEA
        published = L / (0.1 * MU * D ** 4)
        assert rows.loc[d, "published"] == pytest.approx(published, rel=1e-12)
        assert rows.loc[d, "published_rel_error"] == pytest.approx(exact / published - 1, abs=1e-3)
    assert rows.loc[40.0, "dofs"] > 1000

    summary = (out / "summary.md").read_text()
    assert f"{Q}: published departs by more than 0.05 at 2/2 points" in summary
    assert f"{Q}: corrected within 0.05 of FEA at all 2 points" in summary
    assert (out / "plots" / f"{Q}__vs__output_shaft_inner_diameter_mm.png").stat().st_size > 10_000
    assert len(json.loads((out / "points.json").read_text())) == 2

    with pytest.warns(UserWarning):
        again = run_sweep("shaft-torsion", vary=vary, params_path=short, out_dir=out, quick=True)
    # everything comes from the cache: no cluster is started at all
    assert (again.n_points, again.n_ok, again.n_cached, again.workers) == (2, 2, 2, 0)
    assert pd.read_parquet(out / "sweep.parquet")["fea"].equals(frame["fea"])


@pytest.mark.heavy
def test_shaft_crack_depth_sweep_seeds_the_shafts_own_crack(tmp_path):
    """Sweeping output_shaft.crack_depth_mm meshes the shaft's crack at each depth, bounded by the shaft's
    own 12.5 mm wall (not the cup's 2.24 mm, issue 11): every point is good and the flexibility rises."""
    short = tmp_path / "short.toml"
    short.write_text(f"[output_shaft]\nlength_mm = {L}\n")
    with pytest.warns(UserWarning):
        outcome = run_sweep("shaft-torsion", vary=["output_shaft.crack_depth_mm=1:5:3"], params_path=short,
                            out_dir=tmp_path / "sweep", quick=True, workers=2)
    assert (outcome.n_points, outcome.n_ok) == (3, 3)
    frame = pd.read_parquet(tmp_path / "sweep" / "sweep.parquet")
    cracked = frame[frame["quantity"] == "cracked_flexibility_rad_per_Nmm"].sort_values("output_shaft.crack_depth_mm")
    delta = frame[frame["quantity"] == "delta_flexibility_rad_per_Nmm"].sort_values("output_shaft.crack_depth_mm")
    assert list(cracked["output_shaft.crack_depth_mm"]) == [1.0, 3.0, 5.0]
    assert cracked["fea"].is_monotonic_increasing and delta["fea"].is_monotonic_increasing
    assert (delta["fea"] > 0).all()
    # the crack compliance has its closed form beside it (registry pairing shared with validate)
    assert delta["analytic_key"].eq("checks.shaft.crack_compliance").all() and delta["corrected"].notna().all()
