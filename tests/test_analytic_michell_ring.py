"""The exact n = 2 ring (analytic/michell_ring.py) from first principles: its displacements satisfy Hooke's law
with its stresses, its boundary conditions hold, and a thin ring tends to the thin-ring form."""
import math

import numpy as np
import pytest

from strainwave.analytic import michell_ring as m

E, NU, RI, RO, W0 = 2.1e5, 0.3, 52.76, 62.76, 0.8


@pytest.mark.parametrize("plane", list(m.Plane))
def test_boundary_conditions(plane):
    u_r, _ = m.cam_ring_displacement_mm(E, NU, RI, RO, W0, RI, 0.3, plane)
    assert u_r == pytest.approx(W0 * math.cos(0.6), rel=1e-12)
    srr_i, _, srt_i = m.cam_ring_stresses_MPa(E, NU, RI, RO, W0, RI, 0.3, plane)
    srr_o, _, srt_o = m.cam_ring_stresses_MPa(E, NU, RI, RO, W0, RO, 0.3, plane)
    scale = abs(m.cam_ring_hoop_stress_MPa(E, NU, RI, RO, W0, plane=plane))
    for value in (srt_i, srr_o, srt_o):
        assert abs(value) < 1e-10 * scale


@pytest.mark.parametrize("plane", list(m.Plane))
def test_strains_of_the_displacements_obey_hooke(plane):
    """Strains differentiated from (u_r, u_theta) equal those Hooke's law gives from the stresses."""
    r, phi, h = 57.0, 0.4, 1e-4
    ur = lambda rr, pp: m.cam_ring_displacement_mm(E, NU, RI, RO, W0, rr, pp, plane)[0]   # noqa: E731
    ut = lambda rr, pp: m.cam_ring_displacement_mm(E, NU, RI, RO, W0, rr, pp, plane)[1]   # noqa: E731
    e_rr = (ur(r + h, phi) - ur(r - h, phi)) / (2 * h)
    e_tt = (ur(r, phi) + (ut(r, phi + h) - ut(r, phi - h)) / (2 * h)) / r
    g_rt = ((ur(r, phi + h) - ur(r, phi - h)) / (2 * h) / r + (ut(r + h, phi) - ut(r - h, phi)) / (2 * h)
            - ut(r, phi) / r)
    srr, stt, srt = m.cam_ring_stresses_MPa(E, NU, RI, RO, W0, r, phi, plane)
    if plane is m.Plane.STRESS:
        hooke = ((srr - NU * stt) / E, (stt - NU * srr) / E)
    else:
        hooke = ((1 + NU) / E * ((1 - NU) * srr - NU * stt), (1 + NU) / E * ((1 - NU) * stt - NU * srr))
    assert e_rr == pytest.approx(hooke[0], rel=1e-6)
    assert e_tt == pytest.approx(hooke[1], rel=1e-6)
    assert g_rt == pytest.approx(2 * (1 + NU) / E * srt, rel=1e-6)


def test_thin_ring_limit_and_bounds():
    """t/r -> 0: 3 E t w0/(2 r_m^2) at the race (its error O(t/r)); plane strain lies above plane stress."""
    r_m, t, w0 = 100.0, 0.2, 0.05
    exact = m.cam_ring_hoop_stress_MPa(E, NU, r_m - t / 2, r_m + t / 2, w0)
    assert exact == pytest.approx(3 * E * t * w0 / (2 * r_m ** 2), rel=2 * t / r_m)
    stress = m.cam_ring_hoop_stress_MPa(E, NU, RI, RO, W0, plane=m.Plane.STRESS)
    strain = m.cam_ring_hoop_stress_MPa(E, NU, RI, RO, W0, plane=m.Plane.STRAIN)
    assert stress > 0 and strain > stress
    assert m.cam_ring_hoop_stress_MPa(E, NU, RI, RO, W0, phi_rad=0.5 * math.pi) == pytest.approx(-stress)
    with pytest.raises(ValueError):
        m.cam_ring_constants(E, NU, RO, RI, W0)
    assert np.isfinite(m.kappa(NU, m.Plane.STRAIN))


def test_held_bore_series_under_an_even_pressure_is_lames_ring():
    """360 equal balls press the race nearly evenly: inside the wall the series is Lame's ring with its bore held
    (u_r(a) = 0, plane stress); the patches' ripple (n = 360, 720, ...) has died out there (1e-5)."""
    Z, a, b, B, nu, Q = 360, 52.76, 62.76, 20.0, 0.3, 10.0
    psi = 2 * np.pi * np.arange(Z) / Z
    p0 = Z * Q / (2 * np.pi * b * B)
    r = np.array([55.0, 57.76, 60.0])
    series = m.held_bore_hoop_stress_MPa(nu, a, b, B, psi, np.full(Z, Q), np.full(Z, 0.4), r, harmonics=4000)
    k = m.kappa(nu, m.Plane.STRESS)
    A0 = -p0 / (1 + 0.5 * (k - 1) * a ** 2 / b ** 2)      # u_r(a) = 0: (1 - nu) A a = (1 + nu) C / a
    lame = A0 - 0.5 * (k - 1) * A0 * a ** 2 / r ** 2
    assert series == pytest.approx(lame, rel=1e-5)
    assert np.all(series < 0)        # the race pressed, the bore held: hoop compression
