"""Decision 069, item 3: the circular spline body as a thin inextensible ring under the two mesh zones."""
import math

import pytest

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cs_ring import S_RADIAL, S_TANGENTIAL, cs_body_twist_rad_per_Nmm, ring_mesh_twist_rad_per_Nmm


def test_the_radial_pair_opens_the_ring_as_the_diametral_formula():
    """Two opposite point loads P open a thin ring's diameter by (pi/4 - 2/pi) P R^3 / EI (Roark)."""
    R, EI, r_p, alpha = 36.0, 1e8, 32.0, 20.0
    _, radial = ring_mesh_twist_rad_per_Nmm(R, EI, r_p, alpha)
    a = math.radians(alpha)
    P = math.tan(a) / (2.0 * r_p)                       # per zone at T = 1 N mm
    u0 = 0.5 * (math.pi / 4.0 - 2.0 / math.pi) * P * R ** 3 / EI
    assert radial == pytest.approx(u0 * math.tan(a) / r_p, rel=1e-6)
    assert S_TANGENTIAL == pytest.approx(1.0 / 36.0, rel=0.02)      # the n = 2 term carries the ring


def test_the_body_softens_with_a_thinner_body_and_scales_as_one_over_d_cubed():
    rules = MeshRules()
    a = cs_body_twist_rad_per_Nmm(rules.design(25, 30), 1.25 * 63.5)
    b = cs_body_twist_rad_per_Nmm(rules.design(25, 100), 1.25 * 63.5)
    c = cs_body_twist_rad_per_Nmm(rules.design(50, 100), 1.25 * 127.0)
    assert a > b                                        # i = 30: deeper teeth, a thinner body
    assert c == pytest.approx(b / 8.0, rel=1e-9)
    assert cs_body_twist_rad_per_Nmm(rules.design(25, 100), 1.4 * 63.5) < b
    with pytest.raises(ValueError, match="inside its root"):
        cs_body_twist_rad_per_Nmm(rules.design(25, 100), 60.0)


def test_the_fe_body_is_the_closed_forms_ring_where_the_ring_is_thin():
    """Like against like: a thin annulus (h / R = 0.05) under the radial pair opens as the inextensible ring does
    (1-3 %); the tangential pair twists it more than the mid-surface form (the load sits on the bore, h / 2 off)."""
    from strainwave.fea.cs_body_fe import cs_body_fe_twist_rad_per_Nmm
    R, h, b, E = 36.0, 1.8, 11.9, 2.1e5
    closed_t, closed_r = ring_mesh_twist_rad_per_Nmm(R, E * b * h ** 3 / 12.0, R - 0.5 * h, 20.0)
    fe, _ = cs_body_fe_twist_rad_per_Nmm(R - 0.5 * h, R + 0.5 * h, E, b, R - 0.5 * h, 20.0, 2, 288)
    assert fe["radial"] == pytest.approx(closed_r, rel=0.04)
    assert not fe["radial"] == pytest.approx(1.2 * closed_r, rel=0.04)
    assert closed_t < fe["tangential"] < 1.3 * closed_t
