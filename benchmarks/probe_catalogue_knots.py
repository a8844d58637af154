"""The catalogue's readings against the loop's torque step and the reader's grid (decision 074).

Usage: python benchmarks/probe_catalogue_knots.py TABLE.csv [--steps 60,120,240] [--grid 400,800] [--grade A]
       [--old] [--out FILE]      (--old: the reading before decision 074, on the solve's own steps)

The FE series terms (cup zone, circular spline body) do not depend on the loop's step: solved once per ratio and
reused; each (step, grid) pair then predicts every row, and the readings are written as JSON
{"step/grid": [{size, ratio, name: predicted}, ...]}, with each pair's CPU-s.
"""
from __future__ import annotations

import argparse
import functools
import json
import time
from pathlib import Path

from strainwave.analytic import catalogue_predict as cp
from strainwave.analytic import drive_curve as dc
from strainwave.analytic.catalogue_rules import MeshRules

NAMES = tuple(f"{n}_predicted" for n in cp.NAMES) + ("K1_Nm_per_rad_reader", "K2_Nm_per_rad_reader", "K3_Nm_per_rad_reader",
                    "lost_motion_arcmin_reader", "hysteresis_loss_arcmin_reader", "hysteresis_loss_arcmin_predicted",
                    "lost_motion_arcmin_predicted", "loop_width_max_arcmin")


def _old_reading() -> None:
    """The catalogue's paths with the exact loop switched off (the reading on the solve's own steps)."""
    from strainwave.analytic import catalogue_similar as cs
    for mod, name in ((cs, "predict_curve"), (cp, "predict_curve"), (cp, "unit_curves")):
        f = getattr(dc, name)
        setattr(mod, name, lambda *args, _f=f, **kw: _f(*args, **{**kw, "exact": False}))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("table")
    ap.add_argument("--steps", default="60,120,240")
    ap.add_argument("--grid", default="400")
    ap.add_argument("--grade", type=float, default=None, help="ISO 1328-1 class (tooth deviations, 4 units)")
    ap.add_argument("--old", action="store_true", help="read the solve's own steps (before decision 074)")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    if a.old:
        _old_reading()
    rules = MeshRules()
    if a.grade is not None:
        from dataclasses import replace
        rules = replace(rules, accuracy_grade=a.grade, deviation_units=4)
    # the FE terms once per ratio (they do not see the loop's step)
    for name in ("cup_zone_term", "cs_body_term"):
        setattr(MeshRules, name, functools.lru_cache(maxsize=None)(getattr(MeshRules, name)))
    rows = cp.read_table(Path(a.table).read_text("utf-8"))
    from threadpoolctl import threadpool_limits
    out = {}
    with threadpool_limits(limits=1):
        cp._predict_rows(rules, rows[:1])          # warm the FE terms' cache
        for steps in (int(s) for s in a.steps.split(",")):
            for grid in (int(g) for g in a.grid.split(",")):
                dc.LOOP_STEPS_PER_LEG = steps
                if hasattr(dc, "READ_STEPS_PER_LEG"):
                    dc.READ_STEPS_PER_LEG = grid
                t0 = time.process_time()
                pred = cp._predict_rows(rules, rows).to_dict()["rows"]
                key = f"{steps}/{grid}"
                out[key] = {"cpu_s": time.process_time() - t0,
                            "rows": [{k: r.get(k) for k in ("size", "ratio") + NAMES} for r in pred]}
                print(key, f"{out[key]['cpu_s']:.2f} CPU-s", flush=True)
    text = json.dumps(out, indent=1)
    if a.out:
        Path(a.out).write_text(text)
    else:
        print(text)


if __name__ == "__main__":
    main()
