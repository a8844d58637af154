"""The flexspline cup's wall on the wave generator: mesh, forms and solves of study ``cup-wave-generator``.

The wall is the cup's cylinder (bore d1/2 - delta to d1/2, ``geometry/flexspline_cup.py``) from the
diaphragm's mid-plane to the open rim; the diaphragm and hub are replaced by the end held round (u_r = u_theta
= 0 on the end face, u_z = 0 on its mid-wall circle: a diaphragm is stiff in its plane and free to bend).
The mesh is a structured lattice in (r, theta, z) of 27-node hexahedra (P2, one through the wall: the
bending strain is linear through it), mapped exactly onto the cylinder, over one quarter: the wave
generator's cos 2 phi is symmetric about both axes. Every dof point carries its own cylindrical frame (the
stiffness is rotated node by node), so the cam's radial constraint, the symmetry planes and the held end are
plain Dirichlet conditions.

Kinematics: linear, or total Lagrangian with the Green-Lagrange strain and St Venant-Kirchhoff (Newton: each
step's tangent, and the torque's on a nonlinear state, solved by conjugate gradients preconditioned by the one
factorisation of the linear stiffness K0, docs/decisions/061-wg-newton.md).
The torque acts on top of the inserted state: the tangent stiffness at that state, loaded by a uniform
tangential shear on the band's outer surface; on the quarter the torque increment is antisymmetric about
both planes (u_r = u_z = 0 there), which is exact for the tangent problem of a symmetric state.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from strainwave.errors import InputError, StageError
from strainwave.fea.assembly import Lame

STUDY = "cup-wave-generator"
TOL_MM = 1e-7


@dataclass(frozen=True)
class TubeGeometry:
    r_i_mm: float              # bore
    r_o_mm: float              # outer radius (the tooth root circle: teeth stand on the wall)
    z_end_mm: float            # the held-round end (diaphragm mid-plane)
    length_mm: float           # the open rim
    band_mm: float             # tooth band width, ending at the rim

    def __post_init__(self):
        # the band's bore is the cam's; a band reaching the held end would hold the same points twice (no such cup)
        if self.band_start_mm <= self.z_end_mm:
            raise InputError("cup length_mm", round(self.length_mm, 6),
                             shortest_cup_message(self.z_end_mm, self.band_mm))

    @property
    def r_m_mm(self) -> float:
        return 0.5 * (self.r_i_mm + self.r_o_mm)

    @property
    def wall_mm(self) -> float:
        return self.r_o_mm - self.r_i_mm

    @property
    def band_start_mm(self) -> float:
        return self.length_mm - self.band_mm


def shortest_cup_message(z_end_mm: float, band_mm: float) -> str:
    """What a cup's length must exceed: the tooth band at the open end starts above the diaphragm's mid-plane."""
    return (f"must be > {z_end_mm + band_mm:.4g} mm: the tooth band ({band_mm:.4g} mm at the open end) must start "
            f"above the diaphragm's mid-plane ({z_end_mm:.4g} mm from the closed end)")


def tube_geometry(params) -> TubeGeometry:
    from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS
    fc = params.flexspline_cup
    t = fc.wall_thickness_mm
    return TubeGeometry(0.5 * fc.pitch_diameter_mm - t, 0.5 * fc.pitch_diameter_mm, (BOSS_HEIGHT_WALLS - 0.5) * t,
                        fc.length_mm, BAND_RATIO * fc.pitch_diameter_mm)


@dataclass
class Tube:
    """Mesh, scalar P2 basis and the dof table: dof 3 s + k is component k (x, y, z; in the rotated frame
    r, theta, z) of scalar dof point s at (r, phi, z); ``comp[k]`` lists them for every point."""

    geo: TubeGeometry
    param_mesh: object
    mesh: object
    basis: object               # scalar ElementHex2 CellBasis (27-point Gauss)
    comp: np.ndarray
    r: np.ndarray
    phi: np.ndarray
    z: np.ndarray
    rot: sp.csr_matrix          # u_cartesian = rot @ u_cylindrical
    h_mm: float
    samplers: dict = field(default_factory=dict, repr=False, compare=False)   # stresses_at's located points

    @functools.cached_property
    def pattern(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The stiffness's CSR pattern (indices, indptr) and the slot of each element-matrix entry K_aibk in it, in
        ``assemble``'s order (element, a, i, k, b): every assembly sums into the same slots, no COO sort per Newton
        step. Found on the node pairs (9x fewer than the entries), each a 3x3 block of the scalar pattern."""
        nodes = self.basis.element_dofs.T                       # (element, a)
        n = self.basis.N
        pairs, pair = np.unique((nodes[:, :, None] * n + nodes[:, None, :]).ravel(), return_inverse=True)
        rows = pairs // n
        ptr = np.searchsorted(pairs, np.arange(n + 1) * n)
        width = np.diff(ptr)                                    # node pairs per node row
        pair = pair.reshape(nodes.shape[0], nodes.shape[1], nodes.shape[1])
        row = rows[pair]
        first, w3 = 9 * ptr[row] + 3 * (pair - ptr[row]), 3 * width[row]
        i = np.arange(3)
        slots = first[:, :, None, None, :] + i[:, None, None] * w3[:, :, None, None, :] + i[:, None]
        p = np.arange(pairs.size)
        at = 9 * ptr[rows] + 3 * (p - ptr[rows])                # each pair's block in its node row's three rows
        indices = np.empty(9 * pairs.size, np.int64)
        indices[(at[:, None, None] + i[:, None] * 3 * width[rows][:, None, None] + i).reshape(-1)] = \
            np.broadcast_to(3 * (pairs % n)[:, None, None] + i, (pairs.size, 3, 3)).reshape(-1)
        indptr = np.concatenate([[0], np.cumsum(np.repeat(3 * width, 3))])
        return slots.reshape(-1), indices, indptr

    @functools.cached_property
    def rot_t(self) -> sp.csr_matrix:
        """rot^T in CSR (rot.T is CSC: every product with it would convert)."""
        return self.rot.T.tocsr()

    @property
    def dofs(self) -> int:
        return 3 * self.basis.N

    @property
    def elements(self) -> int:
        return self.mesh.t.shape[1]


def _axial_grid(geo: TubeGeometry, h_mm: float) -> np.ndarray:
    below = max(2, round((geo.band_start_mm - geo.z_end_mm) / h_mm))
    # h/2 along the band, an even count: its mid-width is a node plane and the axial stress gradients of the
    # band's junction with the coned wall are resolved where the axes' stresses are read
    band = 2 * max(2, round(geo.band_mm / h_mm))
    return np.concatenate([np.linspace(geo.z_end_mm, geo.band_start_mm, below + 1),
                           np.linspace(geo.band_start_mm, geo.length_mm, band + 1)[1:]])


def tube_mesh(geo: TubeGeometry, n_theta: int) -> Tube:
    """The quarter wall with ``n_theta`` elements around, square-ish elements along z, one through the wall."""
    from skfem import MeshHex, MeshHex2

    h = 0.5 * math.pi * geo.r_m_mm / n_theta
    pm = MeshHex.init_tensor(np.array([geo.r_i_mm, geo.r_o_mm]), np.linspace(0.0, 0.5 * math.pi, n_theta + 1),
                             _axial_grid(geo, h))
    p2 = MeshHex2.from_mesh(pm)
    r, th, z = p2.doflocs
    mesh = MeshHex2(np.array([r * np.cos(th), r * np.sin(th), z]), p2.t)
    return Tube(geo, pm, mesh, *cylindrical_basis(mesh), h)


def cylindrical_basis(mesh) -> tuple:
    """(P2 vector basis, its dofs by component, r, phi, z at the dofs, the rotation from (r, phi, z) dofs to
    Cartesian ones) of a hexahedral tube mesh: the fields of ``Tube`` after its mesh."""
    from skfem import CellBasis, ElementHex2

    basis = CellBasis(mesh, ElementHex2(), intorder=5)
    x = basis.doflocs
    rr, pp = np.hypot(x[0], x[1]), np.arctan2(x[1], x[0])
    comp = 3 * np.arange(basis.N) + np.arange(3)[:, None]
    c, s = np.cos(pp), np.sin(pp)
    rows = np.concatenate([comp[0], comp[0], comp[1], comp[1], comp[2]])
    cols = np.concatenate([comp[0], comp[1], comp[0], comp[1], comp[2]])
    vals = np.concatenate([c, -s, s, c, np.ones_like(c)])
    rot = sp.csr_matrix((vals, (rows, cols)), shape=(3 * basis.N, 3 * basis.N))
    return basis, comp, rr, pp, x[2], rot


# ---- St Venant-Kirchhoff, total Lagrangian (linear: F = I, S = 0 in the tangent, Hooke's stress) ----

def _gradients(basis) -> np.ndarray:
    """(element, point, a, J): dN_a/dX_J of the 27 scalar shape functions."""
    return np.stack([basis.basis[a][0].grad for a in range(len(basis.basis))]).transpose(2, 3, 0, 1)


def _element_dofs(basis) -> np.ndarray:
    """(element, 3 a + k) global dofs."""
    return (3 * basis.element_dofs.T[:, :, None] + np.arange(3)).reshape(basis.element_dofs.shape[1], -1)


def _state(G: np.ndarray, Ue: np.ndarray, lame: Lame, nonlinear: bool):
    """(F, S) at every point: deformation gradient (I when linear) and 2nd Piola-Kirchhoff (linear: Hooke)."""
    gu = np.matmul(Ue.transpose(0, 2, 1)[:, None], G)          # (e, q, k, J): du_k/dX_J
    ident = np.eye(3)
    F = ident + gu if nonlinear else np.broadcast_to(ident, gu.shape)
    strain = 0.5 * (np.matmul(F.swapaxes(2, 3), F) - ident) if nonlinear else 0.5 * (gu + gu.swapaxes(2, 3))
    tr = np.trace(strain, axis1=2, axis2=3)[..., None, None]
    return F, lame.lam_MPa * tr * ident + 2.0 * lame.mu_MPa * strain


# elements per batch of the element matrices: a batch's intermediates stay in cache (decision 043)
ELEMENT_CHUNK = 16


def _tangent_moduli(F: np.ndarray, S: np.ndarray, lame: Lame, nonlinear: bool) -> np.ndarray:
    """A (element, point, J, i, k, L) = dP_iJ/dF_kL of St Venant-Kirchhoff: F_iI C_IJKL F_kK, plus d_ik S_JL
    when nonlinear (the geometric stiffness); stored J-first so the element matrices need no large transpose."""
    lam, mu = lame.lam_MPa, lame.mu_MPa
    ident = np.eye(3)
    Ft = F.swapaxes(2, 3)
    A = np.empty(F.shape[:2] + (3, 3, 3, 3))
    np.multiply(Ft[:, :, :, :, None, None], lam * F[:, :, None, None, :, :], out=A)     # lam F_iJ F_kL
    A += mu * np.matmul(F, Ft)[:, :, None, :, :, None] * ident[:, None, None, :]       # mu (F F^T)_ik d_JL
    A += mu * F[:, :, None, :, None, :] * Ft[:, :, :, None, :, None]                   # mu F_iL F_kJ
    if nonlinear:
        A += ident[None, :, :, None] * S[:, :, :, None, None, :]                       # d_ik S_JL
    return A


def assemble(tube: Tube, u: np.ndarray, lame: Lame, nonlinear: bool) -> tuple[sp.csr_matrix, np.ndarray]:
    """(tangent stiffness, internal force vector) at ``u`` (Cartesian dofs), vectorised over elements:
    K_aibk = sum_q w dN_a/dX_J A_iJkL dN_b/dX_L, f_ai = sum_q w dN_a/dX_J P_iJ (P = F S)."""
    G, dx, edofs = _gradients(tube.basis), tube.basis.dx, _element_dofs(tube.basis)
    ne, nq, na = G.shape[:3]
    F, S = _state(G, u[edofs].reshape(ne, na, 3), lame, nonlinear)
    Gt = G.transpose(0, 2, 1, 3).reshape(ne, na, nq * 3)                                # (e, a, (q, J))
    P = np.matmul(F, S) * dx[:, :, None, None]                                          # (e, q, i, J)
    fe = np.matmul(Gt, P.swapaxes(2, 3).reshape(ne, nq * 3, 3))
    Ke = np.empty((ne, na, 9 * na))                                                      # (e, a, (i, k, b))
    for c in range(0, ne, ELEMENT_CHUNK):
        e = slice(c, c + ELEMENT_CHUNK)
        A = _tangent_moduli(F[e], S[e], lame, nonlinear) * dx[e, :, None, None, None, None]
        # contractions as batched matrix products (BLAS): over L for every point, then over (q, J) per element
        W = np.matmul(A.reshape(-1, nq, 9, 3, 3), G[e].swapaxes(2, 3)[:, :, None])     # (e, q, (J, i), k, b)
        np.matmul(Gt[e], W.reshape(-1, nq * 3, 9 * na), out=Ke[e])
    slots, indices, indptr = tube.pattern
    K = sp.csr_matrix((np.bincount(slots, Ke.ravel(), minlength=indices.size), indices, indptr),
                      shape=(tube.dofs, tube.dofs))
    return K, np.bincount(edofs.ravel(), fe.ravel(), minlength=tube.dofs)


def band_outer_loads(tube: Tube) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(load vector of a unit tangential shear, twist functional g (twist = g.u, the area-weighted mean
    rotation), quarter moment arm int r dA, quarter area) on the band's outer surface: the band's elements at
    their outer reference face (one element through the wall), the facet rule of intorder 6."""
    cb, x, r, dA = band_outer_quadrature(tube, 6)
    e_theta, rot_weight = np.stack([-x[1], x[0]]) / r, np.stack([-x[1], x[0]]) / r ** 2
    N = np.stack([cb.basis[a][0].value for a in range(len(cb.basis))]) * dA      # (a, element, point)
    dofs = cb.element_dofs.ravel()                                               # (a, element) scalar dofs
    shear, turn = np.zeros(tube.dofs), np.zeros(tube.dofs)
    for k in (0, 1):
        shear += np.bincount(3 * dofs + k, np.sum(N * e_theta[k], axis=2).ravel(), minlength=tube.dofs)
        turn += np.bincount(3 * dofs + k, np.sum(N * rot_weight[k], axis=2).ravel(), minlength=tube.dofs)
    arm, area = float(np.sum(r * dA)), float(np.sum(dA))
    return shear, turn / area, arm, area


def band_outer_quadrature(tube: Tube, intorder: int) -> tuple:
    """(basis on the band's elements at their outer reference face, the points x (3, element, point), their
    radius, their area weights dA): the facet rule of ``intorder`` on the band's outer surface."""
    from skfem import CellBasis
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefQuad

    geo, pm = tube.geo, tube.param_mesh
    elements = np.flatnonzero(pm.p[2, pm.t].min(axis=0) > geo.band_start_mm - TOL_MM)
    axis, value = _outer_face(tube, elements)
    tangent = [j for j in range(3) if j != axis]
    st, w = get_quadrature(RefQuad, intorder)
    X = np.empty((3, st.shape[1]))
    X[axis], X[tangent] = value, st
    cb = CellBasis(tube.mesh, tube.basis.elem, elements=elements, quadrature=(X, w))
    x = cb.global_coordinates().value
    DF = cb.mapping.DF(X, tind=elements)            # (i, J, element, point)
    dA = np.linalg.norm(np.cross(DF[:, tangent[0]], DF[:, tangent[1]], axis=0), axis=0) * w
    return cb, x, np.hypot(x[0], x[1]), dA


def _outer_face(tube: Tube, elements: np.ndarray) -> tuple[int, float]:
    """(reference axis, its value) of the face that every one of ``elements`` has on the outer radius."""
    from skfem.refdom import RefHex
    r = tube.param_mesh.p[0, tube.param_mesh.t[:, elements]]         # (vertex, element): the param mesh's r
    for axis in range(3):
        for value in (0.0, 1.0):
            if np.all(_on(r[RefHex.p[axis] == value], tube.geo.r_o_mm, tube.geo.r_o_mm)):
                return axis, value
    raise StageError("mesh", STUDY, "the band's elements share no reference face on the outer radius")


# ---- constraints in the nodal cylindrical frames ----

def _on(a: np.ndarray, value: float, scale: float) -> np.ndarray:
    return np.abs(a - value) < 1e-6 * scale


def held_dofs(tube: Tube, symmetric: bool) -> np.ndarray:
    """Rotated-frame dofs held at zero: symmetry planes (theta dof; antisymmetric: r and z dofs) and the end."""
    geo, c = tube.geo, tube.comp
    plane = _on(tube.phi, 0.0, 1.0) | _on(tube.phi, 0.5 * math.pi, 1.0)
    end = _on(tube.z, geo.z_end_mm, geo.length_mm)
    mid = end & _on(tube.r, geo.r_m_mm, geo.r_m_mm)
    on_plane = [c[1][plane]] if symmetric else [c[0][plane], c[2][plane]]
    return np.unique(np.concatenate(on_plane + [c[0][end], c[1][end], c[2][mid]]))


def band_bore_points(tube: Tube) -> np.ndarray:
    """Dof points of the band's bore, where the wave generator acts."""
    geo = tube.geo
    return np.flatnonzero(_on(tube.r, geo.r_i_mm, geo.r_i_mm) & (tube.z > geo.band_start_mm - TOL_MM))


def solve_constrained(tube: Tube, K: sp.csr_matrix, rhs: np.ndarray, fixed: np.ndarray,
                      values: np.ndarray) -> np.ndarray:
    """Solve K x = rhs (Cartesian) with rotated-frame dofs ``fixed`` = ``values``; returns Cartesian x."""
    from strainwave.fea.solver import _direct, condense

    Kc = (tube.rot_t @ K @ tube.rot).tocsr()
    x = np.zeros(tube.dofs)
    x[fixed] = values
    keep = np.ones(tube.dofs, bool)
    keep[fixed] = False
    b = (tube.rot_t @ rhs - Kc @ x)[keep]
    x[keep], _ = _direct(condense(Kc, keep), b, STUDY, node_blocks=True)
    return tube.rot @ x


@dataclass
class BoreSystem:
    """K in the nodal frames with ``held_dofs`` held, factorised once with its Schur complement S on the band
    bore's radial dofs that the base leaves free (``face_schur.FaceSystem``): every set of held bore points is
    then a dense solve of S's free block and back-substitutions, no factorisation."""

    faces: object               # face_schur.FaceSystem
    on_face: np.ndarray         # bool over band_bore_points: u_r free in the base (antisymmetric: off the planes)

    def close(self) -> None:
        self.faces.factor.close()


def bore_system(tube: Tube, K: sp.csr_matrix, symmetric: bool) -> BoreSystem:
    """``BoreSystem`` of K under the symmetric or antisymmetric conditions (the held end holds the band with the
    bore free)."""
    from strainwave.fea.face_schur import FaceSystem
    base, radial = held_dofs(tube, symmetric), tube.comp[0][band_bore_points(tube)]
    on_face = ~np.isin(radial, base)
    return BoreSystem(FaceSystem.of((tube.rot_t @ K @ tube.rot).tocsr(), base, radial[on_face], STUDY), on_face)


def held_solve(tube: Tube, system: BoreSystem, rhs: np.ndarray, active: np.ndarray, values) -> np.ndarray:
    """``solve_constrained`` through a ``BoreSystem``: K x = rhs (Cartesian) with its base held at 0 and the
    bore's radial dofs ``active`` (over band_bore_points) at ``values`` (a scalar or one per bore point);
    returns Cartesian x. One step of iterative refinement on the residual, with the same factors, brings the
    digits S's products lose to the bore's stiff radial coupling back to round-off."""
    fs, on = system.faces, system.on_face
    active = np.asarray(active, bool)[on]
    values = np.asarray(values, float)[on] if np.ndim(values) else values
    f = tube.rot_t @ rhs
    x = fs.held(f, fs.face_loads(f), active, values)
    res = f - fs.K @ x
    res[fs.base] = 0.0
    res[fs.face_z[active]] = 0.0
    x += fs.held(res, fs.face_loads(res), active)
    return tube.rot @ x


# ---- the wave generator's insertion: prescribed shape or rigid cam in frictionless contact ----

MAX_NEWTON = 25
MAX_ACTIVE_SET = 40
NEWTON_TOL = 1e-8          # |du|/|u|: Newton converges quadratically, the stresses are then fixed to ~1e-12


def cam_radius_mm(phi, r_bore_mm: float, w0_mm: float):
    """Polar radius of the rigid elliptical cam, semi-axes r_bore + w0 (major, phi = 0) and r_bore - w0."""
    a, b = r_bore_mm + w0_mm, r_bore_mm - w0_mm
    return a * b / np.hypot(b * np.cos(phi), a * np.sin(phi))


@dataclass
class Inserted:
    """The band on the wave generator: displacement, tangent stiffness there, which bore points the cam holds."""

    u: np.ndarray
    K: sp.csr_matrix
    active: np.ndarray           # bool over band_bore_points
    newton_iterations: int
    active_set_iterations: int
    nonlinear: bool


def _bore_target_mm(tube: Tube, u: np.ndarray, pts: np.ndarray, w0_mm: float, contact: bool,
                    nonlinear: bool) -> np.ndarray:
    """Radial displacement the wave generator asks of the bore points: w0 cos 2 phi at the material angle
    (prescribed), or the cam's radius at the point's angle (contact; nonlinear: its current angle, less the
    radius the tangential displacement adds, v^2/2r)."""
    r_i = tube.geo.r_i_mm
    if not contact:
        return w0_mm * np.cos(2.0 * tube.phi[pts])
    if not nonlinear:
        return cam_radius_mm(tube.phi[pts], r_i, w0_mm) - r_i
    v = (tube.rot_t @ u)[tube.comp[1][pts]]
    return cam_radius_mm(tube.phi[pts] + v / r_i, r_i, w0_mm) - r_i - 0.5 * v ** 2 / r_i


def _reassess(tube, R, u, bore, active, w0_mm, nonlinear) -> np.ndarray:
    """The active set at ``u``: a held point stays while the cam pushes it (reaction >= 0); a free point is
    taken up where it would enter the cam."""
    reaction = (tube.rot_t @ R)[tube.comp[0][bore]]
    gap = (tube.rot_t @ u)[tube.comp[0][bore]] - _bore_target_mm(tube, u, bore, w0_mm, True, nonlinear)
    return np.where(active, reaction >= 0.0, gap < -1e-6 * w0_mm)


def _insert_linear(tube: Tube, K0: sp.csr_matrix, w0_mm: float, contact: bool, system) -> Inserted:
    """The linear insertion through ``system`` (``bore_system`` of K0, symmetric: every bore point on its face):
    with the cam, its active set on S (docs/decisions/034-wave-generator-solves.md), then the state with the set
    held (``held_solve``, refined: docs/decisions/043-wave-generator-and-surface-crack-speed.md)."""
    bore = band_bore_points(tube)
    target = _bore_target_mm(tube, None, bore, w0_mm, contact, False)
    active, steps = _cam_active_set(system.faces.factor.S, np.zeros(bore.size), np.ones(bore.size, bool), target,
                                    np.full(bore.size, -1e-6 * w0_mm)) if contact else (np.ones(bore.size, bool), 1)
    return Inserted(held_solve(tube, system, np.zeros(tube.dofs), active, target), K0, active, steps, steps, False)


def _cam_active_set(S: np.ndarray, r: np.ndarray, active: np.ndarray, target: np.ndarray,
                    take_up: np.ndarray) -> tuple[np.ndarray, int]:
    """The cam's active set on the bore's radial dofs (True = held at ``target``) of the condensed system
    S u = r + reaction, from ``active``, and the sets tried: a held point stays while the cam pushes it
    (reaction >= 0), a free one is taken up where u - target < ``take_up``."""
    from strainwave.fea.solver import tail_solve
    for it in range(1, MAX_ACTIVE_SET + 1):
        u_r = tail_solve(S, r, active, target)
        reaction = S @ u_r - r          # the cam's reaction on the bore (0 off the set)
        now = np.where(active, reaction >= 0.0, u_r - target < take_up)
        if np.array_equal(now, active):
            return active, it
        active = now
    raise StageError("solve", STUDY, f"the cam's active set did not settle in {MAX_ACTIVE_SET} steps")


def insert(tube: Tube, lame: Lame, w0_mm: float, *, contact: bool, nonlinear: bool, K0=None,
           start: Inserted | None = None, system=None) -> Inserted:
    """The band forced onto the wave generator. Linear: ``_insert_linear`` through ``system`` (``bore_system``
    of K0, symmetric; made and freed here when None). Nonlinear: Newton and, with contact, the active set of
    the bore's radial dofs in one loop (a semi-smooth Newton): each step solves with the set that the step's
    own linearised contact problem settles on (``_contact_step``), then the set is reassessed at the new
    state; done when the set holds and the step is below NEWTON_TOL. With ``system`` every Newton step is a
    Krylov solve of the tangent preconditioned by K0's factors (``_tangent_step``), else a factorisation."""
    K0 = K0 if K0 is not None else assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    if not nonlinear:
        own = system is None
        system = bore_system(tube, K0, symmetric=True) if own else system
        try:
            return _insert_linear(tube, K0, w0_mm, contact, system)
        finally:
            if own:
                system.close()
    bore = band_bore_points(tube)
    # a start (the linear solution) gives the nonlinear solve its active set and first iterate
    active = np.ones(bore.size, bool) if start is None else start.active.copy()
    u = np.zeros(tube.dofs) if start is None else start.u.copy()
    converged, changes = False, 0
    for it in range(1, MAX_NEWTON + MAX_ACTIVE_SET + 1):
        K, R = assemble(tube, u, lame, True)
        if contact and it > 1:
            now = _reassess(tube, R, u, bore, active, w0_mm, True)
            changed, active = not np.array_equal(now, active), now
            changes += changed
            converged = converged and not changed
        if converged:
            return Inserted(u, K, active, it - 1, changes + 1, True)
        held, du = _contact_step(tube, K, R, u, bore, active if contact else None, w0_mm, system)
        active = active if held is None else held
        u = u + du
        converged = np.linalg.norm(du) <= NEWTON_TOL * np.linalg.norm(u)
    raise StageError("solve", STUDY, f"insertion did not converge in {it} Newton / active-set steps")


def _contact_step(tube: Tube, K, R, u, bore, active, w0_mm: float, system=None) -> tuple[np.ndarray, np.ndarray]:
    """One Newton step of the band on the cam (``active`` None: the prescribed shape, every bore point held):
    the step's linearised contact problem (cam radius at the current state) settled on a Schur complement S on
    the bore from ``active`` (``_cam_active_set``), then the step with that set held. ``system``: K0's
    symmetric ``bore_system``, whose S predicts the set and whose factors precondition a Krylov solve of the
    tangent (``_tangent_step``); without it, or when that stalls, K is factorised (with its own S on the bore
    under the cam). Returns (set, Cartesian step)."""
    prescribed = active is None
    f = -(tube.rot_t @ R)
    # the held points' radial step: onto the cam's radius (the prescribed shape) at the current state
    step = _bore_target_mm(tube, u, bore, w0_mm, not prescribed, True) - (tube.rot_t @ u)[tube.comp[0][bore]]
    take_up = np.full(bore.size, -1e-6 * w0_mm)
    if system is not None:      # the symmetric conditions leave every bore point's radial dof free
        held = np.ones(bore.size, bool) if prescribed else _cam_active_set(
            system.faces.factor.S, _condensed_load(system.faces, f), active, step, take_up)[0]
        du = _tangent_step(tube, K, f, system, held, step, KRYLOV_RTOL)
        if du is not None:
            return (None if prescribed else held), tube.rot @ du
    if prescribed:
        base = held_dofs(tube, symmetric=True)
        fixed = np.concatenate([base, tube.comp[0][bore]])
        return None, solve_constrained(tube, K, -R, fixed, np.concatenate([-(tube.rot_t @ u)[base], step]))
    own = bore_system(tube, K, symmetric=True)
    try:
        fs = own.faces
        r = fs.face_loads(f)
        held, _ = _cam_active_set(fs.factor.S, r, active, step, take_up)
        return held, tube.rot @ fs.held(f, r, held, step)
    finally:
        own.close()


def torque_increment(tube: Tube, state: Inserted, shear: np.ndarray, system=None) -> np.ndarray:
    """Displacement increment of the unit tangential shear on the band at the inserted state (tangent problem,
    antisymmetric about both planes; the cam holds the radial dofs it touches). ``system``: a ``bore_system``
    of K0, antisymmetric: the solve itself for a linear state (state.K is K0), the preconditioner of a Krylov
    solve of the state's tangent for a nonlinear one (``_tangent_step``; factorised when that stalls)."""
    if system is not None and not state.nonlinear:
        return held_solve(tube, system, shear, state.active, 0.0)
    if system is not None:
        du = _tangent_step(tube, state.K, tube.rot_t @ shear, system, state.active[system.on_face], 0.0,
                           KRYLOV_RTOL_EXACT)
        if du is not None:
            return tube.rot @ du
    bore = band_bore_points(tube)
    fixed = np.concatenate([held_dofs(tube, symmetric=False), tube.comp[0][bore[state.active]]])
    return solve_constrained(tube, state.K, shear, fixed, np.zeros(fixed.size))


# ---- the tangent's solves by preconditioned conjugate gradients (K0's factors as the preconditioner) ----

# relative residual of a Newton step's Krylov solve: the inexact Newton then converges about as fast as the exact
# one, and the last step, already below NEWTON_TOL, carries an error of a small fraction of itself
KRYLOV_RTOL = 1e-6
# the torque increment is read as a quantity (the torsional stiffness): solved to near round-off
KRYLOV_RTOL_EXACT = 1e-11
# iterations before a Krylov solve is abandoned for a factorisation of the tangent
MAX_KRYLOV = 40


def _condensed_load(fs, f: np.ndarray) -> np.ndarray:
    """``FaceSystem.face_loads`` of one load, by one forward substitution where PARDISO's partial solves exist."""
    if fs.factor.forward is None:
        return fs.face_loads(f)
    return np.asarray(fs.factor.forward(f[fs.free])).ravel()[np.searchsorted(fs.free, fs.face_z)]


def held_preconditioner(system: BoreSystem, active: np.ndarray):
    """r -> x: the nodal-frame solve of ``system``'s K (base held) with the face dofs ``active`` (over
    system.faces.face_z) held at zero, by one forward and one backward substitution of its factors with S's
    free block solved between them (PARDISO's partial solves; two full solves through ``FaceSystem.held``
    otherwise). SPD on the dofs left free: the preconditioner of ``_tangent_step``."""
    from scipy.linalg import cho_factor, cho_solve
    fs = system.faces
    active = np.asarray(active, bool)
    open_ = ~active
    chol = cho_factor(fs.factor.S[np.ix_(open_, open_)]) if open_.any() else None
    tail = np.searchsorted(fs.free, fs.face_z)

    def apply(r: np.ndarray) -> np.ndarray:
        if fs.factor.forward is None:
            return fs.held(r, fs.face_loads(r), active)
        x = np.zeros(r.shape)
        y = np.asarray(fs.factor.forward(r[fs.free])).ravel()
        u_tail = np.zeros(tail.size)
        if chol is not None:
            u_tail[open_] = cho_solve(chol, y[tail][open_])
        y[tail] = u_tail
        x[fs.free] = np.asarray(fs.factor.backward(y)).ravel()
        x[fs.face_z[active]] = 0.0
        return x
    return apply


def _tangent_step(tube: Tube, K: sp.csr_matrix, f: np.ndarray, system: BoreSystem, active: np.ndarray, values,
                  rtol: float) -> np.ndarray | None:
    """Nodal-frame solution of K x = f (K Cartesian, f in the nodal frames) with ``system``'s base held at zero
    and its face dofs ``active`` at ``values`` (per face dof, or one number), by conjugate gradients on the
    dofs left free, preconditioned by ``held_preconditioner`` (K is symmetric: St Venant-Kirchhoff's tangent).
    None when they do not reach ``rtol`` in MAX_KRYLOV iterations."""
    import scipy.sparse.linalg as spla
    fs = system.faces
    active = np.asarray(active, bool)
    x = np.zeros(tube.dofs)
    x[fs.face_z[active]] = np.broadcast_to(values, active.shape)[active] if np.ndim(values) else values
    keep = np.ones(tube.dofs)
    keep[fs.base] = keep[fs.face_z[active]] = 0.0

    def product(y: np.ndarray) -> np.ndarray:
        return tube.rot_t @ (K @ (tube.rot @ y))

    n = tube.dofs
    A = spla.LinearOperator((n, n), matvec=lambda y: keep * product(keep * y), dtype=float)
    M = spla.LinearOperator((n, n), matvec=held_preconditioner(system, active), dtype=float)
    y, info = spla.cg(A, keep * (f - product(x)), M=M, rtol=rtol, atol=0.0, maxiter=MAX_KRYLOV)
    return x + keep * y if info == 0 else None


# ---- stresses at sample points ----

def stresses_at(tube: Tube, u: np.ndarray, lame: Lame, nonlinear: bool, r, phi, z) -> np.ndarray:
    """Cauchy stress (linear: Hooke's) at points given in (r, phi, z), in the cylindrical frame of each point:
    (N, 3, 3) with indices r, theta, z."""
    pts = np.array([r, phi, z], dtype=float)
    key = pts.tobytes()
    if key not in tube.samplers:     # every state of a mesh is read at the same points: locate them once
        tube.samplers[key] = _sampler(tube, pts)
    out = np.empty((pts.shape[1], 3, 3))
    for sel, G, edofs, Q in tube.samplers[key]:
        F, S = _state(G, u[edofs].reshape(len(sel), -1, 3), lame, nonlinear)
        F, S = F[:, 0], S[:, 0]
        sigma = np.einsum("niJ,nJL,nkL->nik", F, S, F) / np.linalg.det(F)[:, None, None] if nonlinear else S
        out[sel] = np.einsum("nij,njk,nlk->nil", Q, sigma, Q)     # Q sigma Q^T
    return out


def _sampler(tube: Tube, pts: np.ndarray) -> list[tuple]:
    """The points as one group: (their indices, shape-function gradients, element dofs, rotation to the
    cylindrical frame). One basis on their elements at every distinct reference position (each point's gradients
    are its own element's at its own position), not a basis per position."""
    from skfem import CellBasis

    tind = tube.param_mesh.element_finder()(*pts)
    X = tube.param_mesh.mapping().invF(pts[:, :, None], tind=tind)[:, :, 0]
    _, first, position = np.unique(np.round(X, 9), axis=1, return_index=True, return_inverse=True)
    elements, element = np.unique(tind, return_inverse=True)
    cb = CellBasis(tube.mesh, tube.basis.elem, elements=elements, quadrature=(X[:, first], np.ones(first.size)))
    G = _gradients(cb)[element, position.ravel()][:, None]          # (point, 1, a, J)
    c, s = np.cos(pts[1]), np.sin(pts[1])
    Q = np.zeros((pts.shape[1], 3, 3))
    Q[:, 0, 0], Q[:, 0, 1], Q[:, 1, 0], Q[:, 1, 1], Q[:, 2, 2] = c, s, -s, c, 1.0
    return [(np.arange(pts.shape[1]), G, _element_dofs(cb)[element], Q)]


def von_mises_MPa(sig: np.ndarray) -> np.ndarray:
    dev = sig - np.trace(sig, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3.0
    return np.sqrt(1.5 * np.einsum("nij,nij->n", dev, dev))


# skfem's hexahedron vertex order (000, 001, 010, 100, 011, 101, 110, 111) in VTK's (000, 100, 110, 010, ...)
_VTK_HEX = (0, 3, 6, 2, 1, 5, 7, 4)


def write_fields(path, tube: Tube, u: np.ndarray, lame: Lame, nonlinear: bool, info: dict):
    """The quarter wall as VTU (8-node hexahedra on the P2 vertices): displacement, von Mises, Cauchy stress in
    the cylindrical frame (rr, tt, zz, tz, rz, rt) and its hoop component alone at the vertices."""
    from strainwave.io_atomic import atomic_path
    from strainwave.fea.fields import _grid, _write_grid

    pm = tube.param_mesh
    sig = stresses_at(tube, u, lame, nonlinear, *pm.p)
    disp = np.stack([u[3 * np.arange(pm.p.shape[1]) + k] for k in range(3)], axis=1)
    voigt = np.stack([sig[:, 0, 0], sig[:, 1, 1], sig[:, 2, 2], sig[:, 1, 2], sig[:, 0, 2], sig[:, 0, 1]], axis=1)
    cells = tube.mesh.t[list(_VTK_HEX)].T
    grid = _grid(tube.mesh.p[:, :pm.p.shape[1]].T, [cells], np.full(cells.shape[0], 12), {
        "displacement_mm": disp, "von_mises_MPa": von_mises_MPa(sig), "stress_cylindrical_MPa": voigt,
        "hoop_stress_MPa": voigt[:, 1]},
        {"physical_group": np.ones(cells.shape[0], np.int64)}, info, ["solid"])
    with atomic_path(path) as tmp:
        _write_grid(tmp, grid)
    return path
