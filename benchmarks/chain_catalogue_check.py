"""Issue 48 item 4: what `gear.catalogue_stiffness` (compare/validate/mesh_chain_checks.py, not in the required
list) reads on a validate run's recorded members, with the circular spline body in the chain (decision 070).

Run: .venv/bin/python benchmarks/chain_catalogue_check.py RESULTS.json [PARAMS.toml]
(RESULTS.json: `strainwave validate [--quick] --out DIR` writes DIR/results.json; its gci_table holds the members)
"""
from __future__ import annotations

import json
import sys

from strainwave.compare.validate import mesh_chain_checks as mc
from strainwave.params import load_params


class RecordedBook:
    """The FEA quantities of a results.json's gci_table: (case, quantity) -> finest value, GCI x value."""

    def __init__(self, results: dict):
        self.rows = {(r["case"], r["quantity"]): r for r in results["gci_table"]}

    def quantity(self, label, name):
        r = self.rows.get((label, name))
        if r is None:
            return None, f"{label}: no {name}"
        v = r["values"][0]
        return type("Q", (), {"value": v, "uncertainty": (r["gci_fine"] or 0.0) * abs(v)}), ""

    def case(self, prefix):
        return next(c for c, _ in self.rows if c.startswith(prefix))


def main(path, params_path=None):
    book = RecordedBook(json.load(open(path)))
    params = load_params(params_path)
    labels = {"cup": book.case("cup-"), "shaft": book.case("shaft-")}
    c = mc.catalogue_check(book, labels, "wg-bearing", "tooth-mesh", params)
    print(f"{c.id}: value {c.fea:.4g} {c.unit}, reference {c.analytic['corrected']:.4g}, "
          f"ratio {c.fea / c.analytic['corrected']:.3f}, tolerance +-{100 * c.tolerance.relative:.3g} % "
          f"({c.tolerance.reason}), error {c.rel_error}, passed {c.passed}")
    print(f"note: {c.note}")
    print(mc.gear_line(book, type("P", (), {"headline": {k: type("C", (), {"label": v}) for k, v in labels.items()},
                                            "label_of": lambda self, s: {"wg-bearing": "wg-bearing",
                                                                         "tooth-mesh": "tooth-mesh"}[s]})(), params))


if __name__ == "__main__":
    main(*sys.argv[1:3])
