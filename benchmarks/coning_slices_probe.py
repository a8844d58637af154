"""Decision 071-coning48: the CHA table predicted with 1, 2, 4, 8 face slices (coning), each number's GCI on 2-4-8.

    .venv/bin/python benchmarks/coning_slices_probe.py [TABLE.csv] [--json OUT] [--slices 1,2,4,8]

The GCI is taken on the last three slice counts (each twice the one before).
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

from strainwave.analytic.catalogue_predict import NAMES, GOALS, predict_table
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.fea.convergence import GciUndefined, grid_convergence

SLICES = (1, 2, 4, 8)
RULE_GCI = {"K3_Nm_per_rad": 0.05, "K1_Nm_per_rad": 0.07}     # decision 071's rule: a fifth of each goal's band


def _gci(slices, values: list[float]) -> tuple[float, bool]:
    """(GCI_fine of the three slice counts (h = 1/n, formal order 2), monotone)."""
    try:
        c = grid_convergence([1 / n for n in slices], values, formal_order=2.0)
    except GciUndefined:
        return 0.0, True
    return c.gci_fine, c.monotone


def run(table: Path, slices=SLICES) -> dict:
    out = {"slices": list(slices), "runs": {}}
    for n in slices:
        t0 = time.process_time()
        p = predict_table(table, replace(MeshRules(), face_slices=n))
        out["runs"][n] = {"cpu_s": p.cpu_s, "process_cpu_s": time.process_time() - t0, **p.to_dict()}
        print(f"slices {n}: {p.cpu_s:.1f} CPU-s", flush=True)
    rows = []
    for k, r1 in enumerate(out["runs"][1]["rows"]):
        row = {"size": r1["size"], "ratio": r1["ratio"]}
        for name in NAMES:
            vals = [out["runs"][n]["rows"][k][f"{name}_predicted"] for n in slices]
            cat = r1[f"{name}_catalogue"]
            row[name] = {"over_catalogue": [v / cat if cat else None for v in vals]}
            row[name]["gci"], row[name]["monotone"] = _gci(slices[-3:], vals[-3:])
        rows.append(row)
    out["table"] = rows
    out["rule_met"] = all(r[name]["gci"] <= tol for r in rows for name, tol in RULE_GCI.items())
    out["goal_counts"] = {n: {name: sum(1 for r in rows if r[name]["over_catalogue"][i] is not None
                                        and abs(r[name]["over_catalogue"][i] - 1) <= tol)
                              for name, tol in GOALS.items()} for i, n in enumerate(slices)}
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("table", nargs="?", default="/work/shared/data/cha_torsional_stiffness.csv")
    ap.add_argument("--json")
    ap.add_argument("--slices", default=",".join(map(str, SLICES)), help="comma-separated, the last three doubling")
    a = ap.parse_args()
    out = run(Path(a.table), tuple(int(n) for n in a.slices.split(",")))
    for r in out["table"]:
        cells = [f"{r['size']:g}/{r['ratio']}"]
        for name in NAMES:
            q = r[name]["over_catalogue"]
            cells.append(" / ".join(f"{v:.2f}" if v else "-" for v in q) + f" ({100 * r[name]['gci']:.2g} %"
                         + ("" if r[name]["monotone"] else ", osc") + ")")
        print(" | ".join(cells))
    print("rule met:", out["rule_met"])
    print("goal counts:", json.dumps(out["goal_counts"]))
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1, default=str))


if __name__ == "__main__":
    main()
