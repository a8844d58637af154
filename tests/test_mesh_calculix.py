"""CalculiX and strainwave on one frictional tooth-contact problem on the same P2 mesh (issue 48 item 8).

benchmarks/mesh_ccx_job.py: a sector of the cup's toothed rim (bore clamped), one rigid flat punch per
+theta-flank pair of a lobe at the study's unloaded clearances, mu = the study's. strainwave's band-load
compliance and contact solve give the twist at the lobe's rated torque and, after the reversal, at half of it;
CalculiX (CPE6, node-to-surface contact, *FRICTION) runs the same twists in two steps. The issue's goal (peak
share within 2 %) is NOT met (decision 069-ccx48: +8.1 % on this mesh, +4.5 % on the study's finest; the tip flank's
contact is stiffer in CalculiX); the bench prints it as a MISS. What this test guards is the measured state: the
same teeth in contact, the peak share within 10 % (a regression bound set after the measurement, not a goal),
friction inside Coulomb's cone (the loaded flanks and the lobe); and a reference with the lobe's upper
clearances x1.2 or x0.8 fails that bound.
Like tests/test_calculix.py, a missing ccx fails under CI (.ci/run installs it) and skips elsewhere only when
it cannot be installed.
"""
from __future__ import annotations

import os
import warnings
from dataclasses import replace

import numpy as np
import pytest
from conftest import benchmark_module

H_OVER_M = 0.42      # the study's quick finest mesh: ccx ~20 s; the bench runs the full finest (0.30)
REGRESSION_REL = 0.10   # the measured gap (+8.1 % / +5.8 % at 0.42 m) with room; NOT the 2 % goal
UNLOAD_TO = 0.5


@pytest.fixture(scope="module")
def jobs():
    with benchmark_module("calculix_job") as cj, benchmark_module("mesh_ccx_job") as mj:
        if cj.ensure_ccx() is None:
            if os.environ.get("CI"):   # .ci/run installs calculix-ccx: missing there is a broken set-up
                pytest.fail("ccx is not installed although .ci/run installs it")
            pytest.skip("ccx is not installed and cannot be installed here (not root or no apt-get)")
        yield cj, mj


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # the seed's E/nu vs mu warning
        return load_params()


@pytest.fixture(scope="module")
def solved(jobs, params, tmp_path_factory):
    _, mj = jobs
    problem, pairs = mj.problem_for(params, H_OVER_M * params.flexspline_cup.module_mm)
    sw = mj.strainwave_solve(problem, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    ccx = mj.run_calculix(problem, params, [sw["twist_rad"], sw["unloaded"]["twist_rad"]],
                          tmp_path_factory.mktemp("mesh-ccx"))
    return problem, pairs, sw, ccx


@pytest.mark.heavy
@pytest.mark.parametrize("step", [0, 1], ids=["first-loading", "after-reversal"])
def test_calculix_carries_the_same_tooth_shares(jobs, solved, step):
    _, mj = jobs
    problem, pairs, sw, ccx = solved
    ref, got = (sw, sw["unloaded"])[step], ccx["steps"][step]
    ag = mj.agreement(ref, got, REGRESSION_REL)
    assert ag["teeth_in_contact"][0] == ag["teeth_in_contact"][1] >= 2
    assert abs(ag["peak_share_rel"]) <= REGRESSION_REL, ag
    assert ag["passes"]
    assert np.argmax(ref["share"]) == np.argmax(got["share"])          # the same tooth carries the most
    assert np.array_equal(ref["forces_N"] > 0, got["forces_N"] > 1e-3 * got["forces_N"].max())
    # first principles: flank loads push, and friction stays inside Coulomb's cone (|tangential| <= mu N)
    assert np.all(got["forces_N"] > -1e-6 * got["forces_N"].max())
    mu = problem.system.friction_coefficient
    # per flank on the flanks with >= 10 % of the load (after the reversal the 3 % flank's penalty friction exceeds
    # mu N by 29 %: decision 069-ccx48), and over the lobe
    big = got["share"] >= 0.10
    assert np.all(np.abs(got["tangential_N"][big]) <= 1.01 * mu * got["forces_N"][big])
    assert abs(got["tangential_N"].sum()) <= mu * got["forces_N"].sum()


@pytest.mark.heavy
@pytest.mark.parametrize("factor", [1.2, 0.8])
def test_a_perturbed_reference_fails(jobs, solved, factor):
    """strainwave's reference with the clearances of the tip-side pairs (the upper half of the lobe) scaled by
    ``factor`` no longer matches CalculiX's unperturbed problem."""
    _, mj = jobs
    problem, pairs, sw, ccx = solved
    c = problem.system.clearance_mm.copy()
    upper = problem.teeth > np.median(problem.teeth)
    c[upper] *= factor
    perturbed = replace(problem, system=replace(problem.system, clearance_mm=c))
    bad = mj.strainwave_solve(perturbed, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    assert not mj.agreement(bad, ccx["steps"][0], REGRESSION_REL)["passes"]
    assert not mj.agreement(bad["unloaded"], ccx["steps"][1], REGRESSION_REL)["passes"]


def test_the_deck_is_the_problem(jobs, params, tmp_path):
    """Cheap, without ccx: the punches sit at the clearances along the flank normals, every flank has its slave
    faces, the nodes are the sector's P2 dofs and the gaps close at the base radius' rate."""
    _, mj = jobs
    pairs = mj.pairs_for(params)
    problem = mj.build(params, pairs, 0.6 * params.flexspline_cup.module_mm)
    info = mj.write_deck(tmp_path / "d.inp", problem, params, 1e-4)
    face = info["punch_xy"][:, :2].mean(axis=1)
    gap = np.einsum("ij,ij->i", face - problem.point_mm, problem.normal)
    assert gap == pytest.approx(problem.clearance_mm, rel=1e-9, abs=1e-12)
    text = (tmp_path / "d.inp").read_text()
    assert text.count("*CONTACT PAIR") == problem.teeth.size
    assert text.count("TYPE=CPE6") == 1 and "*FRICTION" in text
    from strainwave.geometry.mesh_geometry import mesh_geometry
    # an involute's normal is tangent to the base circle; the mesh's straight facets tilt it by < 2 %
    assert problem.system.lever_mm == pytest.approx(mesh_geometry(params).fs.base_radius_mm, rel=0.02)
