"""Sweep points and sweep tables without a cluster: --vary parsing, full grids, sample files, tidy rows."""
import math

import pandas as pd
import pytest

from strainwave.compare.sweep.grid import build_points, full_grid, parse_vary, read_samples
from strainwave.compare.sweep.outputs import departures, records_frame
from strainwave.errors import InputError
from strainwave.params import default_dict


@pytest.fixture(scope="module")
def schema():
    return default_dict()


def test_range_gives_evenly_spaced_floats(schema):
    axis = parse_vary("output_shaft.inner_diameter_mm=30:60:4", schema)
    assert axis.key == "output_shaft.inner_diameter_mm"
    assert axis.values == (30.0, 40.0, 50.0, 60.0)
    assert all(isinstance(v, float) for v in axis.values)


def test_integer_key_stays_integer(schema):
    assert parse_vary("flexspline_cup.teeth=100:200:3", schema).values == (100, 150, 200)
    assert parse_vary("flexspline_cup.teeth=160,200", schema).values == (160, 200)
    with pytest.raises(InputError, match="whole steps"):
        parse_vary("flexspline_cup.teeth=100:201:3", schema)


def test_explicit_list_and_enum_and_bool(schema):
    assert parse_vary("output_shaft.crack_depth_mm=0.1,0.2,0.5", schema).values == (0.1, 0.2, 0.5)
    assert parse_vary("flexspline_cup.shape=cylindrical,bell", schema).values == ("cylindrical", "bell")
    assert parse_vary("flexspline_cup.cup=true,false", schema).values == (True, False)


def test_full_grid_is_the_product_first_axis_slowest(schema):
    axes = [parse_vary("output_shaft.crack_depth_mm=0.1,0.2", schema), parse_vary("output_shaft.length_mm=100:300:3", schema)]
    grid = full_grid(axes)
    assert len(grid) == 6
    assert grid[0] == {"output_shaft.crack_depth_mm": 0.1, "output_shaft.length_mm": 100.0}
    assert grid[2] == {"output_shaft.crack_depth_mm": 0.1, "output_shaft.length_mm": 300.0}
    assert grid[3] == {"output_shaft.crack_depth_mm": 0.2, "output_shaft.length_mm": 100.0}


@pytest.mark.parametrize("text, fragment", [
    ("output_shaft.bore_mm=1:2:3", "unknown key; output_shaft has"),
    ("shafts.length_mm=1:2:3", "unknown key; sections are"),
    ("output_shaft.length_mm=100:200:0", "N after the second ':'"),
    ("output_shaft.length_mm=100:200:two", "N after the second ':'"),
    ("output_shaft.length_mm=100:200", "expected KEY=START:STOP:N"),
    ("output_shaft.length_mm=abc,200", "takes a number"),
    ("output_shaft.length_mm=100,,200", "empty value"),
    ("output_shaft.length_mm=100,100", "values repeat"),
    ("output_shaft.length_mm=nan,100", "finite"),
    ("output_shaft.length_mm", "expected KEY=START:STOP:N"),
    ("flexspline_cup.shape=a:b:3", "not numeric"),
    ("wave_generator.contact_semi_axes_mm=1,2", "list-valued key cannot be swept"),
])
def test_bad_vary_is_one_input_error(schema, text, fragment):
    with pytest.raises(InputError, match=fragment) as info:
        parse_vary(text, schema)
    assert "\n" not in str(info.value)


def test_same_key_twice_is_refused(schema):
    with pytest.raises(InputError, match="only once"):
        build_points(["output_shaft.crack_depth_mm=0.1,0.2", "output_shaft.crack_depth_mm=0.3,0.4"], None, schema)


def test_nothing_to_vary_is_refused(schema):
    with pytest.raises(InputError, match="at least one --vary"):
        build_points([], None, schema)


def test_sample_file_rows_and_bad_cell_line(schema, tmp_path):
    good = tmp_path / "lhs.csv"
    good.write_text("# latin hypercube, 3 rows\noutput_shaft.inner_diameter_mm,flexspline_cup.teeth\n"
                    "30.5,160\n41.25,180\n\n52,200\n")
    rows = read_samples(good, schema)
    assert rows == [{"output_shaft.inner_diameter_mm": 30.5, "flexspline_cup.teeth": 160},
                    {"output_shaft.inner_diameter_mm": 41.25, "flexspline_cup.teeth": 180},
                    {"output_shaft.inner_diameter_mm": 52.0, "flexspline_cup.teeth": 200}]
    bad = tmp_path / "bad.csv"
    bad.write_text("output_shaft.inner_diameter_mm,flexspline_cup.teeth\n30,160\n40,17.5\n")
    with pytest.raises(InputError, match=r"bad.csv:3.*integer"):
        read_samples(bad, schema)
    unknown = tmp_path / "unknown.csv"
    unknown.write_text("output_shaft.bore\n1\n")
    with pytest.raises(InputError, match=r"unknown.csv:1.*unknown key"):
        read_samples(unknown, schema)


def test_samples_combine_with_a_grid(schema, tmp_path):
    samples = tmp_path / "s.csv"
    samples.write_text("output_shaft.inner_diameter_mm\n30\n40\n")
    keys, points = build_points(["output_shaft.crack_depth_mm=0.1,0.2,0.3"], samples, schema)
    assert keys == ["output_shaft.inner_diameter_mm", "output_shaft.crack_depth_mm"]
    assert len(points) == 6 and points[4] == {"output_shaft.inner_diameter_mm": 40.0, "output_shaft.crack_depth_mm": 0.2}


def _record(index, a, fea, published, corrected, status="ok"):
    return {"index": index, "status": status, "error": None if status == "ok" else "InputError: too deep",
            "inputs": {"output_shaft.crack_depth_mm": a}, "dofs": 1000,
            "fea": {} if status != "ok" else {"flexibility_rad_per_Nmm": {"value": fea, "unit": "rad/(N mm)",
                                                                           "uncertainty": 0.01 * fea}},
            "analytic": {} if status != "ok" else {"flexibility_rad_per_Nmm": {
                "key": "seed000.lambda_so0", "published": published, "corrected": corrected}}}


def test_tidy_rows_relative_errors_and_named_departures():
    records = [_record(0, 0.1, 2.0, 1.0, 2.02), _record(1, 0.2, 4.0, 2.0, 4.4), _record(2, 20.0, 0, 0, 0, "failed")]
    frame = records_frame(records, ["output_shaft.crack_depth_mm"])
    assert len(frame) == 3 and list(frame["point"]) == [0, 1, 2]
    # (fea - ref) / |ref|, the closed form as reference (validate's sign): (2 - 1)/1 and (4 - 4.4)/4.4
    assert frame.loc[0, "published_rel_error"] == pytest.approx(1.0, rel=1e-12)
    assert frame.loc[1, "corrected_rel_error"] == pytest.approx(-0.4 / 4.4, rel=1e-12)
    assert frame.loc[2, "status"] == "failed" and pd.isna(frame.loc[2, "quantity"])
    assert math.isnan(frame.loc[2, "fea"])
    lines = departures(frame, ["output_shaft.crack_depth_mm"], tolerance=0.05)
    published, corrected = lines
    assert "published departs by more than 0.05 at 2/2 points" in published
    assert "output_shaft.crack_depth_mm in [0.1, 0.2]" in published
    assert "corrected departs by more than 0.05 at 1/2 points" in corrected
    assert "output_shaft.crack_depth_mm in [0.2, 0.2]" in corrected and "worst -0.0909 at point 1" in corrected


def test_plots_one_per_quantity_and_varied_input(tmp_path):
    from strainwave.compare.sweep.outputs import plot_sweep
    records = []
    for index, (a, d) in enumerate([(0.1, 30.0), (0.2, 30.0), (0.1, 45.0), (0.2, 45.0)]):
        rec = _record(index, a, 1.0 + a + d / 100, 1.0, 1.1)
        rec["inputs"]["output_shaft.inner_diameter_mm"] = d
        records.append(rec)
    varied = ["output_shaft.crack_depth_mm", "output_shaft.inner_diameter_mm"]
    frame = records_frame(records, varied)
    grid = plot_sweep(frame, varied, tmp_path / "grid")
    scatter = plot_sweep(frame, varied, tmp_path / "samples", lines=False)
    names = ["flexibility_rad_per_Nmm__vs__output_shaft_crack_depth_mm.png",
             "flexibility_rad_per_Nmm__vs__output_shaft_inner_diameter_mm.png"]
    assert [p.name for p in grid] == names and [p.name for p in scatter] == names
    assert all(p.stat().st_size > 10_000 for p in grid + scatter)   # a drawn figure, not an empty canvas
