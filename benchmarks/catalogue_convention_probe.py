"""Decision 069 (cat48d): the CHA table read as the catalogue defines K1/K2/K3 (secants of the mean loop curve over
the row's own T1, T2 windows, K3 to the loop amplitude), beside the knee reader, and what the amplitude does.

Run: .venv/bin/python benchmarks/catalogue_convention_probe.py [RULES_JSON]   (prints one JSON line per row and a
summary; RULES_JSON: MeshRules overrides, e.g. '{"rim_rule": "fatigue"}'; --rated-only: the rated amplitude only;
--cs-ring=F: the circular spline body's free-ring twist x F in series, analytic/cs_ring.py)
"""
from __future__ import annotations

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from strainwave.analytic.catalogue_predict import read_table
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import _loop, catalogue_secants, read_catalogue_numbers

TABLE = Path("/work/shared/data/cha_torsional_stiffness.csv")
AMPLITUDES = {"rated": None, "1.2T2": 1.2, "2T2": 2.0}     # loop amplitude: the rules' rated torque, or x T2


def first_loading_secants(T, tw, T1, T2, A):
    k0 = int(np.argmax(T))
    phi = np.interp([0.0, T1, T2, A], T[:k0 + 1], tw[:k0 + 1])
    return {"K1": T1 / (phi[1] - phi[0]), "K2": (T2 - T1) / (phi[2] - phi[1]), "K3": (A - T2) / (phi[3] - phi[2])}


def main(overrides: dict) -> None:
    rules = replace(MeshRules(), **overrides)
    rows = read_table(TABLE.read_text())
    t0 = time.process_time()
    zone = {r: rules.cup_zone_term(r) for r in sorted({row.ratio for row in rows})}
    out = []
    for row in rows:
        d = rules.pitch_diameter_mm(row.size)
        design = rules.design(row.size, row.ratio)
        series = rules.cup_flexibility_rad_per_Nmm(row.size) + (zone[row.ratio].at(d) if zone[row.ratio] else 0.0)
        if CS_RING:      # decision 069 item 3: the circular spline body as a free ring (the soft bound), x CS_RING
            from strainwave.analytic.cs_ring import cs_body_twist_rad_per_Nmm
            series += CS_RING * cs_body_twist_rad_per_Nmm(design, 1.25 * d)
        cat = row.values
        T1, T2 = cat["T1_Nm"], cat["T2_Nm"]
        rec = {"size": row.size, "ratio": row.ratio_label}
        for name, f in (AMPLITUDES if FULL else {"rated": None}).items():
            A = rules.rated_torque_Nm(row.size) if f is None else f * T2
            T, tw, _ = _loop(design, series, A, 0.0)
            sec = catalogue_secants(T, tw, T1, T2)
            rec[name] = {k.split("_")[0]: sec[k] / cat[k] for k in sec}
            rec[name]["A_over_T2"] = A / T2
            if f is None:
                v = read_catalogue_numbers(T, tw, A)
                rec["reader"] = {k: v[k][0] / cat[f"{k}_Nm_per_rad" if k[0] == "K" else f"{k}_Nm"]
                                 for k in ("K1", "K2", "K3", "T1", "T2")}
                fl = first_loading_secants(T, tw, T1, T2, A)
                rec["first_loading"] = {k: fl[k] / cat[f"{k}_Nm_per_rad"] for k in fl}
                rec["secant_K3_abs"] = sec["K3_Nm_per_rad"]
        out.append(rec)
        print(json.dumps(rec))
    cpu = time.process_time() - t0
    _summary(out, cpu)


def _summary(out, cpu):
    goals = {"K1": 0.35, "K3": 0.25, "T1": 0.35, "T2": 0.35}
    for src in ("reader", "rated", "1.2T2", "2T2", "first_loading") if FULL else ("reader", "rated", "first_loading"):
        line = [src]
        for k in ("K1", "K2", "K3"):
            q = [r[src][k] for r in out]
            n = sum(abs(x - 1) <= goals.get(k, 0.25) for x in q) if k in goals else "-"
            line.append(f"{k} {min(q):.2f}-{max(q):.2f} ({n}/21)")
        print(" | ".join(line))
    for src in ("reader", "rated", "1.2T2", "2T2") if FULL else ("reader", "rated"):
        tr = []
        for s in sorted({r["size"] for r in out}):
            have = [r for r in out if r["size"] == s]
            lo, hi = have[0], have[-1]
            tr.append(hi[src]["K3"] / lo[src]["K3"])
        print(f"trend {src}: K3(hi)/K3(lo) predicted/catalogue per size " + " ".join(f"{t:.2f}" for t in tr)
              + f" ({sum(abs(t - 1) <= 0.25 for t in tr)}/{len(tr)})")
    print(f"CPU {cpu:.1f} s")


FULL = "--rated-only" not in sys.argv
CS_RING = next((float(a.split("=")[1]) for a in sys.argv if a.startswith("--cs-ring=")), 0.0)

if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(json.loads(args[0]) if args else {})
