"""Study cup-surface-crack on a coarse mesh (the converged one runs in make validate): the open crack against
Newman-Raju, the shut crack adds nothing, and the checks fail on a perturbed closed form."""
from __future__ import annotations

import math
import warnings

import pytest

from strainwave.analytic import surface_crack as sc
from strainwave.fea.surface_crack import ASPECT


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


def _block(params, states=("major", "minor")):
    from strainwave.fea.surface_crack import block_for
    loads = sc.study_loads(params)
    m, t = params.material, params.flexspline_cup.wall_thickness_mm
    return block_for(t, 0.2 * t, ASPECT, m.youngs_modulus_MPa, m.poisson_ratio, loads["per_torque_MPa_per_Nmm"],
                     [s for s in loads["states"] if s[0] in states])


def test_open_crack_matches_newman_raju_and_the_shut_crack_adds_nothing(params, tmp_path):
    from strainwave.fea.surface_crack import _write_fields, solve_block
    block = _block(params)
    # coarse: global h = t/2, front a/3 (the study's finest is t/4 and a/12)
    r = solve_block(block, 0.5 * block.t_mm, 0.125 * block.t_mm, fields_of=("major", "minor"))
    major_vtu, minor_vtu = _write_fields(tmp_path / "block.vtu", block, r, params.material)
    assert (major_vtu.name, minor_vtu.name) == ("block_major.vtu", "block_minor.vtu")
    _check_open_crack_fields(major_vtu, block)
    major, minor = r.states["major"], r.states["minor"]
    ref = sc.delta_flexibility(block.a_mm, ASPECT, block.t_mm, sc.tooth_root_loads(params, 0.0),
                               block.E_MPa / (1 - block.nu ** 2), half_width_mm=block.half_width_mm)
    assert major.shut_fraction == 0.0
    assert major.delta_flexibility == pytest.approx(ref, rel=0.2)
    assert minor.shut_fraction > 0.5 and abs(minor.delta_flexibility) < 1e-6 * major.delta_flexibility


def _check_open_crack_fields(path, block):
    """The written field is the open crack at the major axis: the crack face lifts off (u_z > 0 across it, as
    its mirror moves the other way), the ligament stays on the symmetry plane, von Mises peaks at the front."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from strainwave.fea.fields import _read_grid
    grid = _read_grid(path)
    x = vtk_to_numpy(grid.GetPoints().GetData())
    u = vtk_to_numpy(grid.GetPointData().GetArray("displacement_mm"))
    vm = vtk_to_numpy(grid.GetPointData().GetArray("von_mises_MPa"))
    on_plane = np.abs(x[:, 2]) < 1e-9 * block.length_mm
    r = np.hypot(x[:, 0] / block.c_mm, x[:, 1] / block.a_mm)
    face, ligament = on_plane & (r < 0.9), on_plane & (r > 1.1)
    assert face.sum() > 10 and np.all(u[face, 2] > 0.0)
    assert np.abs(u[ligament, 2]).max() < 1e-9 * u[face, 2].max()
    peak = x[np.argmax(vm)]
    assert abs(np.hypot(peak[0] / block.c_mm, peak[1] / block.a_mm) - 1.0) < 0.5 and abs(peak[2]) < block.a_mm
    # the rated-stress summary finds the front (face and ligament share it) and leaves its singular zone out
    from strainwave.rated_stress import crack_front_nodes
    front = crack_front_nodes(path)
    assert front.size > 5 and np.allclose(r[front], 1.0, atol=1e-3) and np.all(on_plane[front])


def test_block_refuses_a_crack_outside_its_range(params):
    from strainwave.errors import InputError
    from strainwave.fea.surface_crack import block_for
    with pytest.raises(InputError, match="a/c"):
        block_for(2.0, 0.5, 1.5, 2e5, 0.3, 1e-5, ())
    with pytest.raises(InputError, match="depth"):
        block_for(2.0, 1.7, 0.5, 2e5, 0.3, 1e-5, ())


def _book(values: dict):
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.runner import Case, CaseOutcome
    from strainwave.fea.convergence import Convergence
    from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support
    q = {n: Quantity(n, v, "rad/(N*mm)", Convergence((1.0, 1.4, 1.96), (v, v * 0.99, v * 0.98), 1.0, v, 0.02, True))
         for n, v in values.items()}
    res = StudyResult("cup-surface-crack", q, MeshQuality(1, 1, 3, 2, 1.0, 1.0), Load("T", 1.0, "N*mm", ("far",), "x"),
                      (Support(("sym_x",), "symmetry"),), meta={"cracks": {}})
    return FeaBook({"cup-surface-crack": CaseOutcome(Case("cup-surface-crack", "cup-surface-crack"), res, 1.0, False)})


def test_checks_pass_on_their_closed_forms_and_fail_on_perturbed_ones(params):
    from strainwave.compare.validate import surface_crack_checks as scc
    from strainwave.fea.surface_crack import delta_name
    a = scc.headline_depth_mm(params)
    values = {delta_name(s, a): scc.references(params, a, s)["corrected"] for s in ("major", "between")}
    values[delta_name("minor", a)] = 1e-9 * values[delta_name("major", a)]
    book = _book(values)
    good = scc.surface_crack_checks(book, "cup-surface-crack", params)
    assert [c.id for c in good] == [cid for cid, _ in scc.CHECKS] and all(c.passed for c in good)
    # the seed's through-wall crack as the reference, or Newman-Raju 1.5 x, fails the open checks
    seed = scc.surface_crack_checks(book, "cup-surface-crack", params,
                                    reference=lambda p, d, s: {"corrected": scc.references(p, d, s)["published"]})
    assert not seed[0].passed and not seed[1].passed

    def scaled(p, d, s):
        r = scc.references(p, d, s)
        return {"corrected": 1.5 * r["corrected"]}
    assert not any(c.passed for c in scc.surface_crack_checks(book, "cup-surface-crack", params, reference=scaled)[:2])
    # a crack that stays half open at the minor axis fails the contact check
    half = dict(values)
    half[delta_name("minor", a)] = 0.5 * values[delta_name("major", a)]
    assert not scc.surface_crack_checks(_book(half), "cup-surface-crack", params)[2].passed
    missing = scc.surface_crack_checks(book, None, params)
    assert all(c.verdict == "not evaluated" and not c.passed for c in missing)


def test_record_gives_the_breathing_ripple_in_percent_of_K_HD(params):
    from strainwave.analytic.seed000 import seed000_summary
    from strainwave.compare.validate import surface_crack_checks as scc
    from strainwave.fea.surface_crack import delta_name
    a = scc.headline_depth_mm(params)
    book = _book({delta_name("major", a): 4e-16, delta_name("minor", a): 0.0})
    book.outcomes["cup-surface-crack"].result.meta["cracks"] = {f"{a:g}": {}}
    row = scc.surface_crack_record(book, "cup-surface-crack", params)["depths"][0]
    lam = 1.0 / seed000_summary(params)["K_HD"]["corrected"]
    assert row["ripple_percent_of_K_HD"] == pytest.approx(100.0 * 4e-16 / lam, rel=1e-5)
    assert row["ripple_percent_of_K_HD_per_mm"] == pytest.approx(row["ripple_percent_of_K_HD"] / a)
    by_phi = dict((d, v) for d, v in row["newman_raju_by_phi"])
    assert by_phi[0] > 0.0 and by_phi[90] == 0.0 and by_phi[45] == pytest.approx(by_phi[0])


def test_checks_and_record_reach_results_json_through_the_check_list(params):
    from strainwave.analytic.summary import analytic_summary
    from strainwave.compare.validate import check_list
    from strainwave.compare.validate import surface_crack_checks as scc
    from strainwave.compare.validate.check_list import At
    from strainwave.compare.validate.check_set import build_checks
    from strainwave.compare.validate.plan import make_plan
    from strainwave.compare.validate.results import load_schema, plain
    from strainwave.fea.surface_crack import delta_name
    import jsonschema
    a = scc.headline_depth_mm(params)
    plan = make_plan(params, quick=True)
    assert plan.label_of(scc.STUDY) == "cup-surface-crack"      # validate --quick plans the case
    major = check_list.check_spec("cup.surface_crack_major").reference(params, At())
    values = {delta_name(s, a): major.corrected for s in ("major", "between")} | {delta_name("minor", a): 0.0}
    book = _book(values)
    book.outcomes["cup-surface-crack"].result.meta["cracks"] = {f"{a:g}": {}}
    built = build_checks(book, plan, analytic_summary(params), params)
    ours = [c for c in built.checks if c.id.startswith("cup.surface_crack")]
    assert [c.id for c in ours] == [cid for cid, _ in scc.CHECKS] and all(c.passed for c in ours)
    record = built.records["cup.surface_crack_major"]
    assert record["depths"][0]["states"]["major"]["fea"] == major.corrected
    doc = {"checks": [c.to_dict() for c in built.checks], "records": built.records}
    schema = load_schema()
    jsonschema.validate(plain(doc), {"$defs": schema["$defs"], "type": "object", "properties": {
        "checks": schema["properties"]["checks"], "records": schema["properties"]["records"]}})


def test_symmetry_plane_model_equals_the_seam_with_face_contact(params):
    # the same block mirrored about the crack plane, the crack as a seam (crack_seam.open_crack) and the faces in
    # contact by crack_contact: the quarter model's symmetry plane and active set are the same problem
    import numpy as np
    from strainwave.fea import surface_crack as fs
    from strainwave.fea.assembly import Lame
    from strainwave.fea.crack_contact import crack_pairs, solve_with_contact
    from strainwave.fea.crack_seam import open_crack
    from strainwave.fea.mesh_data import group_dofs
    from strainwave.fea.static import assemble
    from strainwave.fea.surface import SurfaceQuadrature
    block = _block(params)
    h, h_fine = 0.6, 0.15
    quarter = fs.solve_block(block, h, h_fine)
    seam = fs.block_mesh(block, h, h_fine, mirrored=True)

    def system(md):
        sk, K, _, _, _ = assemble(md, Lame.from_young(block.E_MPa, block.nu))
        quad = SurfaceQuadrature.of(md, "far")

        def f(membrane, bending):   # the far faces z = +-L pulled apart by sigma_n(y)
            return quad.load_vector(lambda x: np.stack([0 * x[0], 0 * x[0], np.sign(x[2]) * (
                membrane + bending * (1 - 2 * x[1] / block.t_mm))]), sk.node_to_dof, 3, K.shape[0])
        near = [int(np.argmin(np.linalg.norm(sk.doflocs.T - q, axis=1))) for q in
                ([0, block.t_mm, 0], [block.half_width_mm, 0, 0], [block.half_width_mm, block.t_mm, 0])]
        fixed = np.unique(np.r_[3 * group_dofs(sk, md, "sym_x"), 3 * near[0] + 1, 3 * near[1] + 2, 3 * near[2] + 2])
        return sk, K, f, lambda K_, f_, fx: fs._solve(K_, f_, fx, sk), fixed

    _, K0, f0, solve0, fixed0 = system(seam)
    opened = open_crack(seam)
    sk1, K1, f1, solve1, fixed1 = system(opened)
    unit0, unit1 = f0(1.0, 0.0), f1(1.0, 0.0)
    delta = 2.0 * (unit1 @ solve1(K1, unit1, fixed1) - unit0 @ solve0(K0, unit0, fixed0)) * block.per_torque_MPa_per_Nmm ** 2
    assert delta == pytest.approx(quarter.states["major"].delta_flexibility, rel=0.02)
    pairs = crack_pairs(opened).in_dofs(sk1.node_to_dof)
    for name, membrane, bending in block.states:
        r = solve_with_contact(K1, f1(membrane, bending), fixed1, pairs, solve1)
        assert r.active.mean() == pytest.approx(quarter.states[name].shut_fraction, abs=0.05)


def test_element_estimate_is_the_deepest_blocks_mesh_within_a_factor_of_two(params):
    from strainwave.fea import surface_crack as fs
    from strainwave.fea.budget import estimate
    t = params.flexspline_cup.wall_thickness_mm
    h = fs.default_size_mm(params, quick=False)
    deepest = fs.block_for(t, fs.SurfaceCrack.deepest_crack_mm(params), fs.ASPECT, 2e5, 0.3, 1e-5, ())
    elements = fs.block_mesh(deepest, h, h).quality.elements
    assert 0.5 < estimate(fs.STUDY, params, None).elements / elements < 2.0
