"""The one command-line interface: parse flags, call one library function, print, map errors to exit codes.

Exit codes: 0 fine; 1 a check, mesher or solver failed; 2 bad input. Library imports are
lazy so ``strainwave --help`` stays instant and no stage does work at import time.
"""
from __future__ import annotations

import argparse
import json
import sys
import traceback
import warnings
from pathlib import Path

from .errors import InputError, RangeWarning, StrainwaveError

STUDIES = ("shaft-torsion", "cup-torsion", "bearing-ring", "ring-compression")
PARTS = ("flexspline-cup", "ewg-flexspline-ring", "ewg", "output-shaft", "wg-bearing-ring", "assembly")


class _Parser(argparse.ArgumentParser):
    """argparse that raises InputError (exit 2, one line) instead of printing usage and exiting."""

    def error(self, message):
        raise InputError("command line", " ".join(sys.argv[1:]), message)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0 or value != value or value == float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} must be a finite number > 0")
    return value


def _params(args):
    from .params import load_params
    return load_params(args.params)


def _write_json(data: dict, out: Path | None) -> None:
    text = json.dumps(data, indent=2, default=str)
    if out is None:
        print(text)
    else:
        from .io_atomic import atomic_write_text
        atomic_write_text(Path(out), text + "\n")


# ---- subcommands: each is a thin layer over one library function -------------------------------

def _cmd_analytic(args) -> int:
    params = _params(args)
    from .analytic.summary import analytic_summary, format_summary
    summary = analytic_summary(params)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(format_summary(summary))
    return 0


def _cmd_export_step(args) -> int:
    from .geometry.export import export_part
    written = export_part(args.part, _params(args), Path(args.output), crack_depth_mm=args.crack_depth_mm,
                          teeth=not args.no_teeth, png=Path(args.png) if args.png else None)
    for path in written:
        print(f"wrote {path}")
    return 0


def _cmd_solve(args) -> int:
    from .fea.studies import run_study
    result = run_study(args.study, _params(args), mesh_size_mm=args.mesh_size_mm, order=args.order,
                       crack_depth_mm=args.crack_depth_mm, vtu=Path(args.vtu) if args.vtu else None,
                       progress=lambda msg: print(msg, file=sys.stderr))
    print(json.dumps(result.to_dict(), indent=2, default=str) if args.json else result.summary())
    return 0


def _cmd_validate(args) -> int:
    from .compare.validate.pipeline import run_validate
    outcome = run_validate(_params(args), Path(args.out), quick=args.quick,
                           progress=lambda msg: print(msg, file=sys.stderr))
    print(outcome.summary())
    return 0 if outcome.passed else 1


def _cmd_diagnose(args) -> int:
    from .compare.diagnose.pipeline import diagnose_file
    diagnosis = diagnose_file(Path(args.recording), params_path=args.params, baseline=args.baseline,
                              json_out=Path(args.json) if args.json else None,
                              plot_out=Path(args.plot) if args.plot else None)
    print(diagnosis.summary())
    return 0


def _cmd_benchmark_diagnose(args) -> int:
    from .compare.diagnose.benchmark import run_benchmark
    report = run_benchmark(n_per_class=args.n, seed=args.seed, out_dir=Path(args.out) if args.out else None)
    print(report.summary())
    return 0 if report.meets_targets else 1


def _cmd_sweep(args) -> int:
    from .compare.sweep.pipeline import run_sweep
    outcome = run_sweep(args.study, vary=args.vary, params_path=args.params, sample_file=args.samples,
                        scheduler=args.scheduler, workers=args.workers, out_dir=Path(args.out),
                        quick=args.quick, tolerance=args.tolerance,
                        progress=lambda msg: print(msg, file=sys.stderr))
    print(outcome.summary())
    # Failed points are results (recorded with their error); only a sweep with no good point at all fails.
    return 0 if outcome.n_ok else 1


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="strainwave", description="Strain wave gear CAD, FEA and seed-paper validation.")
    parser.add_argument("--debug", action="store_true", help="show tracebacks of internal errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    def add(name, func, help_text):
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.add_argument("--params", metavar="FILE.toml", help="partial parameter file (rest from the default)")
        p.set_defaults(func=func)
        return p

    p = add("analytic", _cmd_analytic, "every closed form of both seeds, published and corrected")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")

    p = add("export-step", _cmd_export_step, "build a part and write it as STEP (mm)")
    p.add_argument("--part", required=True, choices=PARTS)
    p.add_argument("--crack-depth-mm", type=_positive_float, default=None, help="seed a crack of this depth")
    p.add_argument("--no-teeth", action="store_true", help="smooth shell of the same mid-surface")
    p.add_argument("--png", metavar="FILE.png", help="also render an off-screen preview")
    p.add_argument("-o", "--output", required=True, metavar="FILE.step")

    p = add("solve", _cmd_solve, "mesh and solve one FEA study")
    p.add_argument("study", choices=STUDIES)
    p.add_argument("--mesh-size-mm", type=_positive_float, default=None)
    p.add_argument("--order", type=int, choices=(1, 2), default=2)
    p.add_argument("--crack-depth-mm", type=_positive_float, default=None)
    p.add_argument("--json", action="store_true")
    p.add_argument("--vtu", metavar="FILE.vtu")

    p = add("validate", _cmd_validate, "all studies vs the closed forms: report, images, STEP, VTU")
    p.add_argument("--out", default="reports/validate", metavar="DIR")
    p.add_argument("--quick", action="store_true", help="coarse meshes, fewer sweep points")

    p = add("diagnose", _cmd_diagnose, "locate, name and model the mismatch between a recording and the model")
    p.add_argument("recording", metavar="RECORDING.csv")
    p.add_argument("--baseline", choices=("analytic", "fea"), default="analytic")
    p.add_argument("--json", metavar="OUT.json")
    p.add_argument("--plot", metavar="OUT.png")

    p = add("benchmark-diagnose", _cmd_benchmark_diagnose, "score diagnose blind on generated recordings")
    p.add_argument("--n", type=int, default=20, help="recordings per effect class")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", metavar="DIR")

    p = add("sweep", _cmd_sweep, "parameter sweep of one study on Dask")
    p.add_argument("study", choices=STUDIES)
    p.add_argument("--vary", action="append", default=[], metavar="KEY=START:STOP:N|v1,v2")
    p.add_argument("--samples", metavar="FILE.csv", help="CSV of parameter rows (dotted keys as columns)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="existing Dask scheduler, e.g. tcp://host:8786")
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--out", default="reports/sweep", metavar="DIR")
    p.add_argument("--quick", action="store_true", help="coarse meshes")
    p.add_argument("--tolerance", type=float, default=0.05, help="relative departure named in the summary")
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    debug = "--debug" in argv
    with warnings.catch_warnings():
        warnings.simplefilter("default", RangeWarning)  # each distinct warning once
        warnings.showwarning = lambda msg, cat, *a, **k: print(f"warning: {msg}", file=sys.stderr)
        try:
            args = build_parser().parse_args(argv)
            return args.func(args)
        except StrainwaveError as exc:
            print(f"error: {exc}", file=sys.stderr)
            if debug:
                traceback.print_exc()
            return exc.exit_status
        except KeyboardInterrupt:
            print("error: interrupted", file=sys.stderr)
            return 130
        except Exception as exc:  # noqa: BLE001 - last line of defence: one line, no traceback
            print(f"error: internal error ({type(exc).__name__}: {exc}); rerun with --debug", file=sys.stderr)
            if debug:
                traceback.print_exc()
            return 1


if __name__ == "__main__":
    sys.exit(main())
