"""CalculiX and strainwave on one frictional tooth-contact problem on the same P2 mesh (issue 48 item 8).

Two comparisons on a sector of the cup's toothed rim (bore clamped), one rigid punch per +theta-flank pair of a
lobe at the study's unloaded clearances, mu = the study's, the lobe's rated torque then back down to half of it:

- **The band contact** (benchmarks/mesh_ccx_band.py, decision 070-ccx2pct48): CalculiX is handed strainwave's band
  (a reference node per flank tied to the band by *EQUATION, node-to-surface frictional contact on the punch), and
  strainwave solves it with friction on the true slip and its load on the teeth (fea/mesh_friction.py): ONE discrete
  problem. Bound: the issue's goal, 2 % on the peak tooth share (measured +0.34 % / +0.50 % on this mesh; decision
  070's tighter 0.5 % prediction, fixed before, was missed by 0.005 points after the reversal: the stick of a
  flank in the increment where it closes, said there); a reference with the lobe's upper clearances x1.2 / x0.8
  (-28 % / +26 %) fails it.
  The -T leg: both flanks of the lobe along 0 -> +T -> -T -> +T on the 0.60 m mesh, the same 2 % at every step.
- **The geometric contact** (benchmarks/mesh_ccx_job.py, decision 069-ccx48): a rigid flat punch on the flank
  facets against the study's band and torque-only friction: two different problems; a 10 % regression bound set
  after that measurement (not the goal).
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
REGRESSION_REL = 0.10   # the geometric contact's measured gap (+8.1 % / +5.8 % at 0.42 m) with room; NOT the goal
BAND_REL = 0.02         # the band problem: the goal (decision 070-ccx2pct48; its 0.5 % prediction missed once)
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
def band():
    with benchmark_module("mesh_ccx_band") as mb:
        yield mb


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


@pytest.fixture(scope="module")
def band_solved(jobs, band, params, tmp_path_factory):
    _, mj = jobs
    m = params.flexspline_cup.module_mm
    problem, pairs = mj.problem_for(params, H_OVER_M * m, on_involute=True)
    sw = band.strainwave_true_slip(problem, m, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    ccx = band.run_band(problem, params, [sw["twist_rad"], sw["unloaded"]["twist_rad"]],
                        tmp_path_factory.mktemp("mesh-ccx-band"))
    return problem, pairs, sw, ccx


@pytest.mark.heavy
@pytest.mark.parametrize("step", [0, 1], ids=["first-loading", "after-reversal"])
def test_calculix_solves_the_same_band_problem(jobs, band_solved, step):
    """The issue's comparison on one discrete problem: the peak share within 2 %, the same teeth and the same
    most-loaded tooth, each flank's load within 2 % of the largest, and Coulomb's state the same: where
    strainwave's flank slips CalculiX's friction sits on the cone (|Q| = mu N), where it sticks inside it."""
    _, mj = jobs
    problem, pairs, sw, ccx = band_solved
    ref, got = (sw, sw["unloaded"])[step], ccx["steps"][step]
    ag = mj.agreement(ref, got, BAND_REL)
    assert abs(ag["peak_share_rel"]) <= BAND_REL and ag["passes"], ag
    assert np.argmax(ref["share"]) == np.argmax(got["share"])
    assert np.abs(got["forces_N"] - ref["forces_N"]).max() <= BAND_REL * ref["forces_N"].max()
    mu, q = problem.system.friction_coefficient, -got["tangential_N"]     # q: CalculiX's friction on the flank
    loaded = ref["forces_N"] >= 0.05 * ref["forces_N"].max()
    slips = loaded & ~ref["stick"]
    assert slips.any()      # loading: the tip flank slips; after the reversal tooth -11 slides back
    assert np.abs(q[slips]) == pytest.approx(mu * got["forces_N"][slips], rel=0.01)
    assert np.all(np.sign(q[slips]) == np.sign(ref["tangential_N"][slips]))
    assert np.all(np.abs(q[loaded & ref["stick"]]) < mu * got["forces_N"][loaded & ref["stick"]])


@pytest.mark.heavy
@pytest.mark.parametrize("factor", [1.2, 0.8])
def test_a_perturbed_reference_fails_the_band_bound(jobs, band, band_solved, params, factor):
    """strainwave's true-slip answer with the lobe's upper clearances x factor misses CalculiX's unperturbed
    answer by more than the 2 % bound, at both steps."""
    _, mj = jobs
    problem, pairs, sw, ccx = band_solved
    c = problem.system.clearance_mm.copy()
    c[problem.teeth > np.median(problem.teeth)] *= factor
    perturbed = replace(problem, clearance_mm=c, system=replace(problem.system, clearance_mm=c))
    bad = band.strainwave_true_slip(perturbed, params.flexspline_cup.module_mm, pairs["torque_Nmm"],
                                    unload_to=UNLOAD_TO)
    assert not mj.agreement(bad, ccx["steps"][0], BAND_REL)["passes"]
    assert not mj.agreement(bad["unloaded"], ccx["steps"][1], BAND_REL)["passes"]


def test_the_band_deck_is_strainwaves_band(jobs, band, params, tmp_path):
    """Cheap, without ccx: each reference node's *EQUATION reads strainwave's band, -n . u_R = f . u and
    t . u_R = g . u for any displacement u, so the node's contact force reaches the tooth as strainwave's load."""
    _, mj = jobs
    m = params.flexspline_cup.module_mm
    problem = mj.build(params, mj.pairs_for(params), 0.6 * m, on_involute=True)
    info = band.write_band_deck(tmp_path / "b.inp", problem, params, 1e-4)
    lines = (tmp_path / "b.inp").read_text().splitlines()
    F, G = band.band_vectors(problem, m)
    ndof = F.shape[0]
    E = {}
    for k, line in enumerate(lines):
        if line == "*EQUATION":
            nterms, terms, j = int(lines[k + 1]), [], k + 2
            while len(terms) < nterms:
                v = lines[j].split(",")
                terms += [(int(v[i]), int(v[i + 1]), float(v[i + 2])) for i in range(0, len(v), 3)]
                j += 1
            row = np.zeros(ndof)
            for nd, dof, c in terms[1:]:
                row[2 * (nd - 1) + dof - 1] = -c
            E[(terms[0][0], terms[0][1])] = row
    assert len(E) == 2 * problem.teeth.size
    u = np.random.default_rng(0).normal(size=ndof)
    t = np.column_stack([-problem.normal[:, 1], problem.normal[:, 0]])
    for k, rid in enumerate(info["ref_nodes"].tolist()):
        uR = np.array([E[(rid, 1)] @ u, E[(rid, 2)] @ u])
        assert -problem.normal[k] @ uR == pytest.approx(F[:, k] @ u, rel=1e-9)
        assert t[k] @ uR == pytest.approx(G[:, k] @ u, rel=1e-9)


@pytest.fixture(scope="module")
def loop_solved(jobs, band, params, tmp_path_factory):
    """Both flanks of the lobe along the study's load 0 -> +T -> -T -> +T, on the coarse 0.60 m mesh (CalculiX
    ~1 min): the -T leg."""
    _, mj = jobs
    m = params.flexspline_cup.module_mm
    problem, pairs = mj.problem_for(params, 0.60 * m, on_involute=True, sides=(1, -1))
    T = pairs["torque_Nmm"]
    legs = band.strainwave_true_slip_path(problem, m, [T, -T, T])
    ccx = band.run_band(problem, params, [r["twist_rad"] for r in legs], tmp_path_factory.mktemp("mesh-ccx-loop"))
    return problem, pairs, legs, ccx


@pytest.mark.heavy
def test_the_minus_T_leg_agrees_and_a_perturbed_reference_fails(jobs, band, loop_solved, params):
    """At +T, -T and +T again the peak share within the issue's 2 % with the same teeth (the -T leg loads the
    -theta flanks only); strainwave with the -theta flanks' upper clearances x1.2 misses CalculiX at -T."""
    _, mj = jobs
    problem, pairs, legs, ccx = loop_solved
    for k, (ref, got) in enumerate(zip(legs, ccx["steps"])):
        ag = mj.agreement(ref, got, BAND_REL)
        assert ag["passes"], (k, ag)
        assert np.all(problem.side[ref["forces_N"] > 0] == (-1 if k == 1 else 1))
    c = problem.clearance_mm.copy()
    minus = problem.side == -1
    c[minus & (problem.teeth > np.median(problem.teeth[minus]))] *= 1.2
    bad_problem = replace(problem, clearance_mm=c, system=replace(problem.system, clearance_mm=c))
    T = pairs["torque_Nmm"]
    bad = band.strainwave_true_slip_path(bad_problem, params.flexspline_cup.module_mm, [T, -T, T])
    assert not mj.agreement(bad[1], ccx["steps"][1], BAND_REL)["passes"]


@pytest.fixture(scope="module")
def study_solved(jobs, band, params, tmp_path_factory):
    """The tooth-mesh STUDY's own friction solve on the band problem (decision 073-slipstudy48: mesh_friction's
    torque_path, the study's 40 torque steps and increments), CalculiX run at its twists."""
    _, mj = jobs
    m = params.flexspline_cup.module_mm
    problem, pairs = mj.problem_for(params, H_OVER_M * m, on_involute=True)
    sw = band.strainwave_study_path(problem, m, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    ccx = band.run_band(problem, params, [sw["twist_rad"], sw["unloaded"]["twist_rad"]],
                        tmp_path_factory.mktemp("mesh-ccx-study"))
    return problem, pairs, sw, ccx


@pytest.mark.heavy
@pytest.mark.parametrize("step", [0, 1], ids=["first-loading", "after-reversal"])
def test_the_study_solve_carries_calculix_tooth_shares(jobs, study_solved, step):
    """Issue 48 item 8 for the study's own solve: its peak share within 2 % of CalculiX's on the same band problem,
    the same most-loaded tooth."""
    _, mj = jobs
    problem, pairs, sw, ccx = study_solved
    ref, got = (sw, sw["unloaded"])[step], ccx["steps"][step]
    ag = mj.agreement(ref, got, BAND_REL)
    assert abs(ag["peak_share_rel"]) <= BAND_REL and ag["passes"], ag
    assert np.argmax(ref["share"]) == np.argmax(got["share"])
