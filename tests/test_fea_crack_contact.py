"""Frictionless crack-face contact (fea.crack_contact) on the plane-strain edge-cracked strip of
test_fea_crack_seam: under tension the faces open and contact changes nothing; under compression across the
crack plane (no shear on it) the crack closes and the strip is exactly as stiff as the uncracked one."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.assembly import Lame
from strainwave.fea.crack_contact import crack_pairs, solve_with_contact
from strainwave.fea.crack_seam import open_crack
from strainwave.fea.solver import solve_elasticity
from strainwave.fea.static import _assemble

from test_fea_crack_seam import B, E, HS, NU, SIGMA, _mesh


def _compliances(md, sign: float, contact: bool) -> float:
    from strainwave.fea.mesh_data import to_skfem
    sk = to_skfem(md)
    z = md.group_nodes("zfaces")
    c0 = int(np.argmin(np.linalg.norm(md.nodes_mm - [B, 0, 0], axis=1)))
    c1 = int(np.argmin(np.linalg.norm(md.nodes_mm - [B, 2 * HS, 0], axis=1)))
    fixed = np.concatenate([3 * sk.node_to_dof[z] + 2, 3 * sk.node_to_dof[[c0, c0, c1]] + [0, 1, 0]])
    tractions = {"top": lambda x: np.stack([0 * x[0], 0 * x[0] + sign * SIGMA, 0 * x[0]]),
                 "bottom": lambda x: np.stack([0 * x[0], 0 * x[0] - sign * SIGMA, 0 * x[0]])}
    sk, K, f, dofs, vals = _assemble(md, Lame.from_young(E, NU), None, fixed, 0.0, tractions, None, None,
                                     "test", lambda m: None)

    def linear(Kc, fc, fixed_c):
        return solve_elasticity(Kc, fc, fixed_dofs=fixed_c, coords=sk.doflocs, dim=3, method="direct")[0]
    if contact:
        res = solve_with_contact(K, f, dofs, crack_pairs(md).in_dofs(sk.node_to_dof), linear)
        return float(f @ res.u), res
    return float(f @ linear(K, f, dofs)), None


@pytest.fixture(scope="module")
def seam():
    md = _mesh(True, 2)
    return md, open_crack(md)


def test_tension_opens_the_crack_and_contact_changes_nothing(seam):
    md, opened = seam
    linear, _ = _compliances(opened, +1.0, False)
    with_contact, res = _compliances(opened, +1.0, True)
    closed, _ = _compliances(md, +1.0, False)
    assert linear > 1.01 * closed                   # the crack adds compliance in tension
    assert with_contact == pytest.approx(linear, rel=1e-9)
    assert not res.active.any() and res.opening_mm.min() >= 0.0


def test_compression_closes_the_crack(seam):
    md, opened = seam
    closed, _ = _compliances(md, -1.0, False)
    linear, _ = _compliances(opened, -1.0, False)
    with_contact, res = _compliances(opened, -1.0, True)
    assert linear > 1.01 * closed                   # without contact the faces pass through each other
    assert with_contact == pytest.approx(closed, rel=1e-6)
    # shut everywhere (P2 vertex pairs of a uniform pressure carry ~zero nodal force, so some stay inactive
    # at zero opening); no pair pulls
    assert res.active.any() and res.opening_mm.min() > -1e-9 * np.abs(res.u).max()
    assert (res.contact_force_N[res.active] >= 0.0).all()
