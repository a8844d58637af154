"""The flexspline's torsional buckling: a linear buckling eigenvalue of the cup's wall as a full tube.

The tube is ``wg_band``'s wall (bore to root circle, from the diaphragm's mid-plane to the open rim) meshed
over the full circumference (a torsional buckling mode is helical: no symmetry plane holds it), in the same
27-node hexahedra, one through the wall, mapped onto the cylinder. Linear buckling:

    (K0 + lambda K_G(sigma_1)) phi = 0,

K0 the linear stiffness (``wg_band.assemble``), K_G the geometric stiffness (the d_ik S_JL term of
``wg_band``'s total-Lagrangian tangent) of sigma_1, the FE's own stress of the uniform twist u = beta z x r
(Saint-Venant's torsion of a tube, interpolated in the element space), scaled to the torque T_1 it carries
(the volume mean of r tau_theta z over the length). The buckling torque is lambda T_1.

Ends simply supported, as the closed form (analytic/cylinder_buckling.py): on both end faces u_r = u_theta
= 0 (w = 0 and the helical wave's circumferential restraint; the section turns free about the circumference),
u_z = 0 on the mid-wall circle only. The eigenvalue: Lanczos on K0^-1 K_G (the largest |mu| = 1/|lambda|),
K0 factorised once.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from strainwave.errors import StageError
from strainwave.fea.assembly import Lame
from strainwave.fea.wg_band import Tube, TubeGeometry, _element_dofs, _gradients, _state, _on, cylindrical_basis

__all__ = ["full_tube_mesh", "geometric_stiffness", "buckling_torque", "BucklingSolve", "STUDY"]

STUDY = "cup-buckling"
# ARPACK's relative accuracy of the eigenvalue: far below the GCI (~1e-2), far above round-off
EIG_TOL = 1e-8


def full_tube_mesh(geo: TubeGeometry, n_theta: int) -> Tube:
    """The whole wall: ``n_theta`` elements around, square-ish along z, one through the wall. The straight
    P2 mesh of the merged lattice, with every node moved out onto its own radius (a node between two vertex
    angles sits cos(dtheta/2) inside it on the chord)."""
    from skfem import MeshHex, MeshHex2

    h = 2.0 * math.pi * geo.r_m_mm / n_theta
    nz = max(2, round((geo.length_mm - geo.z_end_mm) / h))
    th = np.linspace(0.0, 2.0 * math.pi, n_theta + 1)
    pm = MeshHex.init_tensor(np.array([geo.r_i_mm, geo.r_o_mm]), th, np.linspace(geo.z_end_mm, geo.length_mm, nz + 1))
    r, t, z = pm.p
    wrap = np.isclose(t, 2.0 * math.pi)
    key = {(round(a, 9), round(c, 9)): i for i, (a, b, c) in enumerate(pm.p.T) if b == 0.0}
    to = np.arange(pm.p.shape[1])
    to[wrap] = [key[(round(a, 9), round(c, 9))] for a, c in zip(r[wrap], z[wrap])]
    keep = np.flatnonzero(~wrap)
    new = np.full(pm.p.shape[1], -1)
    new[keep] = np.arange(keep.size)
    cells = new[to[pm.t]]
    p = np.array([r[keep] * np.cos(t[keep]), r[keep] * np.sin(t[keep]), z[keep]])
    m2 = MeshHex2.from_mesh(MeshHex(p, cells))
    x = m2.doflocs.copy()
    ang = np.arctan2(x[1], x[0]) % (2.0 * math.pi)
    step = 2.0 * math.pi / n_theta
    between = ~np.isclose(np.mod(ang / step + 0.5, 1.0) - 0.5, 0.0, atol=1e-6)
    x[:2, between] /= math.cos(0.5 * step)
    mesh = MeshHex2(x, m2.t)
    return Tube(geo, None, mesh, *cylindrical_basis(mesh), h)


def twist_state(tube: Tube, lame: Lame) -> tuple[np.ndarray, float]:
    """(Hooke's stress (element, point, J, L) of the uniform twist u = z (-y, x) (unit rotation per length), the
    torque it carries in N mm: the volume mean of r tau_theta_z divided by the length)."""
    x = tube.basis.doflocs
    u = np.zeros(tube.dofs)
    u[tube.comp[0]], u[tube.comp[1]] = -x[2] * x[1], x[2] * x[0]
    G, edofs = _gradients(tube.basis), _element_dofs(tube.basis)
    ne, _, na = G.shape[:3]
    _, S = _state(G, u[edofs].reshape(ne, na, 3), lame, False)
    xq = tube.basis.global_coordinates().value            # (3, element, point)
    # r tau_theta_z = x sigma_yz - y sigma_xz
    moment = xq[0] * S[:, :, 1, 2] - xq[1] * S[:, :, 0, 2]
    torque = float(np.sum(moment * tube.basis.dx)) / (tube.geo.length_mm - tube.geo.z_end_mm)
    return S, torque


def geometric_stiffness(tube: Tube, S: np.ndarray) -> sp.csr_matrix:
    """K_G = sum_q w dN_a/dX_J S_JL dN_b/dX_L delta_ik, in ``Tube.pattern``'s slots (element, a, i, k, b)."""
    G, dx = _gradients(tube.basis), tube.basis.dx
    ne, nq, na = G.shape[:3]
    M = np.einsum("eqaJ,eqJL,eqbL,eq->eab", G, S, G, dx, optimize=True)
    Ke = M[:, :, None, None, :] * np.eye(3)[None, None, :, :, None]
    slots, indices, indptr = tube.pattern
    return sp.csr_matrix((np.bincount(slots, Ke.ravel(), minlength=indices.size), indices, indptr),
                         shape=(tube.dofs, tube.dofs))


def end_dofs(tube: Tube) -> np.ndarray:
    """Nodal-frame dofs held: u_r, u_theta on both end faces; u_z at one point only (the rigid axial shift):
    the ends are free axially, N_x = 0, as the closed form's stress function has it (F = F_xx = 0 there)."""
    geo, c = tube.geo, tube.comp
    ends = _on(tube.z, geo.z_end_mm, geo.length_mm) | _on(tube.z, geo.length_mm, geo.length_mm)
    one = np.flatnonzero(ends & _on(tube.r, geo.r_m_mm, geo.r_m_mm))[:1]
    return np.unique(np.concatenate([c[0][ends], c[1][ends], c[2][one]]))


@dataclass(frozen=True)
class BucklingSolve:
    torque_Nmm: float          # the least buckling torque (either sense)
    dofs: int
    h_mm: float
    n_waves: int               # circumferential waves of the mode at the band's mid-length (sign changes / 2)


def buckling_torque(geo: TubeGeometry, lame: Lame, n_theta: int, modes: int = 2) -> BucklingSolve:
    """The least |lambda| T_1 of the tube with ``n_theta`` elements around (module docstring)."""
    import scipy.sparse.linalg as spla
    from strainwave.fea.solver import condense, schur_factor

    tube = full_tube_mesh(geo, n_theta)
    K0 = (tube.rot_t @ _assemble_linear(tube, lame) @ tube.rot).tocsr()
    S, torque = twist_state(tube, lame)
    KG = (tube.rot_t @ geometric_stiffness(tube, S) @ tube.rot).tocsr()
    keep = np.ones(tube.dofs, bool)
    keep[end_dofs(tube)] = False
    A, B = condense(K0, keep), condense(KG, keep)
    factor = schur_factor(A, np.zeros(0, np.int64), STUDY)     # no tail: K0's factors and their solves
    n = A.shape[0]
    op = spla.LinearOperator((n, n), matvec=lambda v: np.asarray(factor.solve(B @ v)).ravel(), dtype=float)
    try:
        # a fixed start vector: ARPACK's random one moves the eigenvalue in its 13th digit from run to run
        v0 = np.random.default_rng(0).standard_normal(n)
        mu, vec = spla.eigs(op, k=modes, which="LM", tol=EIG_TOL, v0=v0)
    except spla.ArpackNoConvergence as exc:
        raise StageError("solve", STUDY, f"the buckling eigenvalues did not converge: {exc}") from None
    finally:
        factor.close()
    j = int(np.argmax(np.abs(mu.real)))
    phi = np.zeros(tube.dofs)
    phi[keep] = vec[:, j].real
    return BucklingSolve(torque / abs(mu[j].real), tube.dofs, tube.h_mm, _waves(tube, phi))


def _assemble_linear(tube: Tube, lame: Lame) -> sp.csr_matrix:
    from strainwave.fea.wg_band import assemble
    return assemble(tube, np.zeros(tube.dofs), lame, False)[0]


def _waves(tube: Tube, phi: np.ndarray) -> int:
    """Circumferential waves of the mode's radial displacement on the bore at mid-length."""
    geo = tube.geo
    zm = 0.5 * (geo.z_end_mm + geo.length_mm)
    zs = np.unique(tube.z)
    at = _on(tube.r, geo.r_i_mm, geo.r_i_mm) & _on(tube.z, zs[np.argmin(np.abs(zs - zm))], geo.length_mm)
    order = np.argsort(tube.phi[at])
    w = phi[tube.comp[0][at]][order]
    return int(np.count_nonzero(np.sign(w) != np.sign(np.roll(w, 1))) // 2)
