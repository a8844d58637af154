"""The wave generator on the cup's band (fea/wg_band.py) and its check (compare/validate/wg_cup_checks.py),
on coarse meshes (seconds)."""
import math
from dataclasses import replace

import numpy as np
import pytest

from strainwave.compare.validate import wg_cup_checks
from strainwave.compare.validate.fea_book import FeaBook
from strainwave.compare.validate.runner import Case, CaseOutcome
from strainwave.fea import wg_band as wb
from strainwave.fea.assembly import Lame
from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support
from strainwave.params import load_params


@pytest.fixture(scope="module")
def setup():
    p = load_params()
    geo = wb.tube_geometry(p)
    return p, geo, wb.tube_mesh(geo, 4), Lame.from_young(2.1e5, 0.3)


def test_patch_test_linear_field_gives_its_exact_stress(setup):
    _, geo, tube, lame = setup
    A = np.array([[1e-3, 2e-4, 0.0], [0.0, -5e-4, 3e-4], [1e-4, 0.0, 2e-4]])
    u = np.zeros(tube.dofs)
    u[tube.comp] = A @ tube.basis.doflocs
    K, R = wb.assemble(tube, u, lame, False)
    inside = (tube.r > geo.r_i_mm + 1e-6) & (tube.r < geo.r_o_mm - 1e-6) & (tube.z > geo.z_end_mm + 1e-6) \
        & (tube.z < geo.length_mm - 1e-6) & (tube.phi > 1e-6) & (tube.phi < 0.5 * math.pi - 1e-6)
    assert np.abs(R[tube.comp[:, inside]]).max() < 1e-8 * np.abs(R).max()
    s = wb.stresses_at(tube, u, lame, False, np.array([78.5]), np.array([0.3]), np.array([150.0]))[0]
    eps = 0.5 * (A + A.T)
    c, sn = math.cos(0.3), math.sin(0.3)
    Q = np.array([[c, sn, 0], [-sn, c, 0], [0, 0, 1]])
    assert s == pytest.approx(Q @ (lame.lam_MPa * np.trace(eps) * np.eye(3) + 2 * lame.mu_MPa * eps) @ Q.T, abs=1e-8)


def test_nonlinear_tangent_is_the_derivative_of_the_internal_force(setup):
    _, _, tube, lame = setup
    rng = np.random.default_rng(0)
    u = 1e-2 * rng.standard_normal(tube.dofs)
    K, R = wb.assemble(tube, u, lame, True)
    d = 1e-6 * rng.standard_normal(tube.dofs)
    _, R2 = wb.assemble(tube, u + d, lame, True)
    assert np.linalg.norm(R2 - R - K @ d) < 1e-4 * np.linalg.norm(K @ d)


def test_twist_functional_and_shear_load_of_a_rigid_rotation(setup):
    _, geo, tube, _ = setup
    shear, twist, arm, area = wb.band_outer_loads(tube)
    x = tube.basis.doflocs
    u = np.zeros(tube.dofs)
    u[tube.comp[0]], u[tube.comp[1]] = -1e-3 * x[1], 1e-3 * x[0]
    assert twist @ u == pytest.approx(1e-3, rel=1e-9)
    assert arm == pytest.approx(0.5 * math.pi * geo.r_o_mm ** 2 * geo.band_mm, rel=2e-3)   # P2 facets on a 22.5 deg arc


def _bending_book(p, tube, lame):
    """A one-case book with the coarse linear prescribed-shape bending at both axes (no GCI)."""
    state = wb.insert(tube, lame, p.gear.radial_deformation_mm, contact=False, nonlinear=False)
    z = tube.geo.length_mm - 0.5 * tube.geo.band_mm
    q = {}
    for axis, phi in (("major", 0.0), ("minor", 0.5 * math.pi)):
        s = wb.stresses_at(tube, state.u, lame, False, np.array([tube.geo.r_o_mm, tube.geo.r_i_mm]),
                           np.full(2, phi), np.full(2, z))[:, 1, 1]
        name = f"prescribed_linear_bending_{axis}_MPa"
        q[name] = Quantity(name, 0.5 * float(s[0] - s[1]), "MPa")
    result = StudyResult("cup-wave-generator", q, MeshQuality(1, 1, 1, 2, 1.0, 1.0),
                         Load("T", 1.0, "N*mm", ("band",), "test"), (Support(("end",), "held round"),), None, {}, (), {}, {})
    return FeaBook({"wg": CaseOutcome(Case("wg", "cup-wave-generator"), result, 0.0, False)})


def test_bending_check_passes_and_fails_on_a_perturbed_reference(setup, monkeypatch):
    p, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 10)        # 12 mm elements: the bending within the allowances, no GCI needed
    book = _bending_book(p, tube, lame)
    checks = wg_cup_checks.wg_checks(book, "wg", p)
    assert [c.passed for c in checks] == [True, True], [c.rel_error for c in checks]
    assert checks[0].fea > 0 > checks[1].fea           # outer fibre in tension at the major axis
    true_refs = wg_cup_checks.references
    monkeypatch.setattr(wg_cup_checks, "references",
                        lambda params, axis: true_refs(params, axis).scaled(1.1))
    assert not any(c.passed for c in wg_cup_checks.wg_checks(book, "wg", p))


def test_contact_lifts_the_band_off_near_the_minor_axis(setup):
    p, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    state = wb.insert(tube, lame, p.gear.radial_deformation_mm, contact=True, nonlinear=False)
    bore = wb.band_bore_points(tube)
    held = tube.phi[bore][state.active]
    assert held.size and held.min() < 1e-9 and held.max() < 0.5 * math.pi - 1e-6


def test_cams_active_set_by_the_schur_complement_meets_the_contact_conditions_of_the_direct_solve(setup):
    # the set _cam_active_set settles on S is the direct constrained solve's contact state: the cam pushes every
    # held point, no free point enters the cam; holding all points instead fails those conditions
    p, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    w0 = p.gear.radial_deformation_mm
    state = wb.insert(tube, lame, w0, contact=True, nonlinear=False)
    bore = wb.band_bore_points(tube)
    radial = tube.comp[0][bore]
    target = wb.cam_radius_mm(tube.phi[bore], geo.r_i_mm, w0) - geo.r_i_mm

    def conditions(active):
        base = wb.held_dofs(tube, symmetric=True)
        fixed = np.concatenate([base, radial[active]])
        u = wb.solve_constrained(tube, state.K, np.zeros(tube.dofs), fixed,
                                 np.concatenate([np.zeros(base.size), target[active]]))
        reaction, u_r = (tube.rot_t @ (state.K @ u))[radial], (tube.rot_t @ u)[radial]
        return u, bool(np.all(reaction[active] >= 0.0) and np.all(u_r[~active] - target[~active] >= -1e-6 * w0))
    u, met = conditions(state.active)
    assert met and state.newton_iterations > 1 and 0 < state.active.sum() < bore.size
    assert np.abs(u - state.u).max() <= 1e-10 * np.abs(u).max()     # the Schur route (held_solve) at round-off
    assert not conditions(np.ones(bore.size, bool))[1]


def test_stiffness_pattern_sums_the_element_matrices_as_a_coo_assembly(setup):
    import scipy.sparse as sp
    _, _, tube, _ = setup
    edofs = wb._element_dofs(tube.basis)
    n = edofs.shape[1]
    Ke = np.random.default_rng(2).standard_normal((edofs.shape[0], n, n))
    coo = sp.csr_matrix((Ke.ravel(), (np.repeat(edofs, n, axis=1).ravel(), np.tile(edofs, (1, n)).ravel())),
                        shape=(tube.dofs, tube.dofs))
    slots, indices, indptr = tube.pattern
    # assemble's order of the entries: (element, a, i, k, b)
    ordered = Ke.reshape(Ke.shape[0], n // 3, 3, n // 3, 3).transpose(0, 1, 2, 4, 3).ravel()
    K = sp.csr_matrix((np.bincount(slots, ordered, minlength=indices.size), indices, indptr), shape=coo.shape)
    assert abs(K - coo).max() <= 1e-12 * abs(coo).max()
    # a slot map off by one entry puts a block's value in its neighbour's place: the comparison can fail
    shifted = sp.csr_matrix((np.bincount(np.roll(slots, 1), ordered, minlength=indices.size), indices, indptr),
                            shape=coo.shape)
    assert abs(shifted - coo).max() > 0.1 * abs(coo).max()


def test_linear_stiffness_is_scikit_fems_linear_elasticity(setup):
    # assemble's tangent-moduli contraction at u = 0 against scikit-fem's own form on the same mesh and quadrature
    import skfem
    from skfem.models.elasticity import linear_elasticity
    _, _, tube, lame = setup
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    vector = skfem.CellBasis(tube.mesh, skfem.ElementVector(skfem.ElementHex2()), intorder=5)
    ref = skfem.asm(linear_elasticity(lame.lam_MPa, lame.mu_MPa), vector)
    assert abs(K0 - ref).max() <= 1e-12 * abs(ref).max()
    # another Poisson ratio is another matrix: the comparison can fail
    other = Lame.from_young(2.1e5, 0.29)
    assert abs(K0 - skfem.asm(linear_elasticity(other.lam_MPa, other.mu_MPa), vector)).max() > 1e-3 * abs(ref).max()


def test_band_loads_on_the_outer_reference_face_are_scikit_fems_facet_integrals(setup):
    import skfem
    _, geo, tube, _ = setup
    shear, _, arm, area = wb.band_outer_loads(tube)
    bf = tube.mesh.boundary_facets()
    v = tube.mesh.p[:, tube.mesh.facets[:, bf]]
    outer = np.all(np.hypot(v[0], v[1]) > geo.r_m_mm, axis=0) & np.all(v[2] > geo.band_start_mm - 1e-7, axis=0)
    fb = skfem.FacetBasis(tube.mesh, skfem.ElementVector(skfem.ElementHex2()), facets=bf[outer], intorder=6)

    @skfem.LinearForm
    def tangential(w, p):
        return (-p.x[1] * w[0] + p.x[0] * w[1]) / np.hypot(p.x[0], p.x[1])

    ref = skfem.asm(tangential, fb)
    assert np.abs(shear - ref).max() <= 1e-12 * np.abs(ref).max()
    assert area == pytest.approx(float(np.sum(fb.dx)), rel=1e-12)
    x = fb.global_coordinates().value
    assert arm == pytest.approx(float(np.sum(np.hypot(x[0], x[1]) * fb.dx)), rel=1e-12)
    # the tangential shear is not the axial one: the comparison can fail
    assert np.abs(shear - skfem.asm(skfem.LinearForm(lambda w, p: w[2]), fb)).max() > 0.1 * np.abs(ref).max()


def test_solves_through_the_antisymmetric_schur_factor_are_the_direct_constrained_solves(setup):
    # a load on every dof with a random set of held bore points, and the torque increment: held_solve through
    # one factorisation of K0 (the planes hold their own bore points' u_r) equals solve_constrained
    _, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    rng = np.random.default_rng(3)
    load, shear = rng.standard_normal(tube.dofs), wb.band_outer_loads(tube)[0]
    radial = tube.comp[0][wb.band_bore_points(tube)]
    active = rng.random(radial.size) < 0.4
    base = wb.held_dofs(tube, symmetric=False)

    def direct(held):
        fixed = np.unique(np.concatenate([base, radial[held]]))
        return wb.solve_constrained(tube, K0, load, fixed, np.zeros(fixed.size))
    state = wb.Inserted(np.zeros(tube.dofs), K0, active, 1, 1, False)
    systems = {sym: wb.bore_system(tube, K0, symmetric=sym) for sym in (False, True)}
    try:
        u = wb.held_solve(tube, systems[False], load, active, 0.0)
        du = wb.torque_increment(tube, state, shear, systems[False])
        du_symmetric = wb.held_solve(tube, systems[True], shear, active, 0.0)
    finally:
        for system in systems.values():
            system.close()
    ref, du_ref = direct(active), wb.torque_increment(tube, state, shear)
    assert np.abs(u - ref).max() <= 1e-10 * np.abs(ref).max()
    assert np.abs(du - du_ref).max() <= 1e-10 * np.abs(du_ref).max()
    assert 0 < systems[False].on_face.sum() < radial.size and systems[True].on_face.all()
    # another set, or the insertion's symmetric conditions under the torque, is another solution: both can fail
    assert np.abs(direct(~active) - ref).max() > 1e-3 * np.abs(ref).max()
    assert np.abs(du_symmetric - du_ref).max() > 1e-3 * np.abs(du_ref).max()


def test_nonlinear_cam_contact_meets_its_contact_conditions(setup):
    # each Newton step settles its set on the tangent's Schur complement; the converged state is in equilibrium
    # off the held dofs, the cam pushes every held point (on its radius) and no free point enters it
    p, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    w0 = p.gear.radial_deformation_mm
    linear = wb.insert(tube, lame, w0, contact=True, nonlinear=False)
    state = wb.insert(tube, lame, w0, contact=True, nonlinear=True, start=linear)
    bore = wb.band_bore_points(tube)
    radial = tube.comp[0][bore]
    free = np.ones(tube.dofs, bool)
    free[np.concatenate([wb.held_dofs(tube, symmetric=True), radial[state.active]])] = False

    def residual(u):
        return tube.rot_t @ wb.assemble(tube, u, lame, True)[1]
    R = residual(state.u)
    gap = (tube.rot_t @ state.u)[radial] - wb._bore_target_mm(tube, state.u, bore, w0, True, True)
    assert np.abs(R[free]).max() <= 1e-6 * np.abs(R).max()
    assert np.all(R[radial][state.active] >= 0.0) and np.all(gap[~state.active] >= -1e-6 * w0)
    assert np.abs(gap[state.active]).max() <= 1e-9 * w0 and 0 < state.active.sum() < bore.size
    # the linear state is no nonlinear equilibrium: the first check can fail
    assert np.abs(residual(linear.u)[free]).max() > 1e-3 * np.abs(R).max()


def _nonlinear_states(tube, lame, w0, system, systems):
    """Both nonlinear insertions and their torque increments: by Krylov solves preconditioned by K0's factors
    (``systems``), or (None) by a factorisation of every tangent."""
    shear = wb.band_outer_loads(tube)[0]
    out = {}
    for contact in (False, True):
        linear = wb.insert(tube, lame, w0, contact=contact, nonlinear=False, system=systems[True])
        state = wb.insert(tube, lame, w0, contact=contact, nonlinear=True, start=linear,
                          system=None if system is None else systems[True])
        out[contact] = state, wb.torque_increment(tube, state, shear, None if system is None else systems[False])
    return out


def test_newton_by_krylov_solves_preconditioned_by_k0_is_the_refactorised_newton(setup, monkeypatch):
    # the converged insertions (prescribed and cam), their contact sets and torque increments equal a Newton that
    # factorises every tangent, and so does the fallback of stalled Krylov solves; the preconditioner used as the
    # tangent's inverse (K0's chord) fails
    import scipy.sparse.linalg as spla
    p, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    w0 = p.gear.radial_deformation_mm
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    systems = {sym: wb.bore_system(tube, K0, symmetric=sym) for sym in (True, False)}
    try:
        ref = _nonlinear_states(tube, lame, w0, None, systems)
        new = _nonlinear_states(tube, lame, w0, True, systems)
        monkeypatch.setattr(wb, "MAX_KRYLOV", 1)       # every Krylov solve stalls: the factorised fallback
        stalled = _nonlinear_states(tube, lame, w0, True, systems)
        monkeypatch.undo()
        monkeypatch.setattr(spla, "cg", lambda A, b, M, **kw: (M @ b, 0))
        chord = _nonlinear_states(tube, lame, w0, True, systems)
    finally:
        for system in systems.values():
            system.close()

    def agree(a, b):
        (sa, da), (sb, db) = a, b
        # Newton to NEWTON_TOL from both routes: the states at ~1e-13, the increments at KRYLOV_RTOL_EXACT's ~1e-12
        return (np.array_equal(sa.active, sb.active) and np.abs(sa.u - sb.u).max() <= 1e-11 * np.abs(sb.u).max()
                and np.abs(da - db).max() <= 1e-10 * np.abs(db).max()
                and sa.newton_iterations <= sb.newton_iterations + 1)
    assert all(agree(new[c], ref[c]) and agree(stalled[c], ref[c]) for c in (False, True))
    assert 0 < ref[True][0].active.sum() < ref[True][0].active.size
    assert not any(agree(chord[c], ref[c]) for c in (False, True))


def test_held_preconditioner_by_partial_solves_is_the_two_solve_held_route(setup):
    # one forward and one backward substitution with S's free block between them (PARDISO's phases 331 / 333)
    # equal FaceSystem.held's two full solves for a random held set; another set is another solution
    _, geo, _, lame = setup
    tube = wb.tube_mesh(geo, 6)
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    system = wb.bore_system(tube, K0, symmetric=False)
    rng = np.random.default_rng(5)
    f = rng.standard_normal(tube.dofs)
    active = rng.random(system.faces.face_z.size) < 0.5
    try:
        fs = system.faces
        # pypardiso is a declared dependency: a factor without partial solves is a fall-back to SuperLU, a regression
        assert fs.factor.method == "pardiso" and fs.factor.forward is not None
        x = wb.held_preconditioner(system, active)(f)
        ref = fs.held(f, fs.face_loads(f), active)
        other = wb.held_preconditioner(system, ~active)(f)
    finally:
        system.close()
    assert np.abs(x - ref).max() <= 1e-10 * np.abs(ref).max()
    assert np.abs(other - ref).max() > 1e-3 * np.abs(ref).max()
