"""The smooth cup's section solution as a 3D field (fea.cup_axisym.section_displacement): the global field the
crack patch is held at. Against Saint-Venant torsion of the tube, which the cup's mid-tube must follow."""
from __future__ import annotations

import math

import numpy as np
import pytest

from strainwave.fea.cup_axisym import section_displacement, section_fine_mm, solve_cup_section
from strainwave.params import load_params


@pytest.fixture(scope="module")
def tube_field():
    params = load_params(None)
    solved = solve_cup_section(params, 2 * section_fine_mm(params, True), keep_fields=True)
    return params, section_displacement(solved.fields["section"])


def _points(r_mm: float, z_mm: np.ndarray, theta: float = 0.7) -> np.ndarray:
    return np.stack([r_mm * np.cos(theta) * np.ones_like(z_mm), r_mm * np.sin(theta) * np.ones_like(z_mm), z_mm], 1)


def test_section_field_is_a_pure_rotation_about_the_axis(tube_field):
    _, u_of = tube_field
    x = _points(79.0, np.linspace(40.0, 100.0, 5))
    u = u_of(x)
    assert np.abs(u[:, 2]).max() == 0.0
    # tangential: no radial component
    assert np.abs(np.einsum("nd,nd->n", u[:, :2], x[:, :2])).max() <= 1e-12 * np.abs(u).max() * 79.0


def test_mid_tube_twist_rate_is_saint_venant_torsion_of_the_tube(tube_field):
    params, u_of = tube_field
    fc, G = params.flexspline_cup, params.material.implied_shear_modulus_MPa
    ro, ri = fc.pitch_diameter_mm / 2, fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm
    J = math.pi / 2 * (ro ** 4 - ri ** 4)
    z = np.array([50.0, 90.0])
    for r in (ri + 0.2, ro - 0.2):
        u = u_of(_points(r, z))
        rate = (np.linalg.norm(u[1]) - np.linalg.norm(u[0])) / (r * (z[1] - z[0]))
        # unit torque: d(theta)/dz = 1 / (G J); the diaphragm's and the band's end effects have decayed here
        assert rate == pytest.approx(1.0 / (G * J), rel=1e-3)


def test_section_is_read_back_for_another_crack_depth_and_solved_again_for_another_cup(tmp_path, monkeypatch):
    from strainwave.fea import session
    params = load_params(None)
    h = 2 * section_fine_mm(params, True)
    first = solve_cup_section(params, h, keep_fields=True, cache_dir=tmp_path)

    def no_mesh(*args, **kwargs):
        raise AssertionError("meshed again")
    monkeypatch.setattr(session, "mesh_in_child", no_mesh)
    deeper = params.with_value("flexspline_cup.root_crack_depth_mm", 0.5)     # the smooth section has no crack
    again = solve_cup_section(deeper, h, keep_fields=True, cache_dir=tmp_path)
    assert again.values == first.values and again.mesh == first.mesh
    x = _points(79.0, np.linspace(40.0, 100.0, 5))
    u_first, u_again = (section_displacement(s.fields["section"])(x) for s in (first, again))
    assert np.array_equal(u_again, u_first)
    assert solve_cup_section(deeper, h, cache_dir=tmp_path).fields == {}        # fields only when asked for
    longer = params.with_value("flexspline_cup.length_mm", 1.1 * params.flexspline_cup.length_mm)
    with pytest.raises(AssertionError, match="meshed again"):
        solve_cup_section(longer, h, cache_dir=tmp_path)
    with pytest.raises(AssertionError, match="meshed again"):
        solve_cup_section(params, 1.2 * h, cache_dir=tmp_path)
