"""The ring on the cam's race crack from one factorisation (fea/ring2d.py ``seam_system``, fea/face_schur.py
``SeamSystem``) against the refactorising route it replaced: every contact set, its iterations and its
displacement are those of the sparse active set (fea/crack_contact.py ``solve_with_contact``, one factorisation
per set); every pair tied is the same grid with the crack merged; ``crack_work`` is the difference of the
energies. A coarse 2D ring (18.6k dofs) whose cam is scaled down so that the crack is partly shut."""
from __future__ import annotations

import numpy as np
import pytest

# the difference of energies f.u carries each solve's round-off: 1e-12 of each energy, summed
ENERGY_ROUNDOFF = 1e-12


@pytest.fixture(scope="module")
def ring(params):
    from strainwave.analytic.study_loads import wg_bearing_load
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import _system, grid, setup_from
    s = setup_from(params, **wg_bearing_load(params))
    r, phi, tip = grid(s, 5.0, 1.96, 1.0)
    cracked = _system(s, r, phi, tip)
    balls = ring2d.patch_load_vectors(cracked, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm)
    seam = ring2d.seam_system(cracked)
    yield s, r, phi, cracked, balls @ np.asarray(s.ball_loads_N), seam
    seam.close()


_SOLVED: dict = {}


def _refactorising(system, f_global, bore_radial_mm, key):
    """The active set with one sparse factorisation per set, as ``solve_ring`` solved it before the seam (kept
    per ``key``: two tests read each state)."""
    from strainwave.fea import ring2d
    from strainwave.fea.crack_contact import solve_with_contact
    if key not in _SOLVED:
        up = ring2d._bore_displacement(system, bore_radial_mm)
        f = system.R.T @ f_global - system.K @ up
        res = solve_with_contact(system.K, f, ring2d._bore_fixed(system), system.pairs, ring2d._direct)
        _SOLVED[key] = (system.R @ (up + res.u), res)
    return _SOLVED[key]


# (cam w0 as a share of the study's, ball loads as a multiple of Stribeck's): partly shut cracks
MIXED = ((0.005, 1.0), (0.02, 3.0))


@pytest.mark.parametrize("cam, load", MIXED)
def test_each_contact_set_is_the_refactorising_active_set(ring, cam, load):
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import cam_displacement_mm
    s, r, phi, cracked, f, seam = ring
    bore = cam_displacement_mm(cracked, cam * s.w0_mm)
    u_old, old = _refactorising(cracked, load * f, bore, (cam, load))
    u_new, new = ring2d.solve_ring(cracked, load * f, bore, seam)
    assert 0 < new.active.sum() < new.active.size           # partly shut: the set is not trivial
    assert np.array_equal(new.active, old.active) and new.iterations == old.iterations
    scale = np.abs(u_old).max()
    assert np.abs(u_new - u_old).max() <= 1e-10 * scale
    assert np.abs(new.opening_mm - old.opening_mm).max() <= 1e-10 * scale
    assert np.abs(new.contact_force_N - old.contact_force_N).max() <= 1e-9 * np.abs(old.contact_force_N).max()


def test_every_pair_tied_is_the_grid_with_the_crack_merged(ring):
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import _system
    s, r, phi, cracked, f, seam = ring
    merged = _system(s, r, phi, None)
    f0 = ring2d.patch_load_vectors(merged, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm) @ np.asarray(
        s.ball_loads_N)
    closed = float(f0 @ ring2d.solve_many(merged, f0[:, None])[:, 0])
    tied = float(f @ ring2d.solve_many(cracked, f[:, None], tied=True, seam=seam)[:, 0])
    assert tied == pytest.approx(closed, rel=1e-11)
    # the faces free (the crack open, nothing held) is a softer ring: the comparison can fail
    ft, rf = seam.loads(cracked.R.T @ f)
    opened = float(f @ (cracked.R @ seam.solution(ft, rf, np.zeros(rf.size, bool))))
    assert opened > closed * (1.0 + 1e-3)


@pytest.mark.parametrize("cam, load", MIXED)
def test_crack_work_is_the_difference_of_the_refactorising_energies(ring, cam, load):
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import _system, cam_displacement_mm
    s, r, phi, cracked, f, seam = ring
    bore = cam_displacement_mm(cracked, cam * s.w0_mm)
    u1, res1 = _refactorising(cracked, np.zeros_like(f), bore, (cam, 0.0))
    u2, res2 = _refactorising(cracked, load * f, bore, (cam, load))
    merged = _system(s, r, phi, None)
    f0 = ring2d.patch_load_vectors(merged, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm) @ np.asarray(
        s.ball_loads_N)
    w = [float(load * f @ u2), float(load * f @ u1), float(load * f0 @ ring2d.solve_many(merged, load * f0[:, None])[:, 0])]
    reference, allowance = w[0] - w[1] - w[2], ENERGY_ROUNDOFF * sum(abs(x) for x in w)
    _, new1 = ring2d.solve_ring(cracked, np.zeros_like(f), bore, seam)
    _, new2 = ring2d.solve_ring(cracked, load * f, bore, seam)
    work = ring2d.crack_work(cracked, seam, load * f, new1, new2)
    assert res2.active.any() and abs(work - reference) <= allowance
    # without the change of the contact reactions from the cam alone to cam + balls: the comparison can fail
    assert abs(ring2d.crack_work(cracked, seam, load * f, new2, new2) - reference) > allowance
