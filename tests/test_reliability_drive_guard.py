"""Issue 53's geometric consistency guard: impossible drives refused in one line naming the user's key, before any
work, by every command; a property test shows each drawn drive either passes and solves (the closed forms, the
cheap path) with finite numbers, or is refused in one line."""
import json
import math
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.cli import main
from strainwave.errors import InputError
from strainwave.params import default_dict, load_params

# the reproducers: (the parameter file's text, the key the refusal must name)
IMPOSSIBLE = [
    ("[gear]\nradial_deformation_mm = 100\n", "gear.radial_deformation_mm"),            # w0 > the bearing's bore
    ("[wave_generator]\ncontact_semi_axes_mm = [900.0, 900.0]\n", "wave_generator.contact_semi_axes_mm"),
    ("[wave_generator]\nbearing_inner_ring_thickness_mm = 90\n", "wave_generator.bearing_inner_ring_thickness_mm"),
    ("[flexspline_cup]\nlength_mm = 1\n", "flexspline_cup.length_mm"),                  # blamed --mesh-size-mm
    ("[gear]\nradial_deformation_mm = 22\n", "gear.radial_deformation_mm"),             # the ring turns inside out
    ("[wave_generator]\ncontact_semi_axes_mm = [5.0, 9.8]\n", "wave_generator.contact_semi_axes_mm"),  # > ball pitch
    ("[wave_generator]\ncontact_semi_axes_mm = [0.3, 3.0]\nbearing_crack_depth_mm = 2.8\n",
     "wave_generator.bearing_crack_depth_mm"),                                          # crack longer than the ring
    ("[ewg_drive]\ntooth_difference = 16\nflexspline_teeth = 40\n", "ewg_drive.tooth_difference"),
]


def _refusal(capsys, status) -> str:
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and err.startswith("error: "), err
    assert "internal error" not in err and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("text,key", IMPOSSIBLE)
def test_impossible_drives_are_refused_naming_the_users_key(tmp_path, capsys, text, key):
    params = tmp_path / "p.toml"
    params.write_text(text)
    for argv in (["analytic"], ["solve", "wg-bearing"], ["validate", "--quick", "--out", str(tmp_path / "v")],
                 ["export-step", "--part", "wg-bearing-ring", "-o", str(tmp_path / "r.step")]):
        err = _refusal(capsys, main([*argv, "--params", str(params)]))
        assert err.startswith(f"error: {key} = "), (argv, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.toml"], "a refused run leaves nothing behind"


def test_the_default_and_every_catalogue_drive_pass_the_guard():
    from strainwave.analytic import catalogue
    load_params()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for row in catalogue.read_catalogue():
            load_params(overrides=catalogue.overrides_for(row))


def test_a_sweep_point_that_cannot_be_built_is_refused_before_any_worker(tmp_path, capsys):
    err = _refusal(capsys, main(["sweep", "wg-bearing", "--vary", "gear.radial_deformation_mm=0.5,60",
                                 "--out", str(tmp_path / "s")]))
    assert "point 1" in err and "gear.radial_deformation_mm" in err
    assert not (tmp_path / "s").exists()


def test_a_recording_header_key_is_named_as_the_header_s(tmp_path, capsys):
    """The issue: a header's [params] blamed --params. The header's own key is named at its own line."""
    from tests.test_reliability_guards import _GOOD
    rec = tmp_path / "r.csv"
    lines = _GOOD.splitlines()
    rec.write_text("\n".join(["# [params.gear]", "# radial_deformation_mm = 100"] + lines) + "\n")
    err = _refusal(capsys, main(["diagnose", str(rec)]))
    assert "--params" not in err and "r.csv" in err and "radial_deformation_mm" in err, err


# Drives around the default: each geometric key scaled by a factor drawn log-uniformly in its range (wide enough
# that every rule of the guard refuses some draws, narrow enough that about half pass and are solved).
def _factor(lo: float, hi: float):
    return st.floats(min_value=math.log(lo), max_value=math.log(hi)).map(math.exp)


_KEYS = {("flexspline_cup", "wall_thickness_mm"): (2.24, _factor(0.1, 10)),
         ("flexspline_cup", "length_mm"): (160.0, _factor(0.1, 10)),
         ("gear", "radial_deformation_mm"): (0.8, _factor(0.1, 50)),
         ("wave_generator", "bearing_inner_ring_thickness_mm"): (10.0, _factor(0.1, 5)),
         ("wave_generator", "bearing_crack_depth_mm"): (0.1, _factor(1, 30)),
         ("flexspline_cup", "root_crack_depth_mm"): (0.1, _factor(1, 10)),
         ("output_shaft", "crack_depth_mm"): (0.1, _factor(1, 30)),
         ("wave_generator", "ball_diameter_mm"): (9.525, _factor(0.2, 3)),
         ("wave_generator", "outer_ring_thickness_mm"): (2.5, _factor(0.2, 3)),
         ("circular_spline", "outer_diameter_mm"): (200.0, _factor(0.7, 2)),
         ("circular_spline", "face_width_mm"): (30.0, _factor(0.3, 10))}
_SCHEMA_KEYS = {f"{section}.{key}" for section, table in default_dict().items() for key in table}


def _finite_numbers(value) -> list[float]:
    if isinstance(value, dict):
        return [x for v in value.values() for x in _finite_numbers(v)]
    if isinstance(value, (list, tuple)):
        return [x for v in value for x in _finite_numbers(v)]
    return [value] if isinstance(value, float) else []


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(factors=st.fixed_dictionaries({k: f for k, (_, f) in _KEYS.items()}), a=_factor(0.2, 3), b=_factor(0.2, 3),
       balls=st.integers(8, 60), wave=st.integers(1, 4))
def test_every_drawn_drive_passes_and_solves_or_is_refused_in_one_line(factors, a, b, balls, wave):
    from strainwave.analytic.summary import analytic_summary
    overrides: dict = {"wave_generator": {"contact_semi_axes_mm": [5.0 * a, 3.0 * b], "ball_count": balls},
                       "gear": {"wave_number": wave}}
    for (section, key), (default, _) in _KEYS.items():
        overrides.setdefault(section, {})[key] = default * factors[(section, key)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            params = load_params(overrides=overrides)
        except InputError as exc:
            assert "\n" not in str(exc) and str(exc).split(" = ")[0] in _SCHEMA_KEYS, str(exc)   # the user's own key
            return
        summary = analytic_summary(params)
    numbers = _finite_numbers(summary)
    assert numbers and all(math.isfinite(x) for x in numbers), [x for x in numbers if not math.isfinite(x)][:5]


def test_a_part_too_fine_for_its_wall_is_refused_naming_its_keys_not_a_flag(tmp_path, capsys):
    """The issue: refusals named --params or --mesh-size-mm (never given) for what the parameters themselves do."""
    params = tmp_path / "p.toml"
    params.write_text("[flexspline_cup]\nwall_thickness_mm = 0.05\nroot_crack_depth_mm = 0.03\n"
                      "[crack_geometry]\nslot_width_mm = 0.005\n")
    for argv in (["validate", "--quick", "--out", str(tmp_path / "v")], ["solve", "cup-torsion"]):
        err = _refusal(capsys, main([*argv, "--params", str(params)]))
        assert "flexspline_cup.pitch_diameter_mm, wall_thickness_mm, length_mm" in err, err
        assert "--params" not in err and "--mesh-size-mm" not in err, err
    err = _refusal(capsys, main(["solve", "cup-torsion", "--mesh-size-mm", "0.01"]))
    assert err.startswith("error: --mesh-size-mm = 0.01: "), "a size the user gave is named as given"


@pytest.mark.parametrize("argv", [["solve", "shaft-torsion", "--crack-depth-mm", "50"],
                                  ["solve", "bearing-ring", "--crack-depth-mm", "20"],
                                  ["export-step", "--part", "output-shaft", "--crack-depth-mm", "50", "-o", "{d}/a.step"],
                                  ["export-step", "--part", "wg-bearing-ring", "--crack-depth-mm", "0.01", "-o",
                                   "{d}/a.step"]])
def test_a_crack_given_on_the_command_line_is_refused_as_given(tmp_path, capsys, argv):
    """It was named as the parameter key (output_shaft.crack_depth_mm), the geometry's argument (crack_depth_mm) or
    the slot width the user never changed."""
    err = _refusal(capsys, main([a.format(d=tmp_path) for a in argv]))
    assert err.startswith(f"error: --crack-depth-mm = {float(argv[argv.index('--crack-depth-mm') + 1])}: "), err
    assert not list(tmp_path.iterdir())
