"""The circular spline body with its bolted face (fea/cs_housing_fe.py, analytic/cs_housing.py; decision 070):
first principles on coarse lattices (a few CPU-s together)."""
from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache

import pytest

from strainwave.analytic.cs_ring import ring_mesh_twist_rad_per_Nmm
from strainwave.fea.cs_housing_fe import BodyCase, Restraint, cs_housing_twist_rad_per_Nmm

# a size-25-like body at i = 50: root 32.6 mm, outer 39.7 mm, 11.9 mm wide
BODY = BodyCase(32.6, 39.7, 11.9, 31.75, 20.0, 2.1e5, Restraint.FACE)


@lru_cache(maxsize=None)
def twist(case, k=1):
    out, _ = cs_housing_twist_rad_per_Nmm(case, k)
    return out["tangential"] + out["radial"]


def test_clamped_face_is_stiffer_than_a_band_than_bolts_than_the_free_ring():
    """More restraint, less twist: the whole face clamped < a band of it < 8 bolt footprints < free in its plane."""
    face = twist(BODY)
    band = twist(replace(BODY, clamp_r=(0.5, 1.0)))
    bolts = twist(replace(BODY, restraint=Restraint.BOLTS, n_bolts=8))
    free = twist(replace(BODY, restraint=Restraint.FREE))
    assert 0.0 < face < band < bolts < free
    assert free > 10.0 * face                   # the housing takes most of the ovalisation away


def test_an_elastic_housing_flange_lies_between_the_rigid_clamp_and_the_free_ring():
    """The face bonded to a housing flange clamped at its far face: a vanishing flange is the rigid clamp; a thicker
    or softer flange lets the body twist more, still less than free."""
    face, free = twist(BODY), twist(replace(BODY, restraint=Restraint.FREE))
    flange = lambda t, E: twist(replace(BODY, restraint=Restraint.HOUSING, housing_mm=t, housing_E_MPa=E))  # noqa: E731
    assert flange(1e-3, 2.1e5) == pytest.approx(face, rel=0.03)
    steel, alu = flange(BODY.b_mm, 2.1e5), flange(BODY.b_mm, 7e4)
    assert face < steel < alu < flange(2 * BODY.b_mm, 7e4) < free


def test_similar_bodies_scale_as_one_over_E_d_cubed():
    """Every length x 2 (loads per unit torque ~ 1/d): twist x 1/8; E halved: twist x 2."""
    a = twist(BODY)
    big = BodyCase(*(2.0 * x for x in (BODY.ri_mm, BODY.ro_mm, BODY.b_mm, BODY.r_p_mm)), 20.0, 2.1e5)
    assert twist(big) == pytest.approx(a / 8.0, rel=1e-9)
    assert twist(replace(BODY, E_MPa=1.05e5)) == pytest.approx(2.0 * a, rel=1e-9)


def test_a_thicker_body_twists_less():
    assert twist(replace(BODY, ro_mm=42.0)) < twist(BODY)
    assert twist(replace(BODY, ro_mm=42.0, restraint=Restraint.FREE)) < twist(replace(BODY, restraint=Restraint.FREE))


def test_the_free_thin_ring_meets_the_closed_form_radial_opening():
    """A thin free ring (h / R = 0.05): the radial pair's opening within 5 % of Timoshenko's inextensible ring
    (Roark's (pi/4 - 2/pi) P R^3 / EI), the tangential within 25 % (the load sits on the bore, h/2 off the
    mid-surface; the plane FE reads 1.17x on the same ring, decision 069)."""
    R, h, b = 40.0, 2.0, 10.0
    case = BodyCase(R - 0.5 * h, R + 0.5 * h, b, R - 0.5 * h, 20.0, 2.1e5, Restraint.FREE)
    out, _ = cs_housing_twist_rad_per_Nmm(case, 1)
    tang, rad = ring_mesh_twist_rad_per_Nmm(R, 2.1e5 * b * h ** 3 / 12.0, R - 0.5 * h, 20.0)
    # the FE bends like a plate strip (anticlastic curvature held): between E I and E I / (1 - nu^2)
    assert 0.95 * (1 - 0.3 ** 2) * rad < out["radial"] < 1.05 * rad
    assert 1.0 < out["tangential"] / tang < 1.25


@pytest.mark.heavy
def test_the_lattices_converge():
    """Three lattices: the clamped twist rises monotonically (a stiffer coarse lattice) and the changes shrink."""
    v = [twist(BODY, k) for k in (1, 2, 3)]
    assert v[0] < v[1] < v[2]
    assert abs(v[2] - v[1]) < 0.5 * abs(v[1] - v[0])


def test_the_term_scales_from_its_reference_size():
    from strainwave.analytic.cs_housing import CsBodyTerm
    from strainwave.fea.result import Quantity

    class C:
        gci_fine = 0.0
    q = Quantity("cs_body_twist_rad_per_Nmm", 1e-9, "rad/(N*mm)", C())
    t = CsBodyTerm("face", 63.5, 2.1e5, q, q, q, 0.0)
    assert t.at(127.0) == pytest.approx(1e-9 / 8.0)
    assert t.at(63.5, 1.05e5) == pytest.approx(2e-9)
    assert math.isclose(t.at(63.5), 1e-9)


def test_the_catalogue_puts_the_body_in_series_per_ratio(monkeypatch, tmp_path):
    """Each row's series flexibility gains the body's term at its ratio, scaled to the row's size; the JSON says so."""
    from strainwave.analytic import catalogue_predict as cp
    from strainwave.analytic.catalogue_rules import MeshRules
    from strainwave.analytic.cs_housing import CsBodyTerm
    from strainwave.fea.result import Quantity

    class C:
        gci_fine, observed_order, h_mm, values = 0.04, 1.7, (1.0, 2.0, 3.0), (3e-10, 2.9e-10, 2.7e-10)
    q = Quantity("cs_body_twist_rad_per_Nmm", 3e-10, "rad/(N*mm)", C())
    term = CsBodyTerm("face", 63.5, 2.1e5, q, q, q, 0.0)
    rules = MeshRules(cup_zone_elements=None)
    monkeypatch.setattr(MeshRules, "cs_body_term", lambda self, ratio: term)
    seen = []

    class Stop(Exception):
        pass

    def record(row, design, series, *a, **k):
        seen.append(series)
        raise Stop
    monkeypatch.setattr(cp, "_loss", record)      # each row's series (decision 071: its curve may be scaled)
    p = tmp_path / "t.csv"
    p.write_text("size,ratio,T1_Nm,T2_Nm,K1_e3,K2_e3,K3_e3\n50,>50,108,382,250,400,440\n")
    with pytest.raises(Stop):
        cp.predict_table(p, rules)
    d = rules.pitch_diameter_mm(50)
    assert seen[0] == pytest.approx(rules.cup_flexibility_rad_per_Nmm(50) + 3e-10 * (63.5 / d) ** 3, rel=1e-12)
    pred = cp.CataloguePrediction([], rules, 0.0, cs_body={100.0: term})
    body = pred.to_dict()["cs_body_terms"][0]
    assert body["ratio"] == 100.0 and body["restraint"] == "face" and body["twist_rad_per_Nmm"]["gci_fine"] == 0.04
    assert "circular spline body, mounting face" in pred.summary()


def test_a_body_that_cannot_be_built_is_refused():
    with pytest.raises(ValueError, match="outer radius"):
        BodyCase(40.0, 39.0, 10.0, 38.0, 20.0, 2.1e5)
    with pytest.raises(ValueError, match="multiple of 4"):
        replace(BODY, restraint=Restraint.BOLTS, n_bolts=6)
    with pytest.raises(ValueError, match="flange thickness"):
        replace(BODY, restraint=Restraint.HOUSING)


@pytest.mark.heavy
def test_the_rules_term_has_its_gci_and_lies_inside_the_bracket():
    """The catalogue's term at i = 30 (three lattices, ~10 CPU-s): resolved (GCI < 10 %), the clamped body below the
    free one, and the free one within 5 % of decision 069's plane-stress FE (1.50e-8 at size 25)."""
    from strainwave.analytic.catalogue_rules import MeshRules
    from strainwave.analytic.cs_housing import cs_body_term
    rules = MeshRules()
    design, od = rules.design(25, 30), rules.cs_outer_over_d * rules.pitch_diameter_mm(25)
    face, free = cs_body_term(design, od, "face"), cs_body_term(design, od, "free")
    assert face.twist.convergence.gci_fine < 0.10 and free.twist.convergence.gci_fine < 0.10
    assert 0.0 < face.twist.value < 0.05 * free.twist.value
    assert free.twist.value == pytest.approx(1.50e-8, rel=0.05)
    assert rules.cs_body_term(30).twist.value == face.twist.value
