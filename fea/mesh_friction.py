"""Frictional contact of the teeth in mesh with the friction on the TRUE slip and its load on the teeth.

``mesh_contact`` (the study's model) adds friction to the torque only: mu |slide| F along the rigid kinematic
slide, no tangential load on the teeth. Here each flank pair carries a normal force N (strainwave's unit band
load f, as in ``mesh_contact``) and a tangential force Q (the same band turned to the flank's tangent, g), both
on the FE's flexibility, and Coulomb's law acts on the true relative slip of the flank against the counter-tooth:

    gap   g_i = c_i - lever_i theta + (Cff N + Cfg Q)_i >= 0,  N_i >= 0,  g_i N_i = 0
    slip  s_i = (Cgf N + Cgg Q)_i + w_i theta          (w_i: the counter-tooth's slide at the contact point)
    stick ds_i = 0 with |Q_i| <= mu N_i;   slip  Q_i = -mu N_i sign(ds_i)
    torque on the counter-teeth  T = sum lever_i N_i - w_i Q_i

Coulomb's law is path dependent: the twist history is followed in increments (backward Euler on the slip, as an
incremental FE code does), each solved exactly on its contact and stick sets by an active-set iteration.
(decision 070-ccx2pct48). ``torque_path`` splits each increment at every state change, located exactly (the
response is linear in the torque on fixed sets), so its path and loop do not depend on the step (decision
078-slipknots48).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BandSystem", "turned_bands", "solve_twist_path", "twists_for_torques", "torque_path"]

MAX_SETS = 200      # active-set iterations per increment before giving up (a P-matrix problem needs few)
# of an increment: where changing one flank's state at a time cycles at a point (the rate problem wants several
# at once), the exact path steps this far by backward Euler, whose end sets are consistent (decision 078)
NUDGE = 1e-7


@dataclass(frozen=True)
class BandSystem:
    """The flank pairs of one lobe (lengths mm, forces N)."""

    clearance_mm: np.ndarray     # (n,) unloaded normal gap
    flex_mm_per_N: np.ndarray    # (2n, 2n) [[Cff, Cfg], [Cgf, Cgg]]: band displacements per band load
    lever_mm: np.ndarray         # (n,) the gap closes by lever * theta
    slide_mm_per_rad: np.ndarray  # (n,) w: the counter-tooth's tangential motion per unit twist (+t)
    friction_coefficient: float

    def __post_init__(self):
        n = len(self.clearance_mm)
        if self.flex_mm_per_N.shape != (2 * n, 2 * n) or len(self.lever_mm) != n or len(self.slide_mm_per_rad) != n:
            raise ValueError("BandSystem: clearance, flexibility, lever and slide must agree in size")
        if np.any(np.asarray(self.clearance_mm) < 0.0):
            raise ValueError("BandSystem: clearance_mm must be >= 0")
        if self.friction_coefficient < 0.0:
            raise ValueError("BandSystem: friction_coefficient must be >= 0")


def turned_bands(F: np.ndarray, tangent: np.ndarray) -> np.ndarray:
    """The band loads F (columns, interleaved x/y dofs) as tangential tractions: each nodal force turned by
    -90 degrees (a pressure's p (-n) becomes p t on every facet), scaled to a unit resultant along ``tangent``."""
    G = np.empty_like(F)
    G[0::2], G[1::2] = F[1::2], -F[0::2]
    res = np.stack([G[0::2].sum(0), G[1::2].sum(0)], axis=1)
    return G / np.einsum("ij,ij->i", res, np.asarray(tangent))[None, :]


@dataclass
class _State:
    contact: np.ndarray      # bool (n,)
    stick: np.ndarray        # bool (n,)
    sign: np.ndarray         # (n,) slip direction of a sliding pair
    slip_mm: np.ndarray      # (n,) s at the end of the last increment
    N: np.ndarray
    Q: np.ndarray

    def copy(self) -> "_State":
        return _State(*(np.copy(v) for v in (self.contact, self.stick, self.sign, self.slip_mm, self.N, self.Q)))


def _linear(s: BandSystem, st: _State, theta: float,
            torque: float | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """N, Q and the twist on the current contact and stick sets: at the twist ``theta``, or, given ``torque``, at
    the twist that carries it (the twist one more unknown, the torque one more row)."""
    n, mu = len(s.clearance_mm), s.friction_coefficient
    A = np.flatnonzero(st.contact)
    S = np.flatnonzero(st.contact & st.stick)
    L = np.flatnonzero(st.contact & ~st.stick)
    slipQ = np.zeros(n)
    slipQ[L] = -mu * st.sign[L]                      # Q_L = slipQ * N_L
    a, k = A.size, S.size
    t = 0 if torque is None or not a else 1
    M = np.zeros((a + k + t, a + k + t))
    rows = np.concatenate([A, n + S])                # the gap rows of A, the stick rows of S
    sub = s.flex_mm_per_N[np.ix_(rows, np.concatenate([A, n + S, n + A]))]
    M[:a + k, :a + k] = sub[:, :a + k]
    M[:a + k, :a] += sub[:, a + k:] * slipQ[A][None, :]
    if t:       # the twist moved to the left: gap rows - lever theta, stick rows + w theta; the torque's row
        M[:a, -1], M[a:a + k, -1] = -s.lever_mm[A], s.slide_mm_per_rad[S]
        M[-1, :a] = s.lever_mm[A] - s.slide_mm_per_rad[A] * slipQ[A]
        M[-1, a:a + k] = -s.slide_mm_per_rad[S]
        rhs = np.concatenate([-s.clearance_mm[A], st.slip_mm[S], [torque]])
    else:
        rhs = np.concatenate([s.lever_mm[A] * theta - s.clearance_mm[A],
                              st.slip_mm[S] - s.slide_mm_per_rad[S] * theta])
    x = np.linalg.solve(M, rhs) if a else np.zeros(0)
    N, Q = np.zeros(n), np.zeros(n)
    N[A] = x[:a]
    Q[S] = x[a:a + k]
    Q[L] = slipQ[L] * N[L]
    return N, Q, float(x[-1]) if t else theta


def _increment(s: BandSystem, st: _State, theta: float, torque: float | None = None) -> float:
    """Solve one increment to ``theta`` (or to the twist that carries ``torque``; ``theta`` then the guess) in
    place: contact, stick and slip sets consistent with Coulomb; returns the twist. One set change per pass, the
    worst violation first (changing all at once can cycle between stick and slip)."""
    n, mu = len(s.clearance_mm), s.friction_coefficient
    g_tol = 1e-12 * max(float(np.max(np.abs(s.clearance_mm), initial=0.0)), 1e-9)
    for _ in range(MAX_SETS):
        if torque is not None and not st.contact.any():
            _first_to_close(s, st, torque)
        N, Q, theta = _linear(s, st, theta, torque)
        s_tol = 1e-10 * max(float(np.max(np.abs(s.slide_mm_per_rad))) * abs(theta), g_tol)
        u = s.flex_mm_per_N @ np.concatenate([N, Q])
        gap = s.clearance_mm - s.lever_mm * theta + u[:n]
        slip = u[n:] + s.slide_mm_per_rad * theta
        f_tol = 1e-10 * max(float(np.max(N, initial=0.0)), 1e-20)
        stick, slide = st.contact & st.stick, st.contact & ~st.stick
        worst = [(np.where(st.contact, -N, -np.inf) / f_tol, "open"),
                 (np.where(~st.contact, -gap, -np.inf) / g_tol, "close"),
                 (np.where(stick, np.abs(Q) - mu * N, -np.inf) / f_tol, "slide"),
                 (np.where(slide, -(slip - st.slip_mm) * st.sign, -np.inf) / s_tol, "stick")]
        viol = [(float(np.max(v)), int(np.argmax(v)), kind) for v, kind in worst if v.size]
        size, i, kind = max(viol)
        if size <= 1.0:
            st.N, st.Q, st.slip_mm = N, Q, slip
            return theta
        if kind in ("open", "close"):
            st.contact[i] = kind == "close"
            st.stick[i] = mu > 0.0
        elif kind == "slide":
            st.stick[i], st.sign[i] = False, -np.sign(Q[i])
        else:
            st.stick[i] = True
    raise RuntimeError(f"mesh_friction: no consistent contact/stick set at theta = {theta:.6g} rad")


def _first_to_close(s: BandSystem, st: _State, torque: float) -> None:
    """No flank touches and a torque is asked for: the flank whose gap closes first as the twist moves toward the
    torque's sign carries it (unloaded, the gaps are c - lever theta)."""
    can = np.flatnonzero(np.sign(s.lever_mm) == np.sign(torque))
    if torque == 0.0 or can.size == 0:
        raise ValueError(f"mesh_friction: torque {torque:.6g} N mm is not carried by any flank")
    i = can[np.argmin(s.clearance_mm[can] / np.abs(s.lever_mm[can]))]
    st.contact[i], st.stick[i] = True, s.friction_coefficient > 0.0


def _new_state(n: int, mu: float) -> _State:
    return _State(np.zeros(n, bool), np.full(n, mu > 0.0), np.ones(n), np.zeros(n), np.zeros(n), np.zeros(n))


def _leg(s: BandSystem, st: _State, theta0: float, theta1: float, increments: int) -> None:
    for th in np.linspace(theta0, theta1, increments + 1)[1:]:
        _increment(s, st, float(th))


def _record(s: BandSystem, st: _State, theta: float) -> dict:
    T = float(s.lever_mm @ st.N - s.slide_mm_per_rad @ st.Q)
    return {"twist_rad": theta, "forces_N": st.N.copy(), "tangential_N": st.Q.copy(), "torque_Nmm": T,
            "stick": st.contact & st.stick, "share": st.N / max(st.N.sum(), 1e-300)}


def solve_twist_path(s: BandSystem, twists_rad, increments: int = 20) -> list[dict]:
    """The state at the end of each leg of the twist history 0 -> twists[0] -> twists[1] ...; each leg in
    ``increments`` equal increments."""
    st, prev, out = _new_state(len(s.clearance_mm), s.friction_coefficient), 0.0, []
    for th in np.atleast_1d(np.asarray(twists_rad, float)).tolist():
        _leg(s, st, prev, th, increments)
        out.append(_record(s, st, th))
        prev = th
    return out


def _false_position(f, lo: float, f_lo: float, hi: float, f_hi: float, f_tol: float) -> float:
    """A root of f in [lo, hi] (f_lo, f_hi of opposite signs) by the Illinois false position: T(theta) along a
    leg is piecewise linear, so it lands in a few evaluations where bisection takes ~40."""
    side = 0
    for _ in range(200):
        mid = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        f_mid = f(mid)
        if abs(f_mid) <= f_tol or abs(hi - lo) <= 1e-14 * abs(hi):
            return mid
        if (f_mid > 0.0) == (f_hi > 0.0):
            hi, f_hi = mid, f_mid
            f_lo = 0.5 * f_lo if side == +1 else f_lo
            side = +1
        else:
            lo, f_lo = mid, f_mid
            f_hi = 0.5 * f_hi if side == -1 else f_hi
            side = -1
    return hi


def _leg_to_torque(s: BandSystem, st: _State, prev: float, T_now: float, T: float, increments: int,
                   rtol: float) -> tuple[float, _State]:
    """The leg from the state ``st`` at twist ``prev`` (torque ``T_now``) whose end twist carries ``T`` (false
    position on the end twist, the leg's increments re-run from ``st`` per trial): (end twist, end state)."""
    lever = float(np.max(np.abs(s.lever_mm)))
    d = 1.0 if T > T_now else -1.0
    step = max(abs(prev), float(np.min(s.clearance_mm)) / lever, 1e-9)

    def torque_at(theta: float) -> tuple[float, _State]:
        trial = st.copy()
        _leg(s, trial, prev, theta, increments)
        return float(s.lever_mm @ trial.N - s.slide_mm_per_rad @ trial.Q), trial

    lo, hi = prev, prev + d * step
    f_lo, f_hi = T_now - T, torque_at(hi)[0] - T
    for _ in range(60):
        if d * f_hi >= 0.0:
            break
        lo, f_lo, hi = hi, f_hi, hi + d * step
        f_hi = torque_at(hi)[0] - T
        step *= 2.0
    else:       # e.g. a torque of the sign no flank of the lobe can carry
        raise ValueError(f"twists_for_torques: torque {T:.6g} N mm is not reached by any twist")
    hi = _false_position(lambda th: torque_at(th)[0] - T, lo, f_lo, hi, f_hi, rtol * abs(T))
    return hi, torque_at(hi)[1]


def twists_for_torques(s: BandSystem, torques_Nmm, increments: int = 20, rtol: float = 1e-10) -> list[dict]:
    """The twist history whose legs end at the given torques (false position on each leg's end twist, the path
    to it followed from the previous leg's state); returns ``solve_twist_path``'s records."""
    st, prev, out = _new_state(len(s.clearance_mm), s.friction_coefficient), 0.0, []
    for T in np.atleast_1d(np.asarray(torques_Nmm, float)).tolist():
        T_now = out[-1]["torque_Nmm"] if out else 0.0
        prev, st = _leg_to_torque(s, st, prev, T_now, T, increments, rtol)
        out.append(_record(s, st, prev))
    return out

ZERO_AIM = 1e-9     # of the history's amplitude: a zero torque inside the loop is aimed at a hair either side of 0


def _targets(torques: np.ndarray, increments: int) -> tuple[np.ndarray, np.ndarray]:
    """The increments' torques (each history step in ``increments`` equal torque increments) and the index of each
    history point among them. A zero torque after a load lies in the backlash's dead band (any twist in it carries
    0): both its edges are solved, a hair either side of 0, and the far edge (the other flanks touch) is the
    history's point, where fea/mesh_contact's tracker lands too."""
    eps = ZERO_AIM * float(np.max(np.abs(torques), initial=0.0))
    out, idx, prev = [], [], 0.0              # the path starts unloaded at 0 (a first point of 0 is that start)
    for Tk in np.asarray(torques, float).tolist():
        Tk = 0.0 if abs(Tk) <= 1e-12 * eps / ZERO_AIM else Tk     # a history's round-off zero is its zero
        if not out and Tk == 0.0:
            idx.append(-1)
            continue
        sub = list(np.linspace(prev, Tk, increments + 1)[1:])
        if Tk == 0.0 and prev != 0.0:
            sub[-1:] = [np.sign(prev) * eps, -np.sign(prev) * eps]
        out += sub
        idx.append(len(out) - 1)
        prev = Tk
    return np.asarray(out), np.asarray(idx)


def _response(s: BandSystem, st: _State, torque: float) -> tuple:
    """(N, Q, twist, gap, slip) on the current sets at ``torque`` (stick flanks held at ``st.slip_mm``): affine in
    the torque while the sets hold."""
    n = len(s.clearance_mm)
    N, Q, theta = _linear(s, st, 0.0, torque)
    u = s.flex_mm_per_N @ np.concatenate([N, Q])
    return N, Q, theta, s.clearance_mm - s.lever_mm * theta + u[:n], u[n:] + s.slide_mm_per_rad * theta


def _first_event(s: BandSystem, st: _State, x0: tuple, x1: tuple) -> tuple[float, int, str]:
    """(ratio along x0 -> x1 of the first state change, its flank, its kind): each condition is linear in the
    ratio on fixed sets, so its crossing is the linear step's own ratio (a condition already on its edge and
    leaving it changes at 0)."""
    mu = s.friction_coefficient
    (N0, Q0, th0, g0, _), (N1, Q1, th1, g1, s1) = x0, x1
    f_tol = 1e-10 * max(float(np.max(np.abs(N0), initial=0.0)), float(np.max(np.abs(N1), initial=0.0)), 1e-20)
    g_tol = 1e-12 * max(float(np.max(np.abs(s.clearance_mm), initial=0.0)), 1e-9)
    s_tol = 1e-10 * max(float(np.max(np.abs(s.slide_mm_per_rad))) * max(abs(th0), abs(th1)), g_tol)
    c = st.contact
    stick, slide = c & st.stick, c & ~st.stick
    conds = [(c, N0, N1 - N0, f_tol, "open"), (~c, g0, g1 - g0, g_tol, "close"),
             (stick, mu * N0 - Q0, mu * (N1 - N0) - (Q1 - Q0), f_tol, "slide"),
             (stick, mu * N0 + Q0, mu * (N1 - N0) + (Q1 - Q0), f_tol, "slide"),
             (slide, np.zeros_like(N0), (s1 - st.slip_mm) * st.sign, s_tol, "stick")]
    best = (np.inf, 0.0, -1, "")
    for mask, f0, df, tol, kind in conds:
        for i in np.flatnonzero(mask & (df < -tol)):
            r = 0.0 if f0[i] <= tol else f0[i] / -df[i]
            key = (r, df[i] / tol)            # the earliest; at a tie the fastest to leave
            if key < best[:2]:
                best = (r, df[i] / tol, int(i), kind)
    return best[0], best[2], best[3]


def _exact_increment(s: BandSystem, st: _State, theta: float, T0: float, T1: float, knots: list) -> float:
    """The increment T0 -> T1 split at every state change (a flank closing or opening, a stick flank reaching the
    cone, a sliding flank stopping), each located by the linear step's ratio and recorded as a knot; in place,
    returns the twist at T1 (decision 078-slipknots48)."""
    stuck = 0
    for _ in range(MAX_SETS):
        if not st.contact.any():        # unloaded: the first flank closes at the band's edge, its slip held from there
            _first_to_close(s, st, T1)
            i = int(np.flatnonzero(st.contact)[0])
            st.N, st.Q = np.zeros_like(st.N), np.zeros_like(st.Q)
            st.slip_mm = s.slide_mm_per_rad * (s.clearance_mm[i] / s.lever_mm[i])
        if stuck > 2 * len(st.contact):     # the one-at-a-time changes cycle at a point: a hair of backward Euler
            trial = st.copy()
            try:
                theta = _increment(s, trial, theta, T0 + NUDGE * (T1 - T0))
            except RuntimeError:            # no torque-driven rate solution (a flank that can neither stick nor slip)
                return _twist_driven_rest(s, st, theta, T0, T1)
            vars(st).update(vars(trial))
            T0, stuck = T0 + NUDGE * (T1 - T0), 0
            knots.append((T0, theta))
        x0, x1 = _response(s, st, T0), _response(s, st, T1)
        if abs(x0[2] - theta) > 1e-12 * max(abs(theta), abs(x0[2]), 1e-12):   # the dead band crossed at 0 N m
            theta = x0[2]
            knots.append((T0, theta))
        r, i, kind = _first_event(s, st, x0, x1)
        if r >= 1.0:
            st.N, st.Q, st.slip_mm = x1[0], x1[1], x1[4]
            return x1[2]
        stuck = stuck + 1 if r == 0.0 else 0
        if r > 0.0:
            x = [a + r * (b - a) for a, b in zip(x0, x1)]
            st.N, st.Q, st.slip_mm, theta = x[0], x[1], x[4], float(x[2])
            T0 = T0 + r * (T1 - T0)
            knots.append((T0, theta))
        if kind in ("open", "close"):
            st.contact[i] = kind == "close"
            st.stick[i] = s.friction_coefficient > 0.0
            T0 = 0.0 if not st.contact.any() else T0       # no flank carries: the torque is 0 exactly
        elif kind == "slide":
            st.stick[i], st.sign[i] = False, -np.sign(st.Q[i]) if st.Q[i] != 0.0 else -np.sign(x1[1][i] - x0[1][i])
        else:
            st.stick[i] = True
    return _twist_driven_rest(s, st, theta, T0, T1)


def _twist_driven_rest(s: BandSystem, st: _State, theta: float, T0: float, T1: float) -> float:
    """The rest of an increment from an event where the torque-driven rate problem has no answer (friction's
    softening): one twist-driven backward-Euler increment, its end by false position; in place (decision 078)."""
    theta, end = _leg_to_torque(s, st, theta, T0, T1, 1, 1e-12)
    st.contact, st.stick, st.sign, st.slip_mm, st.N, st.Q = end.contact, end.stick, end.sign, end.slip_mm, end.N, end.Q
    return theta


def torque_path(s: BandSystem, torques_Nmm, increments: int = 1, exact: bool = True):
    """The history of torques (starting unloaded at 0), each step in ``increments`` equal TORQUE increments, each
    increment solved with its torque prescribed from the previous converged state (the twist an unknown of the
    increment's linear system). ``exact`` (the default): each increment is split at every state change, located
    by the linear step's own ratio (decision 078-slipknots48), so the path is the rate-independent Coulomb path
    whatever the increments and its knots are the loop's exact corners; else each increment is one backward-Euler
    step (its sets from its end), ``twists_for_torques`` on the same increments (tests/test_tooth_mesh_slip.py).
    Returns a fea/mesh_contact.MeshPath (work: trapezoids between the knots) and the tangential forces (m, n)."""
    from strainwave.fea.mesh_contact import MeshPath, dead_band
    T = np.asarray(torques_Nmm, float)
    n = len(s.clearance_mm)
    targets, idx = _targets(T, increments)
    st, theta = _new_state(n, s.friction_coefficient), 0.0
    knots, at = [(0.0, 0.0)], np.zeros(targets.size + 1, int)
    N, Q = np.zeros((T.size, n)), np.zeros((T.size, n))
    rec = {int(j): i for i, j in enumerate(idx)}
    for j, Tj in enumerate(targets):
        T0 = knots[-1][0]
        if Tj != 0.0:           # a zero torque held (the dead band's far edge reached before): nothing moves
            theta, st = _step(s, st, theta, T0, float(Tj), knots, exact)
            # the increment carries Tj (its torque row): recorded as asked, so the loop's peak is the history's and
            # the reader's grid (from the peak) keeps its exact 0 N m (decision 078)
            knots.append((float(Tj), theta))
        at[j + 1] = len(knots) - 1
        if j in rec:
            N[rec[j]], Q[rec[j]] = st.N, st.Q
    kn = np.asarray(knots, float)
    # the loop's knots for fea/tooth_mesh's reader (decision 073-stepconv48): linear between them
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (kn[1:, 0] + kn[:-1, 0]) * np.diff(kn[:, 1]))])
    work = np.diff(cum[at[idx + 1]], prepend=0.0)
    return MeshPath(T, kn[at[idx + 1], 1], N, N > 0.0, np.zeros(T.size, int), work, kn, dead_band(s)), Q


def _step(s: BandSystem, st: _State, theta: float, T0: float, T1: float, knots: list,
          exact: bool) -> tuple[float, _State]:
    """One torque increment T0 -> T1 from ``st`` at ``theta``: (twist, state) at T1; the twist-driven increment,
    its end by false position, where the torque-driven sets cycle."""
    trial, k = st.copy(), len(knots)
    try:
        if exact:
            return _exact_increment(s, trial, theta, T0, T1, knots), trial
        return _increment(s, trial, theta, T1), trial
    except RuntimeError:
        del knots[k:]           # the events found before the sets cycled are dropped with the trial
        return _leg_to_torque(s, st, theta, T0, T1, 1, 1e-12)
