"""Every Diagnosis of a fixed set of generated recordings as JSON: a refactor of the diagnosis must leave it
byte-identical (compare two runs with `cmp`).

Run: OMP_NUM_THREADS=1 .venv/bin/python benchmarks/diagnose_fingerprint.py OUT.json [--seed 3] [--cha 2]
Both generator families, one recording per class of 200-700 rows, ``--cha`` CHA table rows with and without a
loop; one worker, so the answer cannot depend on process scheduling.
"""
from __future__ import annotations

import argparse
import json
import warnings

from strainwave.errors import RangeWarning
from strainwave.io_atomic import json_ready


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--cha", type=int, default=2)
    args = ap.parse_args()
    from strainwave.compare.diagnose.generators.benchmark import concealed_recordings
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.recording import parse_text
    from strainwave.params import load_params
    warnings.simplefilter("ignore", RangeWarning)
    params, out = load_params(), {}
    for family in (1, 2):
        for name, c in concealed_recordings(family, 1, args.seed, params, rows=(200, 700), cha=args.cha):
            rec = parse_text(c.text, f"{name}.csv")
            diag, _ = diagnose(rec, load_params(overrides=rec.param_overrides) if rec.param_overrides else params,
                               workers=1)
            out[name] = {**json_ready(diag.to_dict()), "summary": diag.summary()}
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(out, f, indent=1, sort_keys=True, default=str)
    print(f"{len(out)} recordings -> {args.out}")


if __name__ == "__main__":
    main()
