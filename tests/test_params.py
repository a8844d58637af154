"""The parameter schema: defaults load, partial files merge, impossible values are refused with the key."""
import warnings

import pytest

from strainwave.errors import InputError, RangeWarning
from strainwave.params import CupShape, EwgGenerator, load_params, merge_overrides, default_dict, params_from_dict


def test_default_is_the_seed_examples():
    p = load_params()
    assert p.flexspline_cup.pitch_diameter_mm == 160.0
    assert p.flexspline_cup.shape is CupShape.CYLINDRICAL
    assert p.ewg_drive.generator is EwgGenerator.ROLLERS
    assert p.wave_generator.contact_semi_axes_mm == (5.0, 3.0)
    # delta = 0.012 d_R = 0.012 * 1.0 * 72 (seed 003, text after eq 6)
    assert p.ewg_drive.rim_thickness_mm == pytest.approx(0.864, rel=1e-12)


def test_material_inconsistency_is_warned_with_both_values():
    with pytest.warns(RangeWarning, match=r"80769 MPa .* 80000 .*\+0\.96 %"):
        load_params()


def test_partial_file_keeps_the_rest(tmp_path):
    f = tmp_path / "p.toml"
    f.write_text("[output_shaft]\nouter_diameter_mm = 50\n")
    p = load_params(f)
    assert p.output_shaft.outer_diameter_mm == 50.0
    assert p.output_shaft.inner_diameter_mm == 45.0
    assert p.flexspline_cup.teeth == 200


def test_with_value_returns_validated_copy():
    p = load_params()
    q = p.with_value("output_shaft.crack_depth_mm", 1.0)
    assert q.output_shaft.crack_depth_mm == 1.0 and p.output_shaft.crack_depth_mm == 0.1
    with pytest.raises(InputError) as err:
        p.with_value("output_shaft.crack_depth_mm", 20.0)   # the shaft wall is 12.5 mm
    assert err.value.key == "output_shaft.crack_depth_mm" and "12.5 mm" in str(err.value)


def test_each_crack_is_bounded_by_its_own_wall_only():
    """A 5 mm shaft crack is fine (wall 12.5 mm) although the cup wall is 2.24 mm (issue 11)."""
    p = load_params().with_value("output_shaft.crack_depth_mm", 5.0)
    assert p.output_shaft.crack_depth_mm == 5.0 and p.flexspline_cup.root_crack_depth_mm == 0.1
    for key, depth, wall in (("flexspline_cup.root_crack_depth_mm", 2.24, "wall_thickness_mm = 2.24"),
                             ("wave_generator.bearing_crack_depth_mm", 3.0, "bearing_inner_ring_thickness_mm = 3")):
        with pytest.raises(InputError) as err:
            p.with_value(key, depth)
        assert err.value.key == key and wall in str(err.value)


@pytest.mark.parametrize("how", ["file", "with_value"])
def test_old_single_crack_depth_is_refused_naming_the_new_keys(tmp_path, how):
    with pytest.raises(InputError) as err:
        if how == "file":
            f = tmp_path / "old.toml"
            f.write_text("[cracks]\ndepth_mm = 0.5\n")
            load_params(f)
        else:
            load_params().with_value("cracks.depth_mm", 0.5)
    text = str(err.value)
    assert err.value.key == "cracks.depth_mm"
    for new in ("output_shaft.crack_depth_mm", "flexspline_cup.root_crack_depth_mm",
                "wave_generator.bearing_crack_depth_mm"):
        assert new in text


@pytest.mark.parametrize("section,key,value,needle", [
    ("output_shaft", "inner_diameter_mm", 80.0, "outer_diameter_mm"),
    ("output_shaft", "length_mm", -1.0, "> 0"),
    ("material", "poisson_ratio", 0.5, "(0, 0.5)"),
    ("material", "poisson_ratio", "x", "number"),
    ("ewg_drive", "flexspline_teeth", 3, ">= 2 x tooth_difference"),
    ("ewg_drive", "flexspline_teeth", 72.5, "integer"),
    ("flexspline_cup", "shape", "conical", "'cylindrical'"),
    ("flexspline_cup", "cup", 1, "true or false"),
    ("flexspline_cup", "root_crack_depth_mm", 2.24, "flexspline_cup.wall_thickness_mm"),
    ("cracks", "flexspline_crack_angle_deg", 90.0, "(0, 90)"),
    ("crack_geometry", "slot_width_mm", 0.05, "crack_depth_mm/5"),
])
def test_impossible_values_name_key_value_and_range(section, key, value, needle):
    data = merge_overrides(default_dict(), {section: {key: value}})
    with pytest.raises(InputError) as err:
        params_from_dict(data)
    assert needle in str(err.value)
    assert key in err.value.key or key in str(err.value)


def test_unknown_section_and_key_are_refused():
    with pytest.raises(InputError, match=r"\[gears\].*unknown section"):
        merge_overrides(default_dict(), {"gears": {}})
    with pytest.raises(InputError, match=r"gear\.ratio .*unknown key"):
        merge_overrides(default_dict(), {"gear": {"ratio": 3}})


def test_recommended_range_warns_but_runs():
    data = merge_overrides(default_dict(), {"ewg_drive": {"rim_thickness_ratio": 0.2, "tooth_influence": 1.2}})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p = params_from_dict(data)
    messages = " ".join(str(w.message) for w in caught)
    assert p.ewg_drive.rim_thickness_ratio == 0.2
    assert "0.01..0.015 (seed 003" in messages and "1.05..1.1 (seed 003, eq 10)" in messages
