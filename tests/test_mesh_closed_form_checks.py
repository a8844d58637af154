"""Closed forms beside the tooth-mesh study (issue 48 item 3) as validate checks: the rigid rim's load sharing and the
engagement zone's edge (compare/validate/mesh_closed_form_checks.py)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from strainwave.analytic.mesh_engagement import mesh_geometry, pairs_at
from strainwave.analytic.rigid_rim_sharing import rigid_rim_sharing
from strainwave.compare.validate import mesh_closed_form_checks as mcf
from strainwave.compare.validate.mutation_checks import mutation_rows
from strainwave.fea import tooth_mesh as tm
from strainwave.fea.convergence import grid_convergence
from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path
from strainwave.fea.result import Quantity
from strainwave.params import load_params


def test_rigid_rim_closed_form_by_hand():
    # two driving pairs (lever 10 mm, compliance 1e-3 mm/N, gaps 0 and 0.01 mm), one reverse pair, mu = 0:
    # pair 2 closes at t = 1e-3 rad, where T = 10 x (10 x 1e-3) / 1e-3 = 100 N mm
    g, c, lever, slide = [0.0, 0.01, 0.0], [1e-3] * 3, [10.0, 10.0, -10.0], [1.0, 1.0, 1.0]
    low = rigid_rim_sharing(g, c, lever, slide, 0.0, 50.0)
    assert low.twist_rad == pytest.approx(5e-4) and low.forces_N == pytest.approx([5.0, 0.0, 0.0])
    # above it: 300 = 10 (10 t / 1e-3) + 10 (10 t - 0.01) / 1e-3  ->  t = 2e-3, F = 20, 10
    high = rigid_rim_sharing(g, c, lever, slide, 0.0, 300.0)
    assert high.twist_rad == pytest.approx(2e-3) and high.forces_N == pytest.approx([20.0, 10.0, 0.0])
    assert high.peak_share == pytest.approx(2 / 3) and high.teeth_in_contact == 2
    # a negative torque loads the reverse flank only; friction (mu |slide|) adds to every arm
    neg = rigid_rim_sharing(g, c, lever, slide, 0.1, -101.0)
    assert neg.twist_rad == pytest.approx(-1e-3) and neg.forces_N == pytest.approx([0.0, 0.0, 10.0])


def test_rigid_rim_closed_form_equals_the_contact_solver_on_random_meshes():
    rng = np.random.default_rng(48)
    for _ in range(20):
        n = 30
        g = rng.uniform(0.0, 0.02, n) * (rng.random(n) > 0.1)
        c = rng.uniform(1e-6, 5e-6, n)
        lever = rng.choice([-1.0, 1.0], n) * 76.0
        slide = rng.uniform(10.0, 20.0, n)
        T = rng.uniform(-1e6, 1e6)
        path = solve_torque_path(MeshSystem(g, np.diag(c), lever, slide, 0.08, 79.0), np.array([0.0, T]))
        closed = rigid_rim_sharing(g, c, lever, slide, 0.08, T)
        assert closed.twist_rad == pytest.approx(path.twist_rad[-1], rel=1e-9)
        assert np.allclose(closed.forces_N, path.forces_N[-1], rtol=1e-9, atol=1e-9 * path.forces_N.max())


def _synthetic_influences(geo, mesh):
    """FE-like influences (no FE): the measured default gear's FS tooth 2.9-3.5e-6 and CS tooth 1.35-0.8e-6 mm/N over
    the five radii, a neighbour coupling of 0.77 decaying along the rim."""
    fs_r, cs_r = tm.radii_grids(mesh)
    k = np.arange(5)
    A = np.sqrt(np.outer(2.9e-6 + 0.15e-6 * k, 2.9e-6 + 0.15e-6 * k)) * 0.95 ** np.abs(k[:, None] - k[None, :])
    B = np.sqrt(np.outer(1.35e-6 - 0.13e-6 * k, 1.35e-6 - 0.13e-6 * k)) * 0.95 ** np.abs(k[:, None] - k[None, :])
    d = np.minimum(np.arange(geo.z_f), geo.z_f - np.arange(geo.z_f))
    same = (0.77 ** d)[:, None, None] * A
    cs = np.stack([B * (1.0 if j == 0 else 0.1 / abs(j)) for j in range(-tm.CS_NEIGHBOURS, tm.CS_NEIGHBOURS + 1)])
    return {"fs_same": same, "fs_other": 0.5 * same, "cs": cs, "fs_radii": fs_r, "cs_radii": cs_r}


@pytest.fixture(scope="module")
def rigid_solve():
    params = load_params(None)
    geo = mesh_geometry(params)
    pairs = pairs_at(geo, 0.0)
    from strainwave.fea.mesh_contact import torque_history
    rated = params.gear.rated_output_torque_Nmm
    mesh = {"angles": [pairs], "z_f": geo.z_f, "z_c": geo.z_c, "friction_coefficient": 0.08,
            "rim_radius_mm": geo.r_neutral_mm, "torque_history_Nmm": torque_history(rated),
            "module_mm": geo.fs.module_mm,
            "fs_tip_mm": geo.fs.tip_radius_mm, "cs_tip_mm": geo.cs_tip_mm,
            "fs_radius_range_mm": (pairs["fs_radius_mm"].min(), pairs["fs_radius_mm"].max()),
            "cs_radius_range_mm": (pairs["cs_radius_mm"].min(), pairs["cs_radius_mm"].max())}
    values, inputs = tm.rigid_rim(_synthetic_influences(geo, mesh), mesh)
    return params, values, inputs


class _Book:
    """A solved tooth-mesh case: the rigid-rim share with a GCI of ``unc`` and the solve's record."""

    def __init__(self, share, inputs, unc=0.004):
        h = (0.24, 0.336, 0.4704)
        vals = (share, share * (1 - unc / 3), share * (1 - unc / 3 * 1.4 ** 2))
        self.q = Quantity(mcf.SHARE, share, "1", grid_convergence(h, vals, formal_order=2.0))
        self.meta = {"rigid_rim": inputs}

    def quantity(self, label, name):
        return (self.q, "") if name == mcf.SHARE else (None, f"no {name}")

    def result(self, label):
        return SimpleNamespace(meta=self.meta)


def test_rigid_rim_check_passes_on_the_solve_and_fails_on_a_perturbed_reference(rigid_solve, monkeypatch):
    params, values, inputs = rigid_solve
    share = values["rigid_rim_peak_tooth_share"]
    assert 2 <= values["rigid_rim_teeth_in_contact"] < len(inputs["clearance_mm"])   # load shared, not all pairs
    c = mcf.rigid_rim_check(_Book(share, inputs), "tooth-mesh", params)
    assert c.passed and abs(c.rel_error["corrected"]) < 1e-9, c
    assert f"contact solve {values['rigid_rim_teeth_in_contact']:.0f}, closed form" in c.note
    row = mutation_rows([c.to_dict()])[0]
    assert row.catches_20 and row.catches_10             # the tolerance is the GCI alone
    # the FE value off by +-20 % fails; so does the closed form off by +-20 %
    for f in (0.8, 1.2):
        assert not mcf.rigid_rim_check(_Book(share * f, inputs), "tooth-mesh", params).passed
    ref = mcf.rigid_rim_reference
    for f in (0.8, 1.2):
        monkeypatch.setattr(mcf, "rigid_rim_reference",
                            lambda i, f=f: SimpleNamespace(**{**vars(ref(i)), "peak_share": ref(i).peak_share * f,
                                                              "teeth_in_contact": ref(i).teeth_in_contact}))
        assert not mcf.rigid_rim_check(_Book(share, inputs), "tooth-mesh", params).passed


def test_rigid_rim_check_catches_a_solve_that_lost_the_clearances(rigid_solve):
    """A contact solve that took every flank pair as touching from zero twist (its gaps lost) shares the load
    out over all the driving pairs: the check, holding the same inputs' closed form, fails."""
    params, values, inputs = rigid_solve
    g = np.zeros(len(inputs["clearance_mm"]))
    system = MeshSystem(g, np.diag(inputs["compliance_mm_per_N"]), np.asarray(inputs["lever_mm"]),
                        np.asarray(inputs["slide_mm_per_rad"]), inputs["friction_coefficient"], 79.0)
    F = solve_torque_path(system, np.array([0.0, inputs["torque_Nmm"]])).forces_N[-1]
    c = mcf.rigid_rim_check(_Book(float(F.max() / F.sum()), inputs), "tooth-mesh", params)
    assert not c.passed and abs(c.rel_error["corrected"]) > 0.2


def test_rigid_rim_check_without_a_record_is_not_evaluated():
    params = load_params(None)
    c = mcf.rigid_rim_check(_Book(0.1, None), "tooth-mesh", params)
    assert c.verdict == "not evaluated" and not c.passed
    assert mcf.rigid_rim_check(_Book(0.1, None), None, params).reason_not_evaluated == "no tooth-mesh case"


# --- the engagement zone's edge (kinematic theory) ---------------------------------------------------------------

from strainwave.analytic.engagement_zone import driving_flank_gap_mm, tip_path, zone_edge_rad  # noqa: E402

GEARS = [None, "strainwave/data/second_gear.toml"]


def test_tip_path_rides_an_inextensible_neutral_line():
    w0, rn = 0.8, 78.88
    phi = np.linspace(-1.5, 1.5, 3001)
    R, ang = tip_path(phi, w0, rn, rn)                  # a point on the neutral line itself
    w, v = R - rn, (ang - phi) * rn
    assert np.allclose(np.gradient(v, phi)[1:-1], -w[1:-1], atol=1e-5)    # v' = -w: the line does not stretch
    R0, a0 = tip_path(0.0, w0, rn, 81.88)
    assert R0 == pytest.approx(81.88 + w0) and a0 == pytest.approx(0.0)     # the major axis: full depth, centred


@pytest.mark.parametrize("name", GEARS)
def test_zone_edge_is_where_the_tip_reaches_the_flank_and_agrees_with_the_studys_engagement(name):
    geo = mesh_geometry(load_params(name))
    edge = zone_edge_rad(geo)
    assert math.radians(40) < edge < math.radians(70)
    assert driving_flank_gap_mm(edge - 1e-4, geo) > 0.0 > driving_flank_gap_mm(edge + 1e-4, geo)
    # on the major axis the tooth sits centred in its space: the gap is the backlash and the involutes' fit
    assert driving_flank_gap_mm(0.0, geo) > 0.0
    # the study's engagement (another derivation, contact at the middle of the overlap) keeps driving pairs with a
    # closed gap up to the edge and none beyond it: its outermost pair stands within one pitch inside the edge
    pairs = pairs_at(geo, 0.0)
    folded = 0.5 * np.angle(np.exp(2j * pairs["phi_rad"][pairs["side"] > 0]))
    assert edge - 2 * math.pi / geo.z_f < folded.max() <= edge


def _zone_book(value):
    h = (0.24, 0.336, 0.4704)
    q = Quantity(mcf.ZONE, value, "rad", grid_convergence(h, (value, value * 0.999, value * 0.997), formal_order=2.0))

    class B:
        def quantity(self, label, name):
            return (q, "") if name in (mcf.ZONE, "engagement_edge_first_step_rad") else (None, "")
    return B()


@pytest.mark.parametrize("name", GEARS)
def test_zone_check_passes_on_the_studys_edge_and_fails_on_a_perturbed_reference(name, monkeypatch):
    params = load_params(name)
    fe = math.radians(54.0)            # the study's outermost loaded pair at rated on both gears (quick meshes)
    c = mcf.zone_check(_zone_book(fe), "tooth-mesh", params)
    assert c.passed, c
    assert mutation_rows([c.to_dict()])[0].catches_20
    for f in (0.8, 1.2):
        assert not mcf.zone_check(_zone_book(fe * f), "tooth-mesh", params).passed
    ref = mcf.zone_reference
    for f in (0.8, 1.2):
        monkeypatch.setattr(mcf, "zone_reference", lambda p, f=f: tuple(x * f for x in ref(p)))
        assert not mcf.zone_check(_zone_book(fe), "tooth-mesh", params).passed
    # a pair two pitches inside the edge is more than the quantisation allows
    monkeypatch.setattr(mcf, "zone_reference", ref)
    two_in = ref(params)[0] - 2 * 2 * math.pi / params.flexspline_cup.teeth
    assert not mcf.zone_check(_zone_book(two_in), "tooth-mesh", params).passed
