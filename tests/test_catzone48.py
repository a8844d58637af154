"""The catalogue's cup-zone term net of the plane rim (decision 075-catzone48) and the shortest cup the tube allows."""
import math

import numpy as np
import pytest

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cup_zone import teeth_rated_loads
from strainwave.errors import InputError
from strainwave.fea import cup_zone_load as cz
from strainwave.fea import drive_assembled as da
from strainwave.fea.assembly import Lame
from strainwave.fea.wg_band import TubeGeometry


@pytest.fixture(scope="module")
def drive():
    rules = MeshRules()
    d = rules.design(25, 100)
    geo = cz.tube_of_design(d)
    lame = Lame.from_young(d.E_MPa, 0.3)
    g2 = da.annulus_modes(geo.r_i_mm, geo.r_o_mm, d.geometry.face_width_mm, 0.5 * geo.wall_mm, lame, da.HARMONICS)
    return d, geo, lame, g2, teeth_rated_loads(d, 1e3 * rules.rated_torque_Nm(25))


def _terms(drive, loads=None, contact=True):
    d, geo, lame, g2, rated = drive
    phi, lever, F = rated if loads is None else loads
    return da.zone_terms(geo, 6, lame, d.geometry.w0_mm, phi, lever, F, d.geometry.face_width_mm, g2,
                         contact=contact)


def test_equal_loads_on_every_tooth_add_nothing_to_the_uniform_shear(drive):
    """The limit: the same load on every tooth is the uniform shear, so the wall's extra (gross) vanishes."""
    d = drive[0]
    z = d.geometry.teeth_flexspline
    lever = np.full(z, d.geometry.pitch_radius_mm * math.cos(math.radians(d.geometry.pressure_angle_deg)))
    out = _terms(drive, (2.0 * math.pi * np.arange(z) / z, lever, np.full(z, 5.0)))
    assert abs(out["gross"]) < 1e-9 * out["uniform"]


def test_a_wall_held_round_under_the_band_is_the_plane_annulus(drive):
    """With the whole band bore held radially (no lift-off from the cam) the wall under the teeth is the plane rim
    under the band: what is left after the annulus is taken out is small against the gross (decision 073 found the
    same on the shipped gear); on the cam the wall lifts off between the lobes, which only adds compliance."""
    held, cam = _terms(drive, contact=False), _terms(drive)
    assert held["gross"] > 0.0 and abs(held["net"]) < 0.25 * held["gross"]
    assert cam["net"] > 0.0 and cam["gross"] > held["gross"]


def test_the_catalogue_adds_the_net_not_the_gross(drive):
    """The catalogue's term is the net, with the gross recorded beside it; the reduced model's rim already holds the
    plane part (0.66-0.91 of it, decision 075), so the net is a fraction of the gross."""
    term = MeshRules(cup_zone_elements=(8, 7, 6)).cup_zone_term(100.0)
    assert 0.0 < term.extra.value < 0.5 * term.gross.value
    assert term.to_dict()["gross_rad_per_Nmm"]["value"] == term.gross.value


def test_a_cup_as_short_as_its_tooth_band_is_refused_naming_the_key():
    """L = 0.2 d put the tooth band (0.19 d) into the diaphragm: refused up front with the key, the value and the
    shortest length; the shortest cup allowed meshes and solves."""
    with pytest.raises(InputError) as err:
        MeshRules(length_over_d=0.2).cup_zone_term(100.0)
    assert err.value.key == "length_over_d" and "must be > 0.2976" in str(err.value)
    with pytest.raises(InputError) as err:
        TubeGeometry(29.0, 31.0, 7.0, 12.7, 11.9)
    assert err.value.key == "cup length_mm" and "must be > 18.9 mm" in str(err.value)
    rules = MeshRules(length_over_d=0.30)
    d = rules.design(25, 100)
    out = cz.zone_flexibilities(d, 6, {"uniform": cz.uniform_zone()})
    assert out["uniform"] > 0.0


def test_a_parameter_file_with_a_cup_shorter_than_its_band_is_refused():
    from strainwave.params import load_params
    p = load_params()
    with pytest.raises(InputError) as err:
        p.with_value("flexspline_cup.length_mm", 39.0)      # band 32 mm + 3.5 walls of 2.24 mm = 39.84 mm
    assert err.value.key == "flexspline_cup.length_mm" and "must be > 39.84 mm" in str(err.value)
    assert p.with_value("flexspline_cup.length_mm", 40.0).flexspline_cup.length_mm == 40.0


def test_validate_with_a_cup_shorter_than_its_band_exits_2_with_one_line(tmp_path, capsys):
    from strainwave.cli import main
    f = tmp_path / "short.toml"
    f.write_text("[flexspline_cup]\nlength_mm = 39\n")
    assert main(["validate", "--params", str(f), "--quick", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "flexspline_cup.length_mm = 39" in err and "39.84 mm" in err
