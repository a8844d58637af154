"""The assembled drive (fea/drive_assembled.py) and its check gear.drive_assembled (decision 073-assembled48):
first principles of the assembly, the wall's and the annulus's uniform modes against closed forms, and the check
failing on a perturbed reference."""
import dataclasses
import math

import numpy as np
import pytest

from strainwave.analytic import torsion
from strainwave.fea import drive_assembled as da
from strainwave.fea.assembly import Lame
from strainwave.fea.wg_band import TubeGeometry

E, NU = 2.1e5, 0.3
G_MOD = E / (2 * (1 + NU))


def _set(n: int = 5, C: np.ndarray | None = None) -> da.RatedSet:
    phi = np.radians(np.linspace(0.0, 12.0, n))
    lever = np.full(n, 75.0)
    C = np.diag(np.linspace(4e-6, 6e-6, n)) + 1e-6 if C is None else C
    return da.RatedSet(phi, np.ones(n, int), lever, np.full(n, math.radians(21.0)), C, np.ones(n))


def test_a_uniform_wall_adds_in_series_exactly():
    """No coupling, no error: a wall that only twists uniformly (G = lambda L L^T) adds its lambda in series to
    the teeth, whatever their load share (Sherman-Morrison); the assembly is exactly the chain."""
    s = _set()
    L = s.lever_mm
    lam_u = 2.3e-10
    K = da.stiffness(s, lam_u * np.outer(L, L), np.zeros((5, 5)), np.zeros((5, 5)))
    K_teeth = da.generalized(s.compliance_mm_per_N, s.lever_mm)
    assert K == pytest.approx(1.0 / (1.0 / K_teeth + lam_u), rel=1e-10)
    assert not K == pytest.approx(1.0 / (1.0 / K_teeth + 1.2 * lam_u), rel=1e-3)


def test_rigid_teeth_route_the_load_round_the_wave_generator():
    """With the teeth rigid, the load can shift between teeth at no cost, so it shares itself where the lobes'
    radial give does not open the flanks: the assembly is the wall's uniform twist alone (the lobes drop out), and
    with compliant teeth the lobes soften it."""
    s = _set(C=1e-14 * np.eye(5))
    L = s.lever_mm
    lam_u = 2.3e-10
    Gwg = da.wg_flexibility(s, 2e5)
    K = da.stiffness(s, lam_u * np.outer(L, L), np.zeros((5, 5)), Gwg)
    assert K == pytest.approx(1.0 / lam_u, rel=1e-3)
    soft = _set()
    assert da.stiffness(soft, lam_u * np.outer(L, L), np.zeros((5, 5)), Gwg) < \
        da.stiffness(soft, lam_u * np.outer(L, L), np.zeros((5, 5)), 0 * Gwg)


def test_the_lobes_are_springs_in_k_g():
    s = _set()
    G1, G2 = da.wg_flexibility(s, 1e5), da.wg_flexibility(s, 2e5)
    assert np.allclose(G1, 2.0 * G2)
    # one tooth on the major axis: its lobe moves F sin(alpha) / K_G, its flank opens sin(alpha) of it
    assert G1[0, 0] == pytest.approx(math.sin(math.radians(21.0)) ** 2 / 1e5)


def test_the_mode_map_holds_the_torque_and_cancels_an_even_load():
    """The mean mode of a tangential force t is t / (2 pi) per radian (t round the circle); equal loads on teeth
    spread evenly round a lobe carry only the mean (every higher mode cancels)."""
    P = da.mode_map(np.array([0.3]), np.array([2.0]), 6)
    assert P[0, 0] == pytest.approx(2.0 / (2.0 * math.pi))
    z = 40
    phi = math.pi * np.arange(z) / z
    P = da.mode_map(phi, np.ones(z), 6)
    assert np.sum(P[0]) == pytest.approx(z / (2.0 * math.pi))
    assert np.allclose(P[1:].sum(axis=1), 0.0, atol=1e-12)


def test_the_annulus_twists_as_the_thick_ring_in_shear():
    """Plane annulus, the uniform mode (outer shear balanced by the bore's): theta = T (1/r_i^2 - 1/r_o^2) /
    (4 pi G b), the thick ring's closed form."""
    r_i, r_o, b = 60.0, 64.0, 20.0
    g2 = da.annulus_modes(r_i, r_o, b, 1.0, Lame.from_young(E, NU), 0)
    fe = g2[0, 0] / (2.0 * math.pi * r_o) ** 2
    closed = (1.0 / r_i ** 2 - 1.0 / r_o ** 2) / (4.0 * math.pi * G_MOD * b)
    assert fe == pytest.approx(closed, rel=0.01, abs=0)
    assert not fe == pytest.approx(1.2 * closed, rel=0.01, abs=0)


def test_the_wall_under_the_mean_mode_is_the_tube_of_the_closed_form():
    """The wall's mean mode is the uniform band shear: L_eff / (G J) of the same tube (decision 067's test)."""
    geo = TubeGeometry(38.4, 40.0, 5.6, 80.0, 16.0)
    wall = da.wall_modes(geo, 6, Lame.from_young(E, NU), 0.4, 0)
    fe = wall["g"][0, 0] / (2.0 * math.pi * geo.r_o_mm) ** 2
    J = 0.5 * math.pi * (geo.r_o_mm ** 4 - geo.r_i_mm ** 4)
    closed = torsion.tube_effective_length_mm(geo.length_mm, geo.band_mm, geo.z_end_mm) / (G_MOD * J)
    assert fe == pytest.approx(closed, rel=0.03, abs=0)
    assert not fe == pytest.approx(1.2 * closed, rel=0.03, abs=0)


def test_two_alike_lobes_are_one_lobe_in_parallel():
    """The study's record read back: two pairs on each lobe, uncoupled between lobes, with their lobe springs: the
    drive is twice one lobe (the lobes in parallel), and the lobe springs do not couple the lobes."""
    one = {"phi_rad": [0.0, 0.05], "side": [1, 1], "lever_mm": [75.0, 75.0], "cs_radius_mm": [80.0, 80.0]}
    C1 = np.array([[5e-6, 1e-6], [1e-6, 6e-6]])
    both = {k: v + [x + math.pi for x in v] if k == "phi_rad" else v + v for k, v in one.items()}
    C = np.zeros((4, 4))
    C[:2, :2], C[2:, 2:] = C1, C1
    rec = lambda pairs, c: {"pairs": pairs, "forces_at_rated_N": [1.0] * len(pairs["side"]),  # noqa: E731
                            "rated_compliance": {"index": list(range(len(pairs["side"]))),
                                                 "compliance_mm_per_N": c.tolist()}}
    s1, s2 = da.rated_set(rec(one, C1)), da.rated_set(rec(both, C))
    k1 = da.stiffness(s1, 0 * C1, 0 * C1, da.wg_flexibility(s1, 1e5))
    k2 = da.stiffness(s2, 0 * C, 0 * C, da.wg_flexibility(s2, 1e5))
    assert k2 == pytest.approx(2.0 * k1, rel=1e-12)
    assert np.all(da.wg_flexibility(s2, 1e5)[:2, 2:] == 0.0)


class _Q:
    def __init__(self, value, uncertainty):
        self.value, self.uncertainty = value, uncertainty


class _Book:
    def __init__(self, meta):
        self.meta = meta

    def quantity(self, label, name):
        return {"radial_stiffness_N_per_mm": (_Q(2e5, 10.0), ""), "K3_Nmm_per_rad": (_Q(1e10, 1e7), "")}[name]

    def result(self, label):
        return type("R", (), {"meta": self.meta})()


def _record(scale_chain: float = 1.0) -> dict:
    """A recorded assembly (the finest wall's members and three meshes' ratio), the chain scaled by ``scale_chain``."""
    from strainwave.fea.refinement import converged_quantity
    m = da.AssembledMesh(11, 2.662e9, 2.684e9, 2.6835e9, 7.9e-11, 2.345e-10, 1.6e-11, 5.3e-11, 4.2e-11, 0.24, 7245)
    m = dataclasses.replace(m, K_chain_half_harmonics=m.K_chain_half_harmonics * scale_chain,
                            **{k: getattr(m, k) / scale_chain for k in
                               ("lambda_teeth", "lambda_wall_uniform", "lambda_zone_net", "lambda_wg_lobes")})
    h = [11.3, 15.5, 20.7]
    K = converged_quantity("assembled_drive_stiffness_Nmm_per_rad", "N*mm/rad", h, [2.662e9, 2.682e9, 2.690e9])
    ratio = converged_quantity("assembled_over_chain", "1", h, [1.00014, 1.00015, 1.00019])
    zone = converged_quantity("wall_zone_net_flexibility_rad_per_Nmm", "rad/(N*mm)", h, [1.63e-11, 1.35e-11, 1.24e-11])
    return {"K": K, "ratio": ratio, "zone": zone, "finest": m, "runs": [m], "rated_set": _set(6), "cpu_s": 3.0}


def test_the_check_fails_on_a_perturbed_reference(monkeypatch):
    from strainwave.api import load_params
    from strainwave.compare.validate import drive_assembled_checks as dc
    params = load_params(None)
    book = _Book({"rated_compliance": {"index": [0]}})
    for scale, passes in ((1.0, True), (0.8, False), (1.2, False), (0.97, False)):
        monkeypatch.setattr(da, "assemble", lambda meta, p, kg, s=scale: _record(s))
        c = dc.drive_check(book, "tooth-mesh", "wg-bearing", params)
        assert c.passed is passes, (scale, c.rel_error, c.tolerance)
    assert "assembled / previous" in c.note and c.tolerance.relative < 0.02
    assert not dc.drive_check(book, None, "wg-bearing", params).passed


def test_the_gear_chain_takes_the_assemblys_wave_generator_and_zone_term(monkeypatch):
    """decision 073-assembled48: with an assembly, the validate chain's wave generator is the lobes' and the wall's
    zone term joins it in series; without one it keeps seed 000's lambda_H and says why."""
    import sys
    from strainwave.api import load_params
    from strainwave.compare.validate import drive_assembled_checks as dc
    from strainwave.compare.validate import mesh_chain_checks as mc
    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from test_tooth_mesh import CS_BODY, _ChainBook, _cs_body
    _cs_body(monkeypatch, mc)
    params = load_params(None)
    labels = {"cup": "cup", "shaft": "shaft"}
    old, why = mc.chain(_ChainBook(1.1583e10), labels, "wg", "mesh", params)
    assert "seed 000's lambda_H" in old["wave_generator_form"] and old["lambda_zone_rad_per_Nmm"] == 0.0
    rec = _record()
    monkeypatch.setattr(dc, "assembled", lambda *a, **k: (rec, ""))
    new, _ = mc.chain(_ChainBook(1.1583e10), labels, "wg", "mesh", params)
    lam = 1 / 1.1583e10 + 4.9155e-10 + CS_BODY["face"] + rec["finest"].lambda_wg_lobes + rec["zone"].value
    assert new["K3_chain_Nmm_per_rad"] == pytest.approx(1.0 / lam, rel=1e-12)
    assert new["wave_generator_form"] == "lobes (decision 073-assembled48)"


@pytest.mark.heavy
def test_the_default_gears_assembly_end_to_end():
    """The study's quick finest rim on the default gear, its rated set, the three walls (about 15 CPU-s): the
    assembly is stiffer than the chain of its members (complementary energy: the load share may only improve) but
    by little; the wall's zones add compliance on the cam; seed 000's lambda_H is not the lobes'."""
    from strainwave.analytic.mesh_engagement import study_loads
    from strainwave.api import load_params
    from strainwave.compare.validate.drive_assembled_checks import seed_lambda_H
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import solve_torque_path
    params = load_params(None)
    mesh = study_loads(params, quick=True)["mesh"]
    infl, _ = tm.influences(params, mesh, tm.refinements(params.flexspline_cup.module_mm, True)[0])
    path = solve_torque_path(tm.systems(infl, mesh)[0], np.asarray(mesh["torque_history_Nmm"]))
    k = int(np.argmax(path.torque_Nmm))
    meta = {"pairs": mesh["angles"][0], "forces_at_rated_N": path.forces_N[k].tolist(),
            "rated_compliance": tm.rated_compliance(infl, mesh, path)}
    a = da.assemble(meta, params, 1.993e5)
    for r in a["runs"]:
        assert 1.0 <= r.K_assembled_Nmm_per_rad / r.K_chain_Nmm_per_rad < 1.01
        assert r.lambda_zone_net > 0.0 and r.lambda_zone_gross > r.lambda_zone_net
    f = a["finest"]
    assert seed_lambda_H(params, 1.993e5) > 1.5 * f.lambda_wg_lobes
