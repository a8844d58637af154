"""The mutation table: would each check of a run fail if its FEA value, or its asserted closed form, were wrong by
10 % or 20 %?

For every check of a ``results.json`` the FEA value and then the asserted reference are scaled by each of
``SCALES`` with the run's own tolerance held, and the check is re-judged by the same rule as validate
(``checks.within``). A check must fail at +-20 % either way; one that survives a +-10 % error must say why in
its tolerance reason: a named allowance (a physical spread fixed before the result), not the GCI alone.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.compare.validate.checks import relative_error, within

__all__ = ["SCALES", "Mutation", "MutationRow", "mutation_rows", "mutation_table_md", "weak_checks"]

SCALES = (0.8, 0.9, 1.1, 1.2)
SIDES = ("fea", "reference")


@dataclass(frozen=True)
class Mutation:
    side: str            # "fea" | "reference": which one was scaled
    scale: float
    rel_error: float     # of the mutated check against its asserted closed form
    fails: bool


@dataclass(frozen=True)
class MutationRow:
    check_id: str
    rel_error: float          # the run's own
    tolerance: float
    reason: str
    relation: str
    mutations: tuple[Mutation, ...]
    why_not: str = ""         # why the check carries no mutations (not evaluated)

    def fails_at(self, side: str, scale: float) -> bool:
        return next(m.fails for m in self.mutations if m.side == side and m.scale == scale)

    @property
    def catches_20(self) -> bool:
        """It fails at 0.8 and 1.2, of the FEA and of the reference."""
        return bool(self.mutations) and all(self.fails_at(s, k) for s in SIDES for k in (0.8, 1.2))

    @property
    def catches_10(self) -> bool:
        return bool(self.mutations) and all(self.fails_at(s, k) for s in SIDES for k in (0.9, 1.1))

    @property
    def has_named_allowance(self) -> bool:
        """The tolerance reason names something beside the GCI (a physical spread, stated before the result)."""
        return " + " in self.reason


def _row(check: dict) -> MutationRow:
    cid = check["id"]
    tol = (check.get("tolerance") or {}).get("relative")
    fea = check.get("fea")
    ref = (check.get("analytic") or {}).get(check.get("asserts", "corrected"))
    relation = check.get("relation", "equal")
    reason = (check.get("tolerance") or {}).get("reason", "")
    if fea is None or ref is None or tol is None or not math.isfinite(tol):
        return MutationRow(cid, math.nan, math.nan, reason, relation, (),
                           why_not=check.get("reason_not_evaluated") or "not evaluated")
    mutations = []
    for side in SIDES:
        for k in SCALES:
            e = relative_error(fea * k, ref) if side == "fea" else relative_error(fea, ref * k)
            mutations.append(Mutation(side, k, e, not within(e, tol, relation)))
    return MutationRow(cid, relative_error(fea, ref), tol, reason, relation, tuple(mutations))


def mutation_rows(checks: list[dict]) -> list[MutationRow]:
    """One row per check of a results.json ``checks`` list, in its order."""
    return [_row(c) for c in checks]


def weak_checks(rows: list[MutationRow]) -> list[str]:
    """What the issue forbids: a check surviving +-20 %, or surviving +-10 % with no named allowance."""
    out = []
    for r in rows:
        if not r.mutations:
            out.append(f"{r.check_id}: not evaluated ({r.why_not})")
        elif not r.catches_20:
            out.append(f"{r.check_id}: survives a 20 % error (tolerance {100 * r.tolerance:.3g} %)")
        elif not r.catches_10 and not r.has_named_allowance:
            out.append(f"{r.check_id}: survives a 10 % error with no named allowance ({r.reason})")
    return out


def _cell(row: MutationRow, side: str) -> str:
    return " ".join(("FAIL" if row.fails_at(side, k) else "pass") for k in SCALES)


def mutation_table_md(rows: list[MutationRow]) -> str:
    """The table as markdown: per check its error and tolerance, then the verdict at each scaling of the FEA
    value and of the reference (x0.8 x0.9 x1.1 x1.2), and whether it catches 10 % / 20 %."""
    scales = " ".join(f"x{k:g}" for k in SCALES)
    lines = [f"| check | error | tolerance | FEA {scales} | reference {scales} | catches 10 % | catches 20 % |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r.mutations:
            lines.append(f"| `{r.check_id}` | not evaluated | | | | | |")
            continue
        lines.append(f"| `{r.check_id}` | {100 * r.rel_error:+.2f} % | {100 * r.tolerance:.3g} % | {_cell(r, 'fea')} | "
                     f"{_cell(r, 'reference')} | {'yes' if r.catches_10 else 'no'} | "
                     f"{'yes' if r.catches_20 else 'NO'} |")
    return "\n".join(lines)
