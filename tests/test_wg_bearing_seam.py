"""The ring on the cam's race crack from one factorisation (fea/ring2d.py ``seam_system``, fea/face_schur.py
``SeamSystem``) against the refactorising route it replaced: every contact set, its iterations and its
displacement are those of the sparse active set (fea/crack_contact.py ``solve_with_contact``, one factorisation
per set); every pair tied is the same grid with the crack merged; ``crack_work`` is the difference of the
energies, and so is the study's ``solve_crack`` (both states and the cam reversed from one factorisation and one
back-substitution). A coarse 2D ring (18.6k dofs) whose cam is scaled down so that the crack is partly shut."""
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
    # the 10 mm ring these cam shares and loads were chosen on (the default is 3 mm since issue 49): a solver test
    thick = params.with_value("wave_generator.bearing_inner_ring_thickness_mm", 10.0)
    s = setup_from(thick, **wg_bearing_load(thick))
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
MIXED = ((0.01, 1.0), (0.04, 3.0))   # retuned for the ring as built (issue 49: race radius, width)


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


def _energies(s, r, phi, cracked, f, cam, load):
    """f.(u2 - u1) - f.u0 by the refactorising route (the cam ``cam`` x w0; balls ``load`` x Stribeck's), and
    the round-off allowance of that difference of energies."""
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import _system, cam_displacement_mm
    bore = cam_displacement_mm(cracked, cam * s.w0_mm)
    u1, _ = _refactorising(cracked, np.zeros_like(f), bore, (cam, 0.0))
    u2, res2 = _refactorising(cracked, load * f, bore, (cam, load))
    merged = _system(s, r, phi, None)
    f0 = ring2d.patch_load_vectors(merged, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm) @ np.asarray(
        s.ball_loads_N)
    w = [float(load * f @ u2), float(load * f @ u1), float(load * f0 @ ring2d.solve_many(merged, load * f0[:, None])[:, 0])]
    return w[0] - w[1] - w[2], ENERGY_ROUNDOFF * sum(abs(x) for x in w), res2


@pytest.mark.parametrize("cam, load", MIXED)
def test_crack_work_is_the_difference_of_the_refactorising_energies(ring, cam, load):
    from strainwave.fea import ring2d
    from strainwave.fea.wg_bearing import cam_displacement_mm
    s, r, phi, cracked, f, seam = ring
    reference, allowance, res2 = _energies(s, r, phi, cracked, f, cam, load)
    bore = cam_displacement_mm(cracked, cam * s.w0_mm)
    _, new1 = ring2d.solve_ring(cracked, np.zeros_like(f), bore, seam)
    _, new2 = ring2d.solve_ring(cracked, load * f, bore, seam)
    r_f = seam.loads(cracked.R.T @ (load * f))[1]
    work = ring2d.crack_work(seam, r_f, new1.contact_force_N, new2.contact_force_N)
    assert res2.active.any() and abs(work - reference) <= allowance
    # without the change of the contact reactions from the cam alone to cam + balls: the comparison can fail
    assert abs(ring2d.crack_work(seam, r_f, new2.contact_force_N, new2.contact_force_N) - reference) > allowance


@pytest.mark.parametrize("cam, load", MIXED[1:])
def test_the_study_s_crack_solve_is_the_refactorising_route_with_the_cam_either_way(ring, cam, load):
    """``solve_crack``: both states and the cam reversed from one factorisation and one back-substitution."""
    from dataclasses import replace

    from strainwave.fea.wg_bearing import solve_crack
    s, r, phi, cracked, f, seam = ring
    case = replace(s, w0_mm=cam * s.w0_mm, ball_loads_N=tuple(load * np.asarray(s.ball_loads_N)))
    out = solve_crack(case, 5.0, 1.96, 1.0, profile=False, compressed=True)
    F2 = s.force_N ** 2
    (ref, allow, res), (ref_c, allow_c, res_c) = (_energies(s, r, phi, cracked, f, c, load) for c in (cam, -cam))
    assert out["closed_pairs"] == res.active.sum() and 0 < res.active.sum() < res.active.size
    assert abs(out["delta"] - ref / F2) <= allow / F2
    assert out["compressed"]["closed_pairs"] == res_c.active.sum()
    assert abs(out["compressed"]["delta"] - ref_c / F2) <= allow_c / F2
    # the states of the other cam's sign: the comparison can fail
    assert abs(out["compressed"]["delta"] - ref / F2) > allow / F2
