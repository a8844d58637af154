"""The tooth-mesh study's pieces: ISO's c', the kinematic engagement and the pair-stiffness check."""
from __future__ import annotations

import math

import numpy as np
import pytest

from strainwave.analytic import iso_mesh_stiffness as iso
from strainwave.analytic.mesh_engagement import engagement, engagement_zone_rad, mesh_geometry, study_loads
from strainwave.compare.validate import tooth_mesh_checks as tmc
from strainwave.fea.convergence import grid_convergence
from strainwave.fea.result import Quantity
from strainwave.params import load_params


def test_iso_single_stiffness_of_a_standard_pair():
    # z1 = 20, z2 = 40, x = 0, h_fP = 1.25 m: q' = C1 + C2/20 + C3/40 by hand
    q = 0.04723 + 0.15551 / 20 + 0.25791 / 40
    cb = 1 + 0.5 * (1.2 - 1.25)
    assert iso.single_stiffness_N_per_mm_um(20, 0.0, 40, 0.0) == pytest.approx(cb / q, rel=1e-12)
    # ISO's x terms: a positive shift on the pinion stiffens it (C4 < 0, C8 small)
    assert iso.single_stiffness_N_per_mm_um(20, 0.5, 40, 0.0) > iso.single_stiffness_N_per_mm_um(20, 0.0, 40, 0.0)


def test_engagement_is_centred_on_the_major_axis_with_the_backlash_there():
    geo = mesh_geometry(load_params(None))
    e = engagement(geo, 0.0)
    i = int(np.argmin(np.abs(e.phi_rad)))
    # the tooth on the major axis stands centred in its space: both flanks see the backlash along the normal
    expect = geo.backlash_mm * math.cos(e.pressure_angle_rad[i]) * e.cs_radius_mm[i] / geo.cs_space.pitch_radius_mm
    assert e.clearance_pos_mm[i] == pytest.approx(expect, rel=0.05)
    assert e.clearance_neg_mm[i] == pytest.approx(expect, rel=0.05)
    # every overlapping tooth lies within the kinematic zone (w0 cos 2 phi beats the tip gap)
    zone = engagement_zone_rad(geo)
    phi = np.abs(np.angle(np.exp(2j * e.phi_rad))) / 2
    assert np.all(phi <= zone + 1e-9)


def test_study_loads_are_numbers_the_contact_solver_accepts():
    m = study_loads(load_params(None), quick=True)["mesh"]
    for pairs in m["angles"]:
        assert np.all(pairs["clearance_mm"] >= 0) and set(np.unique(pairs["side"])) == {-1, 1}
        assert np.all(np.sign(pairs["lever_mm"]) == pairs["side"])


class _Book:
    def __init__(self, value, unc):
        h = (0.24, 0.336, 0.4704)
        vals = (value, value * (1 - unc / 3), value * (1 - unc / 3 * 1.4 ** 4))
        self.q = Quantity(tmc.PAIR, value, "N/(mm*um)", grid_convergence(h, vals, formal_order=4.0))

    def quantity(self, label, name):
        return self.q, ""


# the FE's pair stiffness of the default gear (make validate: 18.04 N/(mm um), GCI ~0.2 %)
FE_DEFAULT = 18.04


def test_pair_check_passes_on_the_fe_value_and_fails_on_a_perturbed_reference(monkeypatch):
    params = load_params(None)
    c = tmc.pair_check(_Book(FE_DEFAULT, 0.002), "tooth-mesh", params)
    assert c.passed, c
    ref = tmc.pair_reference(params)
    for f in (0.8, 1.2):
        monkeypatch.setattr(tmc, "pair_reference", lambda p, f=f: type(ref)(None, ref.corrected * f, ref.unit, ref.source))
        assert not tmc.pair_check(_Book(FE_DEFAULT, 0.002), "tooth-mesh", params).passed
