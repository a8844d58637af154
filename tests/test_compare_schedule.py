"""Longest-first scheduling of validation cases from the previous run's durations."""
from strainwave.compare.validate.runner import Case
from strainwave.compare.validate.schedule import durations_file, load_durations, longest_first, save_durations


def _cases(*labels):
    return [Case(label, "shaft-torsion", 1.0) for label in labels]


def test_longest_first_puts_untimed_cases_first_in_plan_order():
    cases = _cases("a", "b", "c", "d")
    order = longest_first(cases, {"a": 5.0, "c": 50.0})
    assert [c.label for c in order] == ["b", "d", "c", "a"]


def test_untimed_cases_go_largest_cost_estimate_first():
    cases = _cases("a", "b", "c", "d")
    order = longest_first(cases, {"a": 5.0}, {"a": 1e9, "b": 10.0, "c": 300.0, "d": 20.0})
    assert [c.label for c in order] == ["c", "d", "b", "a"]   # a's measured time outranks its estimate


def test_durations_round_trip_and_merge(tmp_path):
    path = durations_file(tmp_path / "cache", quick=False)
    assert load_durations(path) == {}                       # first run: nothing known
    save_durations(path, [("a", 12.345), ("b", 3.0)], {})
    save_durations(path, [("b", 4.0)], load_durations(path))
    assert load_durations(path) == {"a": 12.35, "b": 4.0}   # kept a, replaced b, 2 decimals
    assert durations_file(tmp_path, quick=True) != durations_file(tmp_path, quick=False)


def test_damaged_durations_file_is_ignored(tmp_path):
    path = durations_file(tmp_path, quick=True)
    path.write_text("{not json", encoding="utf-8")
    assert load_durations(path) == {}
    path.write_text('["a", 1]', encoding="utf-8")
    assert load_durations(path) == {}
