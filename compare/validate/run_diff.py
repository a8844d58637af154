"""``strainwave compare RUN_A RUN_B``: the checks whose value, verdict or tolerance changed between two runs.

Each run is a validation output folder (or its results.json). A check present in one run only is listed as
added or removed; a value counts as changed beyond ``rtol`` relative (default 1e-9, the regression test's),
so a rerun of the same code on the same machine lists nothing.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from strainwave.errors import InputError

__all__ = ["CheckChange", "RunDiff", "load_run", "diff_runs", "run_warnings"]

FIELDS = ("fea", "fea_uncertainty", "tolerance", "verdict", "passed")


def load_run(path: Path, flag: str) -> dict:
    """The results document of a run folder (or of a results.json); a missing or unreadable one is bad input."""
    path = Path(path)
    file = path / "results.json" if path.is_dir() else path
    if not file.is_file():
        raise InputError(flag, str(path), "a validation output folder holding results.json, or a results.json file")
    try:
        doc = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(flag, str(path), f"a readable results.json ({type(exc).__name__}: {exc})") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("checks"), list):
        raise InputError(flag, str(path), "a results.json of strainwave validate (with a 'checks' list)")
    return doc


def _values(check: dict) -> dict:
    return {"fea": check.get("fea"), "fea_uncertainty": check.get("fea_uncertainty"),
            "tolerance": (check.get("tolerance") or {}).get("relative"), "verdict": check.get("verdict"),
            "passed": check.get("passed")}


def _differs(a, b, rtol: float) -> bool:
    if isinstance(a, float) and isinstance(b, float) and not isinstance(a, bool):
        return not math.isclose(a, b, rel_tol=rtol, abs_tol=0.0)
    return a != b


@dataclass(frozen=True)
class CheckChange:
    check_id: str
    status: str                 # changed | added | removed
    fields: tuple[str, ...]     # what changed
    a: dict
    b: dict

    def to_dict(self) -> dict:
        return {"id": self.check_id, "status": self.status, "changed": list(self.fields), "a": self.a, "b": self.b}


def _mode(doc: dict) -> str | None:
    quick = ((doc.get("metadata") or {}).get("settings") or {}).get("quick")
    return None if quick is None else ("--quick" if quick else "full")


def _depths(doc: dict) -> dict:
    return ((doc.get("metadata") or {}).get("settings") or {}).get("sweep_depths_mm") or {}


def run_warnings(a: dict, b: dict, param_changes: list[dict]) -> list[str]:
    """One line per reason the two runs' checks do not measure the same thing: another mode (meshes and crack
    depths), other crack-depth sweeps, other parameters (another gear)."""
    out = []
    if _mode(a) and _mode(b) and _mode(a) != _mode(b):
        out.append(f"A is a {_mode(a)} run and B a {_mode(b)} run: their meshes and crack depths differ, so a changed "
                   "value is not a regression (compare runs of the same mode)")
    elif _depths(a) != _depths(b) and _depths(a) and _depths(b):
        out.append("the runs swept other crack depths: the crack checks measure different cracks")
    if param_changes:
        keys = ", ".join(d["key"] for d in param_changes[:4]) + (", ..." if len(param_changes) > 4 else "")
        out.append(f"the runs differ in {len(param_changes)} parameter(s) ({keys}): their checks measure "
                   "different gears")
    return out


def _params_of(doc: dict) -> dict:
    return (doc.get("metadata") or {}).get("params") or {}


def _design_of(doc: dict) -> str:
    design = doc.get("design")
    if not design:
        return "not evaluated"
    return design.get("headline") or ("PASS" if design.get("passed") else "FAIL")


def percent_change(a, b) -> float | None:
    """100 (b - a) / |a| for two numbers, None where it means nothing (a missing value, a = 0)."""
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) \
            or not isinstance(b, (int, float)) or a == 0:
        return None
    return 100.0 * (b - a) / abs(a)


def _cell(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "PASS" if value else "FAIL"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


@dataclass(frozen=True)
class RunDiff:
    run_a: str
    run_b: str
    changes: tuple[CheckChange, ...]
    unchanged: int
    warnings: tuple[str, ...] = ()
    params: tuple[dict, ...] = ()          # {key, a, b} of every parameter the runs differ in
    designs: tuple[str, str] = ("not evaluated", "not evaluated")

    def _head(self) -> list[str]:
        lines = [f"warning: {w}" for w in self.warnings] + [f"A = {self.run_a}", f"B = {self.run_b}",
                                                            f"design A: {self.designs[0]}", f"design B: {self.designs[1]}"]
        if self.params:
            width = max(len(p["key"]) for p in self.params)
            lines.append(f"{'parameter':<{width}}  {'A':>14}  {'B':>14}")
            lines += [f"{p['key']:<{width}}  {_cell(p['a']):>14}  {_cell(p['b']):>14}" for p in self.params]
        return lines

    def summary(self) -> str:
        lines = self._head()
        if not self.changes:
            return "\n".join(lines + [f"no check changed value, verdict or tolerance ({self.unchanged} compared)"])
        width = max(len(c.check_id) for c in self.changes)
        lines.append(f"{'check':<{width}}  {'what':<24} {'A':>14}  {'B':>14}  {'change':>9}")
        for c in self.changes:
            for k, name in enumerate(c.fields or ("(whole check)",)):
                label = c.check_id if k == 0 else ""
                what = name if c.status == "changed" else f"{c.status}: {name}"
                a = c.a.get(name) if c.a else None
                b = c.b.get(name) if c.b else None
                pct = percent_change(a, b)
                change = "-" if pct is None else f"{pct:+.3g} %"
                lines.append(f"{label:<{width}}  {what:<24} {_cell(a):>14}  {_cell(b):>14}  {change:>9}")
        lines.append(f"{len(self.changes)} check(s) changed, {self.unchanged} unchanged")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"run_a": self.run_a, "run_b": self.run_b, "unchanged": self.unchanged,
                "warnings": list(self.warnings), "params": list(self.params),
                "design": {"a": self.designs[0], "b": self.designs[1]},
                "changes": [{**c.to_dict(), "percent_change": {f: percent_change(c.a.get(f), c.b.get(f))
                                                               for f in c.fields if c.a and c.b}}
                            for c in self.changes]}


def diff_runs(a: dict, b: dict, *, names: tuple[str, str] = ("A", "B"), rtol: float = 1e-9) -> RunDiff:
    """The checks of run ``b`` against run ``a``, in ``a``'s order then ``b``'s new ones."""
    checks_a = {c["id"]: _values(c) for c in a["checks"]}
    checks_b = {c["id"]: _values(c) for c in b["checks"]}
    changes, unchanged = [], 0
    for check_id in list(checks_a) + [k for k in checks_b if k not in checks_a]:
        va, vb = checks_a.get(check_id), checks_b.get(check_id)
        if va is None or vb is None:
            status = "added" if va is None else "removed"
            changes.append(CheckChange(check_id, status, FIELDS, va or {}, vb or {}))
            continue
        fields = tuple(f for f in FIELDS if _differs(va[f], vb[f], rtol))
        if fields:
            changes.append(CheckChange(check_id, "changed", fields, va, vb))
        else:
            unchanged += 1
    from strainwave.compare.validate.run_record import params_diff
    diff = params_diff(_params_of(b), _params_of(a))   # value = B's, default = A's
    params = tuple({"key": d["key"], "a": d["default"], "b": d["value"]} for d in diff)
    return RunDiff(names[0], names[1], tuple(changes), unchanged, tuple(run_warnings(a, b, diff)), params,
                   (_design_of(a), _design_of(b)))
