"""The mutation table (compare/validate/mutation_checks.py): each check of a recorded full `make validate`
re-judged with its FEA value, then its asserted closed form, scaled by 0.8, 0.9, 1.1 and 1.2.

`pytest -k mutation` prints the table of both shipped gears' recorded runs (tests/data/validate_results_*.json,
written by `strainwave validate`, trimmed to their checks) and fails when a check survives a 20 % error, or a
10 % error without a named allowance, unless it is listed in KNOWN_WEAK with the reason (so a fix shows too)."""
import json
from pathlib import Path

import pytest

from strainwave.compare.validate.mutation_checks import SCALES, mutation_rows, mutation_table_md, weak_checks

DATA = Path(__file__).parent / "data"
RUNS = {"default": DATA / "validate_results_default.json", "second_gear": DATA / "validate_results_second_gear.json"}

# Checks the recorded runs show weak, with why they still are (issue 50: each is an open item, not a pass). Empty since
# issue 50 item 3 (decision 067-crack50b): the surface crack's front resolved (GCI 0.72 / 0.88 %), "between" and
# "minor" retired, the closure angle added.
KNOWN_WEAK: dict[str, dict[str, str]] = {gear: {} for gear in ("default", "second_gear")}


def _synthetic(check_id, fea, ref, tol, relation="equal", reason="GCI 0.1 % (x)"):
    return {"id": check_id, "fea": fea, "analytic": {"corrected": ref}, "asserts": "corrected",
            "tolerance": {"relative": tol, "reason": reason}, "relation": relation}


def test_mutation_rows_rejudge_by_validates_rule():
    tight, loose, bound = mutation_rows([
        _synthetic("a.tight", 1.0, 1.0, 0.05),
        _synthetic("a.loose", 1.0, 1.0, 0.15, reason="GCI 1 % (x) + 14 % plane stress vs plane strain"),
        _synthetic("a.bound", 1.0, 1.0, 0.05, relation="at_most"),
        ])
    assert tight.catches_10 and tight.catches_20
    assert loose.catches_20 and not loose.catches_10 and loose.has_named_allowance
    # 0.9 x the reference puts the FEA 11 % above it: outside 15 %? no; 0.8 x: 25 % above: fails
    assert not loose.fails_at("reference", 0.9) and loose.fails_at("reference", 0.8)
    # an upper bound fails only above it: a lower FEA is no error of that check
    assert bound.fails_at("fea", 1.1) and not bound.fails_at("fea", 0.8) and not bound.catches_20
    assert weak_checks([tight, loose]) == []
    assert weak_checks([bound]) == ["a.bound: survives a 20 % error (tolerance 5 %)"]
    bare = mutation_rows([_synthetic("a.bare", 1.0, 1.0, 0.15)])
    assert weak_checks(bare)[0].startswith("a.bare: survives a 10 % error with no named allowance")
    assert "not evaluated" in weak_checks(mutation_rows([{"id": "a.none", "fea": None}]))[0]


@pytest.mark.parametrize("gear", sorted(RUNS))
def test_mutation_table_of_the_recorded_run(gear, capsys):
    doc = json.loads(RUNS[gear].read_text(encoding="utf-8"))
    rows = mutation_rows(doc["checks"])
    table = mutation_table_md(rows)
    with capsys.disabled():
        print(f"\nmutation table, {gear} ({doc['source']}):\n{table}")
    assert len(rows) == len(doc["checks"]) >= 20 and all(r.mutations for r in rows)
    assert all(len(r.mutations) == 2 * len(SCALES) for r in rows)
    # the recorded run passes: the unscaled checks are inside their tolerances
    assert all(c["passed"] for c in doc["checks"]), [c["id"] for c in doc["checks"] if not c["passed"]]
    weak = {w.split(":", 1)[0]: w for w in weak_checks(rows)}
    assert set(weak) == set(KNOWN_WEAK[gear]), {"weak now": weak, "listed": KNOWN_WEAK[gear]}
