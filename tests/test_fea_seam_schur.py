"""An opened seam crack solved by one factorisation with the Schur complement on the crack pairs' openings
(fea/face_schur.py ``SeamSystem``, the bearing ring's route): every pair tied is the closed seam mesh's own solve,
and the frictionless contact set, its displacement and its compliance are those of the sparse active set
(fea/crack_contact.py ``solve_with_contact``). A small block with an edge crack, P1 tets built without gmsh."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.assembly import Lame, elasticity_stiffness, scalar_basis
from strainwave.fea.mesh_data import MeshData, to_skfem

B, H, W, A = 1.0, 1.0, 0.5, 0.5        # block x, y, z; the crack: y = H/2, 0 <= x <= A, through z (mouth at x = 0)


def _seam_block() -> MeshData:
    """Tensor tets; the crack facets are the cells' faces in y = H/2 at x < A."""
    import skfem
    mesh = skfem.MeshTet.init_tensor(np.linspace(0.0, B, 7), np.linspace(0.0, H, 7), np.linspace(0.0, W, 4))
    p, t = mesh.p.T, mesh.t.T
    faces = np.unique(np.sort(np.vstack([t[:, list(f)] for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))]),
                              axis=1), axis=0)
    x = p[faces]
    crack = faces[np.all(np.isclose(x[..., 1], H / 2), axis=1) & (x[..., 0].max(axis=1) <= A + 1e-12)]
    return MeshData(p.copy(), t.copy(), 3, 1, {"crack": crack})


def _system(md: MeshData):
    """K, the loads (top face: y-pull growing with x, a shear along x) and the fixed bottom face, in dofs."""
    sk = to_skfem(md)
    K = elasticity_stiffness(scalar_basis(sk.mesh, sk.element), Lame.from_young(2.0e5, 0.3))
    x = md.nodes_mm
    f = np.zeros(K.shape[0])
    top = np.flatnonzero(np.isclose(x[:, 1], H))
    # the crack's mouth side (x < 0.3) pushed shut, its tip side pulled open: a mixed contact set
    f[3 * sk.node_to_dof[top] + 1] = x[top, 0] - 0.3
    f[3 * sk.node_to_dof[top]] = 0.1
    bottom = sk.node_to_dof[np.flatnonzero(np.isclose(x[:, 1], 0.0))]
    return sk, K, f, (3 * bottom[:, None] + np.arange(3)).ravel()


def _direct(K, f, fixed, sk):
    from strainwave.fea.solver import solve_elasticity
    return solve_elasticity(K, f, fixed_dofs=fixed, coords=sk.doflocs, dim=3, method="direct")[0]


@pytest.fixture(scope="module")
def seam():
    from strainwave.fea.crack_contact import crack_pairs
    from strainwave.fea.crack_seam import open_crack
    from strainwave.fea.face_schur import SeamSystem
    md = _seam_block()
    opened = open_crack(md)
    sk, K, f, fixed = _system(opened)
    pairs = crack_pairs(opened).in_dofs(sk.node_to_dof)
    system = SeamSystem.of(K, fixed, pairs, "test")
    yield md, opened, sk, K, f, fixed, pairs, system
    system.close()


def test_every_pair_tied_is_the_closed_seam_mesh(seam):
    md, opened, sk, K, f, fixed, pairs, system = seam
    sk0, K0, f0, fixed0 = _system(md)
    closed = float(f0 @ _direct(K0, f0, fixed0, sk0))
    ft, r = system.loads(f)
    tied = system.solution(ft, r, np.ones(r.size, bool))
    assert float(f @ tied) == pytest.approx(closed, rel=1e-11)
    # the same nodes joined: each + copy moves with its original
    assert np.abs(tied.reshape(-1, 3)[pairs.plus] -
                  tied.reshape(-1, 3)[pairs.minus]).max() <= 1e-12 * np.abs(tied).max()
    # holding only the normal openings (the faces slide) is another, softer ring: the comparison can fail
    sliding = system.solution(ft, r, system.held(np.ones(pairs.minus.size, bool)))
    assert float(f @ sliding) > (1.0 + 1e-3) * closed


def test_the_contact_set_through_the_schur_complement_is_the_sparse_active_set(seam):
    from strainwave.fea.crack_contact import solve_with_contact
    from strainwave.fea.face_schur import open_compliance
    md, opened, sk, K, f, fixed, pairs, system = seam
    old = solve_with_contact(K, f, fixed, pairs, lambda Kc, fc, fx: _direct(Kc, fc, fx, sk))
    ft, r = system.loads(f)
    new = system.contact(ft, r)
    assert 0 < new.active.sum() < new.active.size          # a mixed set: some pairs shut, some open
    assert np.array_equal(new.active, old.active) and new.iterations == old.iterations
    scale = np.abs(old.u).max()
    assert np.abs(new.u - old.u).max() <= 1e-10 * scale
    assert np.abs(new.u_unconstrained - old.u_unconstrained).max() <= 1e-10 * scale
    assert np.abs(new.opening_mm - old.opening_mm).max() <= 1e-10 * scale
    # the crack's compliance from S's open block is f.u (contact) - f.u (tied), without the difference
    tied = float(f @ system.solution(ft, r, np.ones(r.size, bool)))
    delta = open_compliance(system.faces.factor.S, r, system.held(new.active))
    assert delta == pytest.approx(float(f @ old.u) - tied, rel=1e-8)
    # the crack free of contact (faces passing through each other) adds more: the comparison can fail
    assert open_compliance(system.faces.factor.S, r, np.zeros(r.size, bool)) > (1.0 + 1e-3) * delta
