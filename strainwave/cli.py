"""The one command-line interface: parse flags, call one library function, print, map errors to exit codes.

Exit codes: 0 fine; 1 a check, mesher or solver failed; 2 bad input; 3 the design fails [n] (validate
--require-design only). Library imports are
lazy so ``strainwave --help`` stays instant and no stage does work at import time.

Conventions shared by every subcommand: ``-q`` / ``-v`` / ``--debug`` go before or after the
subcommand; progress and warnings go through ``logging`` to stderr (``-q`` keeps errors only, ``-v``
adds debug detail); ``--json [FILE]`` writes the command's result as JSON to FILE, or to stdout in
place of the text when FILE is left out or is ``-``.
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import logging
import os
import sys
import traceback
import warnings
from pathlib import Path

from strainwave.errors import InputError, MaterialWarning, RangeWarning, StageError, StrainwaveError
from strainwave.input_guard import printable
from strainwave.geometry.part import PartName
from strainwave.registry import STUDY_NAMES as STUDIES

PARTS = tuple(p.value for p in PartName) + ("assembly",)


LOG = "strainwave"   # the logger every stage's progress and every warning goes through


class _Parser(argparse.ArgumentParser):
    """argparse that raises InputError (exit 2, one line) instead of printing usage and exiting."""

    def error(self, message):
        raise InputError("command line", " ".join(sys.argv[1:]), message)


class _Help(argparse.RawDescriptionHelpFormatter):
    """Every option's help ends with its default when it has a value one (not None, not a flag's False);
    descriptions keep their line breaks."""

    def _get_help_string(self, action):
        text = action.help or ""
        # a help that names its default already ("(default 3)") is not given a second one
        if action.default not in (None, False, argparse.SUPPRESS) and "(default" not in text \
                and action.option_strings and not isinstance(action.default, list):
            text += " (default: %(default)s)"
        return text


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0 or value != value or value == float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} must be a finite number > 0")
    return value


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("strainwave")
    except PackageNotFoundError:   # run from a source tree that was never installed
        return "unknown (not installed)"


def _params(args):
    from strainwave.params import load_params
    return load_params(args.params)


def _progress(msg: str) -> None:
    logging.getLogger(LOG).info(msg)


def _emit(args, text: str, data) -> None:
    """Print ``text``, or the JSON of ``data`` (a dict, or a callable giving one) as ``--json`` asks:
    to stdout instead of the text (``--json`` / ``--json -``), or to a file next to the text."""
    target = getattr(args, "json", None)
    if target is None:
        from strainwave.output_guard import unstage_text
        print(unstage_text(text))
        return
    from strainwave.io_atomic import json_ready
    from strainwave.output_guard import unstage_text   # staged outputs are named by where they will be
    payload = json.dumps(json_ready(data() if callable(data) else data), indent=2, default=str, allow_nan=False) + "\n"
    if target == "-":
        sys.stdout.write(unstage_text(payload))
    else:
        from strainwave.io_atomic import atomic_write_text
        atomic_write_text(Path(target), unstage_text(payload))
        print(unstage_text(text))


def _plain(value):
    """Dataclass records -> JSON-able values (paths and enums as strings)."""
    import dataclasses
    import enum
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        if hasattr(value, "to_dict"):
            return _plain(value.to_dict())
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, Path):
        return str(value)
    return value


# ---- subcommands: each is a thin layer over one library function -------------------------------

def _cmd_analytic(args) -> int:
    params = _params(args)
    from strainwave.analytic.summary import analytic_summary, format_summary
    summary = analytic_summary(params)
    _emit(args, format_summary(summary), summary)
    return 0


def _cmd_params(args) -> int:
    if args.print_default:
        from importlib import resources
        sys.stdout.write(resources.files("strainwave").joinpath("data/defaults.toml").read_text(encoding="utf-8"))
        return 0
    params = _params(args)
    data = params.to_dict()
    text = "\n".join(f"{section}.{key} = {value!r}" for section, table in data.items() for key, value in table.items())
    _emit(args, text, data)
    return 0


@contextlib.contextmanager
def _crack_flag(depth_mm: float | None):
    """A refusal of the crack a user gave as --crack-depth-mm names that flag, not the parameter key or the
    geometry's argument it was passed on as (issue 53: refusals name what the user gave)."""
    try:
        yield
    except InputError as exc:
        if depth_mm is None:
            raise
        if str(exc.key).endswith("crack_depth_mm") and exc.value == depth_mm:
            raise InputError("--crack-depth-mm", depth_mm, exc.allowed) from None
        if exc.key == "crack_geometry.slot_width_mm":   # the parameters' own cracks passed this: the flag's is too shallow
            raise InputError("--crack-depth-mm", depth_mm, f"must be >= 5 x crack_geometry.slot_width_mm = "
                                                           f"{5 * exc.value:g} mm (a slot, not a notch)") from None
        raise


def _cmd_export_step(args) -> int:
    from strainwave.fea.budget import TOOTHED_PARTS, check_cad_teeth
    from strainwave.geometry.export import export_part
    params = _params(args)
    if not args.no_teeth:
        check_cad_teeth(params, list(TOOTHED_PARTS) if args.part == "assembly" else [args.part])
    from strainwave.progress import ticking
    try:
        with _crack_flag(args.crack_depth_mm), \
                ticking(f"export-step {args.part}: building and writing", _progress, first_s=EXPORT_FIRST_TICK_S):
            written = export_part(args.part, params, Path(args.output), crack_depth_mm=args.crack_depth_mm,
                                  teeth=not args.no_teeth, png=Path(args.png) if args.png else None)
    except (StrainwaveError, OSError):
        raise
    except Exception as exc:   # noqa: BLE001 - OCC's own failures ("Could not create line", "No geometry")
        # on a geometry it cannot build: a failure of the CAD stage of this part, said as such (exit 1)
        raise StageError("CAD", args.part, f"{type(exc).__name__}: {exc}") from exc
    _emit(args, "\n".join(f"wrote {path}" for path in written), {"written": [str(p) for p in written]})
    return 0


# the export's first "still working" line: past the seconds a refused crack depth takes to be said on a loaded
# machine (CAD imports), so a refusal stays one line; then every 5 s
EXPORT_FIRST_TICK_S = 10.0


def _cmd_solve(args) -> int:
    with _crack_flag(args.crack_depth_mm):
        return _solve(args)


def _solve(args) -> int:
    import tempfile

    from strainwave.fea.budget import check_budget
    from strainwave.fea.studies import run_study, with_crack
    from strainwave.rated_stress import stress_at_rated, stress_field_of, write_at_rated
    params = _params(args)
    # Refusable before any CAD or meshing: a crack through the wall, a mesh beyond the element budget.
    with_crack(args.study, params, args.crack_depth_mm)
    check_budget(args.study, params, args.mesh_size_mm)
    if args.inp:
        from strainwave.registry import STUDIES as REGISTRY
        if REGISTRY[args.study].facts().plane:   # a CalculiX solid deck needs the 3D mesh
            from strainwave.output_guard import unstage_text
            raise InputError("--inp", unstage_text(args.inp), f"a 3D study; {args.study} is meshed as a plane "
                             "section (use --msh)")
    # The field is always written (to a scratch folder without --vtu): the rated-load peaks are read from it.
    from strainwave.output_guard import make_owned_dir, remove_stale
    remove_stale(tempfile.gettempdir())   # killed solves' folders, when the scratch is the system's
    scratch = make_owned_dir(f"strainwave-solve-{os.getpid()}-")   # under the run's scratch, its owner recorded
    try:
        vtu = Path(args.vtu) if args.vtu else Path(scratch) / f"{args.study}.vtu"
        result = run_study(args.study, params, mesh_size_mm=args.mesh_size_mm, order=args.order,
                           crack_depth_mm=args.crack_depth_mm, vtu=vtu, progress=_progress)
        found = stress_field_of(args.study, result.fields, result.crack_depth_mm)   # a study may seed its own crack
        rated = None if found is None else stress_at_rated(args.study, params, result, found[0], cracked=found[1])
        if args.vtu and rated is not None:   # the file a user opens is at the load this command reports
            write_at_rated(result.fields, rated.load)
        _export_mesh(args, vtu, params, result)
    finally:
        import shutil
        shutil.rmtree(scratch, ignore_errors=True)
    if not args.vtu:
        result = dataclasses.replace(result, fields=())
    text = result.summary() + ("" if rated is None else "\n" + "\n".join(rated.lines()))
    _emit(args, text, lambda: {**result.to_dict(), "stress_at_rated": None if rated is None else rated.to_dict()})
    return 0


def _export_mesh(args, vtu: Path, params, result) -> None:
    """--msh / --inp: the finest mesh the study solved, with its named sets, for gmsh and CalculiX."""
    if not (args.msh or args.inp):
        return
    from strainwave.fea.mesh_export import mesh_of_vtu, write_inp, write_msh
    md = mesh_of_vtu(vtu)
    if args.msh:
        write_msh(md, Path(args.msh))
    if args.inp:
        write_inp(md, Path(args.inp), study=args.study, params=params, load_text=result.load.describe())


def _cmd_validate(args) -> int:
    from strainwave.compare.validate.pipeline import run_validate
    from strainwave.fea.budget import TOOTHED_PARTS, check_budget, check_cad_teeth
    params = _params(args)
    for study in STUDIES:   # every study runs at its default size: the parameters alone may blow the budget
        check_budget(study, params, None, args.quick, flag="--params")
    check_cad_teeth(params, list(TOOTHED_PARTS))   # validate exports every part as designed, teeth on
    outcome = run_validate(params, Path(args.out), quick=args.quick, progress=_progress,
                           step=True if args.step else None, params_file=args.params)
    _emit(args, outcome.summary(), lambda: {
        "passed": outcome.passed, "design": None if outcome.design is None else outcome.design.to_dict(),
        "out_dir": str(outcome.out_dir), "timings_s": outcome.timings_s,
        "checks": [c.to_dict() for c in outcome.checks],
        "results": str(Path(outcome.out_dir) / "results.json")})
    if not outcome.passed:
        return 1
    # the exit status is the validation's; a CI pipeline of a user's own drive also asks for the design's
    return 3 if args.require_design and not outcome.design_passed else 0


def _cmd_compare(args) -> int:
    from strainwave.compare.validate.run_diff import diff_runs, load_run
    if not (args.rtol >= 0 and args.rtol == args.rtol):
        raise InputError("--rtol", args.rtol, "a relative tolerance >= 0")
    diff = diff_runs(load_run(Path(args.run_a), "RUN_A"), load_run(Path(args.run_b), "RUN_B"),
                     names=(args.run_a, args.run_b), rtol=args.rtol)
    _emit(args, diff.summary(), diff.to_dict)
    return 0


def _cmd_diagnose(args) -> int:
    from strainwave.compare.diagnose.pipeline import diagnose_file
    from strainwave.compare.diagnose.recording import TestFlags
    flags = TestFlags(args.kind, args.specimen, args.stiffness, args.rated_torque, args.columns, args.unit)
    diagnosis = diagnose_file(Path(args.recording), params_path=args.params, baseline=args.baseline,
                              plot_out=Path(args.plot) if args.plot else None, flags=flags, progress=_progress)
    _emit(args, diagnosis.summary(), diagnosis.to_dict)
    return 0


def _cmd_catalogue(args) -> int:
    from strainwave.analytic.catalogue_predict import predict_table
    from strainwave.progress import ticking
    if args.accuracy_grade is not None and not 1.0 <= args.accuracy_grade <= 11.0:
        raise InputError("--accuracy-grade", args.accuracy_grade, "an ISO 1328-1:2013 flank tolerance class within 1..11")
    if not 1 <= args.deviation_units <= 256:
        raise InputError("--deviation-units", args.deviation_units, "an integer number of units within 1..256")
    # decision 070-engage48: ideal teeth unless the user states the class the gears are made to
    dev = None if args.accuracy_grade is None else (args.accuracy_grade, args.deviation_units)
    with ticking(f"catalogue {Path(args.table).name}: predicting every row", _progress):
        prediction = predict_table(Path(args.table), deviations=dev)
    _emit(args, prediction.summary(), prediction.to_dict)
    return 0


def _cmd_size_crack(args) -> int:
    from strainwave.compare.diagnose.crack_life import LifeOptions, size_and_life
    if not 1.0 <= args.paris_m <= 10.0:
        raise InputError("--paris-m", args.paris_m, "a Paris exponent within 1..10")
    options = LifeOptions(paris_C=args.paris_c, paris_m=args.paris_m, stiffness_loss=args.stiffness_loss,
                          cycles_per_hour=args.cycles_per_hour,
                          torque_history=Path(args.torque_history) if args.torque_history else None,
                          curves=Path(args.curves) if args.curves else None,
                          cache_dir=Path(args.cache) if args.cache else None)
    report = size_and_life(Path(args.recording), options, params_path=args.params, baseline=args.baseline,
                           plot_out=Path(args.plot) if args.plot else None, progress=_progress)
    _emit(args, report.summary(), report.to_dict)
    return 0


# recordings per class: 1,000 is already hours of fits on two cores; 10**9 would run silently for years
MAX_BENCHMARK_N = 1000


def _benchmark_counter(n: int, families: tuple[int, ...]):
    """k/N of the recordings benchmark-diagnose makes: n of every class, then each CHA row with and without a loop."""
    from strainwave.compare.diagnose.generators.benchmark import CLASSES
    from strainwave.compare.diagnose.generators.cha import cha_rows
    from strainwave.progress import Counter
    total = sum(n * len(CLASSES[f]) + 2 * len(cha_rows()) for f in families)
    return Counter("benchmark-diagnose", total, _progress)


def _cmd_benchmark_diagnose(args) -> int:
    from strainwave.compare.diagnose.generators.benchmark import run_benchmark
    if not 1 <= args.n <= MAX_BENCHMARK_N:
        raise InputError("--n", args.n, f"recordings per class must be an integer from 1 to {MAX_BENCHMARK_N}")
    if not 0 <= args.seed < 2 ** 32:   # numpy's seeds
        raise InputError("--seed", args.seed, "must be an integer from 0 to 2**32 - 1")
    families = (1, 2) if args.family == "both" else (int(args.family),)
    counter = _benchmark_counter(args.n, families)
    report = run_benchmark(n_per_class=args.n, seed=args.seed, out_dir=Path(args.out) if args.out else None,
                           families=families, progress=lambda o: counter.step(f"{o.name}: {o.verdict}"))
    _emit(args, report.summary(), report.to_dict)
    return 0 if report.meets_targets else 1


def _cmd_sweep(args) -> int:
    from strainwave.compare.sweep.pipeline import check_workers, run_sweep
    check_workers(args.workers)
    if args.scheduler:   # a bad address is bad input: refused before the sweep announces any work
        from strainwave.compare.sweep.reach import check_scheduler
        check_scheduler(args.scheduler)
    outcome = run_sweep(args.study, vary=args.vary, params_path=args.params, sample_file=args.samples,
                        scheduler=args.scheduler, workers=args.workers, out_dir=Path(args.out),
                        quick=args.quick, tolerance=args.tolerance, progress=_progress,
                        dashboard=args.dashboard)
    _emit(args, outcome.summary(), lambda: _plain(outcome))
    # Failed points are results (recorded with their error); only a sweep with no good point at all fails.
    return 0 if outcome.n_ok else 1


_FILE_OUTPUTS = (("json", "--json"), ("plot", "--plot"), ("vtu", "--vtu"), ("png", "--png"), ("output", "-o"),
                 ("msh", "--msh"), ("inp", "--inp"))
_INPUTS = (("params", "--params"), ("recording", "recording"), ("samples", "--samples"), ("curves", "--curves"),
           ("torque_history", "--torque-history"))


def _planned_outputs(args) -> list:
    """Every path the command writes: its file flags, the files written beside them, its --out folder."""
    from strainwave.output_guard import Planned

    planned = [Planned(flag, getattr(args, name)) for name, flag in _FILE_OUTPUTS
               if getattr(args, name, None) not in (None, "-")]
    if getattr(args, "vtu", None):   # solve also writes FILE.boundary.vtu next to it
        planned.append(Planned("--vtu", str(Path(args.vtu).with_suffix("")) + ".boundary.vtu", derived=True))
    if getattr(args, "output", None) and getattr(args, "part", None) == "assembly":   # geometry/export.py
        out = Path(args.output)
        planned.append(Planned("-o", str(out.with_name(out.stem + "-ewg-drive.step")), derived=True))
    if getattr(args, "output", None):   # export-step writes each STEP's face index beside it (geometry/face_names)
        from strainwave.geometry.face_names import sidecar_path
        out = Path(args.output)
        steps = [out] + ([out.with_name(out.stem + "-ewg-drive.step")] if getattr(args, "part", None) == "assembly"
                         else [])
        planned += [Planned("-o", str(sidecar_path(step)), derived=True) for step in steps]
    if getattr(args, "out", None) is not None:
        planned.append(Planned("--out", args.out, directory=True, writes=_OUT_INDEX.get(args.command, ())))
    return planned


# the index files each --out command writes (renamed into place last: their presence marks a complete run)
_OUT_INDEX = {"validate": ("results.json", "report.md", "report.html", "report.pdf"),
              "sweep": ("points.json", "summary.md", "sweep.csv", "sweep.parquet"),
              "benchmark-diagnose": ("benchmark_diagnose.json", "benchmark_diagnose.txt")}


def _check_outputs(args) -> None:
    """Every output path the command will write, checked together before any work (a solve must not run
    for minutes and then find that --vtu points into a file): strainwave.output_guard's rules, then that
    each can be written."""
    from strainwave.io_atomic import check_output_path
    from strainwave.output_guard import check_outputs

    inputs = {flag: getattr(args, name, None) for name, flag in _INPUTS}
    planned = _planned_outputs(args)
    check_outputs(planned, inputs, force=getattr(args, "force", False))
    for out in planned:
        check_output_path(out.path, out.flag, directory=out.directory, inputs=tuple(inputs.values()))


def _output_folder(args) -> Path | None:
    """The folder the command writes into (--out, else the parent of its first output file), if any."""
    if getattr(args, "out", None):
        return Path(args.out)
    for name in ("json", "vtu", "output", "plot", "png", "msh", "inp"):
        target = getattr(args, name, None)
        if target not in (None, "-"):
            return Path(target).resolve().parent
    return None


@contextlib.contextmanager
def _scratch_under_outputs(args):
    """Every temporary file of the command (ours, gmsh's BREP hand-over, the children's) goes to a scratch
    folder inside the output folder, removed at the end: nothing lands in /tmp, and a run killed with
    -9 leaves its scratch where the user looks, not in a shared temporary directory.
    Commands without an output folder keep the system's temporary directory."""
    import os
    import shutil
    import tempfile

    folder = _output_folder(args)
    if folder is None:
        yield
        return
    created = [p for p in (folder, *folder.parents) if not p.exists()]   # deepest first
    folder.mkdir(parents=True, exist_ok=True)
    from strainwave.output_guard import folder_lock, make_owned_dir, remove_stale
    with contextlib.ExitStack() as stack:
        stack.callback(_remove_empty, created)   # a refused command leaves no empty output folder behind
        if getattr(args, "out", None):   # one run at a time in an --out folder; a second is refused in one line
            stack.enter_context(folder_lock(folder, wait=False))
        remove_stale(folder)   # scratch and staged files of runs killed with -9 before this one (by their record)
        # multiprocessing keeps its AF_UNIX sockets (fork server) in a temporary folder of its own that it removes
        # itself at exit, after this block has ended; its path must fit the kernel's 108 bytes. So it is made
        # now, in the system's short temporary directory, before TMPDIR points into the scratch: inside the
        # scratch it would be removed under multiprocessing's feet (a traceback at exit) or be too long.
        import multiprocessing.util
        multiprocessing.util.get_temp_dir()
        scratch = str(make_owned_dir(f".strainwave-scratch-{os.getpid()}-", folder))
        stack.callback(shutil.rmtree, scratch, ignore_errors=True)
        saved_env, saved_dir = os.environ.get("TMPDIR"), tempfile.tempdir
        os.environ["TMPDIR"], tempfile.tempdir = scratch, scratch   # children inherit TMPDIR
        try:
            yield
        finally:
            tempfile.tempdir = saved_dir
            if saved_env is None:
                os.environ.pop("TMPDIR", None)
            else:
                os.environ["TMPDIR"] = saved_env


def _remove_empty(created: list[Path]) -> None:
    for made in created:   # deepest first; one not empty holds the command's outputs
        try:
            made.rmdir()
        except OSError:
            break


# ---- parser ------------------------------------------------------------------------------------

def _common(top: bool) -> argparse.ArgumentParser:
    """-q/-v/--debug, accepted before and after the subcommand. On the subcommand they default to
    SUPPRESS, so a flag given before the subcommand is not reset by the subparser."""
    p = argparse.ArgumentParser(add_help=False, allow_abbrev=False)
    unset = {} if top else {"default": argparse.SUPPRESS}
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help="errors only: no progress, no warnings",
                   **({"default": False} if top else unset))
    g.add_argument("-v", "--verbose", action="store_true", help="also debug detail on stderr",
                   **({"default": False} if top else unset))
    p.add_argument("--debug", action="store_true", help="show tracebacks of internal errors",
                   **({"default": False} if top else unset))
    return p


_JSON_HELP = "write the result as JSON to FILE; without FILE (or with -) print it on stdout instead of the text"
_CRACK_HELP = ("crack depth a in mm, from the surface the crack starts at. --part assembly cracks the output shaft "
               "to this depth (the cup and the bearing are drawn as assembled on the cam, uncracked: crack them "
               "with --part); the EWG drive carries none (default: uncracked)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="strainwave", parents=[_common(True)], formatter_class=_Help, allow_abbrev=False,
                     description="Strain wave gear CAD, FEA and seed-paper validation.\n"
                                 "Exit status: 0 fine, 1 a check, mesher or solver failed, 2 bad input, 3 the "
                                 "design fails [n] (validate --require-design only).")
    parser.add_argument("--version", action="version", version=f"strainwave {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser, metavar="COMMAND")
    common = _common(False)

    def add(name, func, help_text, *, material=True):
        p = sub.add_parser(name, help=help_text, description=help_text, parents=[common], formatter_class=_Help,
                           allow_abbrev=False)   # --mesh must not be taken as --mesh-size-mm
        p.add_argument("--params", metavar="FILE.toml",
                       help="partial parameter file; keys it leaves out come from the embedded default "
                            "(strainwave params --print-default)")
        p.add_argument("--json", nargs="?", const="-", default=None, metavar="FILE.json", help=_JSON_HELP)
        p.add_argument("--force", action="store_true",
                       help="replace existing files strainwave did not write (never an input of the run)")
        # material=False: the command never uses the material, so warnings about it would mean nothing
        p.set_defaults(func=func, uses_material=material)
        return p

    for add_command in _COMMANDS:
        add_command(add)
    return parser


def _add_analytic(add) -> None:
    add("analytic", _cmd_analytic, "every closed form of both seeds, published and corrected")


def _add_params(add) -> None:
    p = add("params", _cmd_params, "print the effective parameters (default + --params), or the default file "
            "to start a parameter file from")
    p.add_argument("--print-default", action="store_true",
                   help="print the embedded default parameter file (TOML, with units and sources) and exit")


def _add_export_step(add) -> None:
    p = add("export-step", _cmd_export_step,
            "build a part and write it as STEP (mm, named faces, coloured parts). --part assembly writes "
            "two files: the cup-type gear as a drive (the flexspline cup on the wave generator's cam and ball "
            "bearing, in mesh with the circular spline, and the output shaft) to FILE.step and the EWG drive (flexspline ring and external wave generator) to "
            "FILE-ewg-drive.step", material=False)
    p.add_argument("--part", required=True, choices=PARTS, help="part to build")
    p.add_argument("--crack-depth-mm", type=_positive_float, default=None, metavar="A_MM", help=_CRACK_HELP)
    p.add_argument("--no-teeth", action="store_true", help="smooth shell of the same mid-surface instead of teeth")
    p.add_argument("--png", metavar="FILE.png", help="also render an off-screen preview of what was written")
    p.add_argument("-o", "--output", required=True, metavar="FILE.step", help="STEP file to write")


def _add_solve(add) -> None:
    p = add("solve", _cmd_solve, "mesh and solve one FEA study on three meshes (GCI)")
    p.add_argument("study", choices=STUDIES, help="study to run")
    p.add_argument("--mesh-size-mm", type=_positive_float, default=None, metavar="H_MM",
                   help="element size in mm of the FINEST of the three meshes (the others are 1.4x and "
                        "1.96x coarser); default: the study's own, from the part size")
    p.add_argument("--order", type=int, choices=(1, 2), default=2, help="element order: 1 linear, 2 curved quadratic")
    p.add_argument("--crack-depth-mm", type=_positive_float, default=None, metavar="A_MM",
                   help="crack depth a in mm of the crack in the study's part (registry crack key, e.g. "
                        "output_shaft.crack_depth_mm); ring-compression carries none (default: uncracked)")
    p.add_argument("--vtu", metavar="FILE.vtu",
                   help="write the finest mesh's fields (and FILE.boundary.vtu with the named faces)")
    p.add_argument("--msh", metavar="FILE.msh", help="write the finest mesh as gmsh .msh (2.2), each named face a "
                   "physical group")
    p.add_argument("--inp", metavar="FILE.inp", help="write the finest mesh as a CalculiX/Abaqus deck: a node set "
                   "per named face, the material, and for the torsion studies the clamp, the loads and a static step")


def _add_validate(add) -> None:
    p = add("validate", _cmd_validate, "all studies vs the closed forms: report, images, STEP, VTU")
    p.add_argument("--out", default="reports/validate", metavar="DIR", help="output directory")
    p.add_argument("--quick", action="store_true", help="coarse meshes, one crack depth per component, no STEP")
    p.add_argument("--step", action="store_true", help="export every part as STEP with its preview also with "
                   "--quick (the full run always does)")
    p.add_argument("--require-design", action="store_true",
                   help="exit 3 when the validation passes but the design does not meet [n] at the rated load "
                        "(ewg_drive.permissible_safety); without it the exit status is the validation's alone")


def _add_compare(add) -> None:
    p = add("compare", _cmd_compare, "the checks whose value, verdict or tolerance changed between two validation "
            "runs, side by side", material=False)
    p.add_argument("run_a", metavar="RUN_A", help="validation output folder (or its results.json)")
    p.add_argument("run_b", metavar="RUN_B", help="validation output folder (or its results.json)")
    p.add_argument("--rtol", type=float, default=1e-9, metavar="REL",
                   help="relative difference below which two values count as the same")


def _add_diagnose(add) -> None:
    p = add("diagnose", _cmd_diagnose, "locate, name and model the mismatch between a recording and the model")
    p.add_argument("recording", metavar="RECORDING.csv", help="self-describing recording (docs/recordings.md)")
    p.add_argument("--baseline", choices=("analytic", "fea"), default="analytic",
                   help="model the recording is compared with (fea on specimen gear: the tooth-mesh drive's "
                        "predicted curve, its stiffening and loop)")
    p.add_argument("--plot", metavar="OUT.png", help="also plot the recording, the baseline and the fit")
    p.add_argument("--kind", help="[test] kind, for a recording without a header (or over its header's)")
    p.add_argument("--specimen", help="[test] specimen, for a recording without a header (or over its header's)")
    p.add_argument("--stiffness", metavar="K", help="the specimen's linear stiffness instead of the simulation's, "
                   "e.g. '1.9e3 Nm/rad' (bare number: N*mm/rad, or N/mm for a ring)")
    p.add_argument("--rated-torque", metavar="T", help="the gear's rated torque, e.g. '7.8 Nm' (bare number: N*mm): "
                   "the catalogue's hysteresis loss and lost motion (+/-4 %%) are read at it")
    p.add_argument("--columns", metavar="MAP", help="which columns to read, by 1-based position, with a unit where "
                   "the column row names none: e.g. 'torque=2:Nm,twist=3:deg' (quantities: torque, twist, time, "
                   "input_angle; ring: force, delta_cd, delta_ab, time); the other columns are not read")
    p.add_argument("--unit", metavar="NAME", help="a catalogue drive, e.g. CHA-20A-100: its three-slope curve "
                   "(K1, K2, K3, T1, T2) is the baseline instead of a linear stiffness")


def _add_size_crack(add) -> None:
    p = add("size-crack", _cmd_size_crack, "size the crack a recording's compliance change implies, and its "
            "remaining life (Paris' law)")
    p.add_argument("recording", metavar="RECORDING.csv", help="self-describing recording (docs/recordings.md)")
    p.add_argument("--baseline", choices=("analytic", "fea"), default="analytic",
                   help="model the recording is compared with")
    p.add_argument("--curves", metavar="RESULTS.json", help="a validate results.json: the cup's FEA crack curve")
    p.add_argument("--cache", metavar="DIR", help="keep the FEA curves solved on demand (the shaft's crack, the "
                   "flexspline's breathing ripple, the tooth crack through the mesh) here for the next run")
    p.add_argument("--paris-c", type=_positive_float, default=5.21e-13, metavar="C",
                   help="Paris law da/dN = C dK^m, mm/cycle and N/mm^1.5 (default: %(default)s, BS 7910 steel in air)")
    p.add_argument("--paris-m", type=float, default=3.0, metavar="M", help="Paris exponent")
    p.add_argument("--stiffness-loss", type=_positive_float, default=0.1, metavar="FRACTION",
                   help="stop where the specimen's stiffness has fallen by this fraction")
    p.add_argument("--torque-history", metavar="FILE.csv",
                   help="torque history in N mm, rainflow-counted (default: 0 -> rated torque, constant amplitude)")
    p.add_argument("--cycles-per-hour", type=_positive_float, default=None, metavar="N",
                   help="load cycles per hour, to give the life in hours")
    p.add_argument("--plot", metavar="OUT.png", help="plot stiffness against load cycles")


def _add_benchmark_diagnose(add) -> None:
    p = add("benchmark-diagnose", _cmd_benchmark_diagnose, "score diagnose blind on generated recordings")
    p.add_argument("--n", type=int, default=10, metavar="N", help="recordings per class and family (>= 1)")
    p.add_argument("--family", choices=("1", "2", "both"), default="both",
                   help="generator family: 1 (hifi_*), 2 (independent physics, coloured noise, out of catalogue)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed of the generated recordings")
    p.add_argument("--out", metavar="DIR", help="also write benchmark_diagnose.json/.txt here")


def _add_sweep(add) -> None:
    p = add("sweep", _cmd_sweep, "parameter sweep of one study on Dask")
    p.add_argument("study", choices=STUDIES, help="study solved at every point")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=START:STOP:N|v1,v2",
                   help="dotted parameter key (units in its name) and its values; repeat for a grid")
    p.add_argument("--samples", metavar="FILE.csv", help="CSV of parameter rows (dotted keys as columns)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="existing Dask scheduler, e.g. tcp://host:8786 "
                   "(default: a local cluster)")
    p.add_argument("--workers", type=int, default=None, metavar="N", help="local Dask workers (default: one per core)")
    p.add_argument("--out", default="reports/sweep", metavar="DIR", help="output directory")
    p.add_argument("--quick", action="store_true", help="coarse meshes")
    p.add_argument("--tolerance", type=float, default=0.05, metavar="REL",
                   help="relative departure from the closed form (dimensionless, 0.05 = 5 %%) named in the summary")
    p.add_argument("--dashboard", action="store_true", help="serve the local cluster's Dask dashboard on 127.0.0.1 "
                   "(this machine only, no login; its address is printed). Without it no HTTP server listens")


# the subcommands in the order --help lists them; each adds its parser through ``add`` (build_parser)
def _add_catalogue(add) -> None:
    p = add("catalogue", _cmd_catalogue,
            "predict every row of a stiffness table (columns size, ratio, T1_Nm, T2_Nm, K1_e3, K2_e3, K3_e3) from the "
            "tooth-mesh model under one set of design rules; print predicted/catalogue and the log-slopes",
            material=False)
    p.add_argument("table", metavar="TABLE.csv", help="the table (blank cells skipped; ratio '>50' means 100; optional "
                   "columns hysteresis_arcmin, lost_motion_arcmin (the row's bounds, else the CHA's) and "
                   "rated_torque_Nm (the lost-motion test's 4 %%, else the rules'))")
    p.add_argument("--accuracy-grade", type=float, default=None, metavar="A",
                   help="the teeth's ISO 1328-1:2013 flank tolerance class (1..11): each row becomes the mean of "
                        "--deviation-units units with pitch and profile deviations drawn to it; without it the teeth are ideal")
    p.add_argument("--deviation-units", type=int, default=8, metavar="N",
                   help="units (seeds 0..N-1) averaged per row with --accuracy-grade (default: %(default)s)")


_COMMANDS = (_add_analytic, _add_params, _add_export_step, _add_solve, _add_validate, _add_compare, _add_diagnose,
             _add_size_crack, _add_benchmark_diagnose, _add_sweep, _add_catalogue)


class _StderrFormat(logging.Formatter):
    """Progress as plain lines; warnings and worse prefixed with their level, as the CLI always printed."""

    def format(self, record: logging.LogRecord) -> str:
        msg = record.getMessage()
        msg = printable(msg)   # a file's control codes never reach the terminal raw
        return msg if record.levelno < logging.WARNING else f"{record.levelname.lower()}: {msg}"


class _HeldWarnings(logging.StreamHandler):
    """Warnings are held until the command starts working (its first progress line) or ends well, and
    dropped when the input is refused: a refusal is its one error line, not a warning about the
    material printed before it."""

    def __init__(self, stream):
        super().__init__(stream)
        self.held: list[logging.LogRecord] = []
        self.working = False

    def emit(self, record: logging.LogRecord) -> None:
        if not self.working and record.levelno == logging.WARNING:
            self.held.append(record)
            return
        if record.levelno < logging.WARNING:
            self.show_held()
        super().emit(record)

    def show_held(self) -> None:
        self.working = True
        held, self.held = self.held, []
        for record in held:
            super().emit(record)

    def drop_held(self) -> None:
        self.held = []


def _verbosity(argv: list[str]) -> tuple[int, bool]:
    """(log level, debug) from the raw arguments, so they hold even when parsing fails."""
    quiet = any(a in ("-q", "--quiet") for a in argv)
    verbose = any(a in ("-v", "--verbose") for a in argv)
    level = logging.ERROR if quiet else logging.DEBUG if verbose else logging.INFO
    return level, "--debug" in argv


def _no_stray_writes() -> None:
    """Environment defaults that keep libraries from writing outside the outputs:
    pypardiso looks for MKL with ctypes.util.find_library, which runs ldconfig and gcc on temporary
    files unless told where libmkl_rt is (the MKL wheel installs it under sys.prefix/lib); Mesa keeps a
    shader cache in ~/.cache unless disabled. Only defaults: a user's own setting wins."""
    import os

    mkl = sorted(Path(sys.prefix, "lib").glob("libmkl_rt.so*"))
    if mkl:
        os.environ.setdefault("PYPARDISO_MKL_RT", str(mkl[0]))
    os.environ.setdefault("MESA_SHADER_CACHE_DISABLE", "true")


def _json_takes_no_positional(argv: list[str]) -> list[str]:
    """``--json WORD`` (no extension, no folder) is ``--json`` (stdout) followed by the positional WORD: an
    option never takes the study name as its file (``solve --json shaft-torsion``)."""
    out = []
    for i, arg in enumerate(argv):
        if arg == "--" or (i and argv[i - 1] == "--"):
            return out + argv[i:]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        # a word with no extension or folder (a study name) is a positional; a path is --json's, checked later
        if arg == "--json" and nxt is not None and not nxt.startswith("-") and not any(c in nxt for c in "./\\"):
            out.append("--json=-")
            continue
        out.append(arg)
    return out


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so it unwinds (scratch, staged outputs, Dask cluster) as Ctrl-C does."""


_TERMINATED: list[int] = []   # SIGTERM arrived: an error it caused mid-import ("initialization failed") is it


def _raise_terminated(signum, frame):
    _TERMINATED.append(signum)
    raise Terminated


def _stop_children() -> None:
    """After SIGTERM has unwound: SIGKILL whatever this process started that is still running (a fork server
    still importing, a worker its cluster never got to close); a terminated run leaves no process behind."""
    import signal
    from multiprocessing import resource_tracker

    from strainwave.compare.validate.isolated import descendants
    # multiprocessing's resource tracker leaves by itself once this process has gone; killed, it would be
    # started again by the exit's own clean-up and print its "leaked" warnings
    tracker = getattr(resource_tracker._resource_tracker, "_pid", None)
    for pid in descendants(os.getpid()):
        if pid != tracker:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


@contextlib.contextmanager
def _sigterm_unwinds():
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _TERMINATED.clear()
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _run(args) -> int:
    """The command inside its scratch folder, its --out folder marked as strainwave's, its files staged."""
    from strainwave.output_guard import marked_folder, staged_outputs, staged_run
    out = getattr(args, "out", None)
    force = getattr(args, "force", False)
    with _scratch_under_outputs(args), marked_folder(Path(out)) if out is not None else contextlib.nullcontext():
        # an --out run is staged whole and renamed into place at the end (output_guard.staged_run)
        whole = staged_run(args, force=force, index=_OUT_INDEX.get(args.command, ())) if out is not None \
            else contextlib.nullcontext()
        with whole, staged_outputs(args, tuple(name for name, _ in _FILE_OUTPUTS)):
            return args.func(args)


def _terminated() -> int:
    _stop_children()
    print("error: terminated", file=sys.stderr)
    return 143


def _unexpected(exc: Exception, args, debug: bool) -> int:
    """One line for an exception no stage named: a termination SIGTERM caused mid-import, a full disk (exit
    1 naming where), else an internal error."""
    if _TERMINATED:
        return _terminated()
    full = _disk_full(exc)
    if full is not None:   # a genuine failure, not bad input
        from strainwave.output_guard import target_of
        where = full.filename or (args is not None and _output_folder(args)) or "the output folder"
        print(f"error: disk full: {printable(target_of(str(where)))}", file=sys.stderr)
        return 1
    print(f"error: internal error ({type(exc).__name__}: {printable(str(exc))}); rerun with --debug", file=sys.stderr)
    if debug:
        traceback.print_exc()
    return 1


def _disk_full(exc: BaseException) -> OSError | None:
    import errno
    while exc is not None:
        if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, getattr(errno, "EDQUOT", -1)):
            return exc
        exc = exc.__cause__ or exc.__context__
    return None


def main(argv: list[str] | None = None) -> int:
    argv = _json_takes_no_positional(sys.argv[1:] if argv is None else list(argv))
    _no_stray_writes()
    level, debug = _verbosity(argv)
    logger = logging.getLogger(LOG)
    handler = _HeldWarnings(sys.stderr)
    handler.setFormatter(_StderrFormat())
    saved_level, saved_propagate = logger.level, logger.propagate
    logger.addHandler(handler)
    logger.setLevel(level)
    logger.propagate = False
    try:
        shown: set[str] = set()

        def show_once(msg, *rest, **kw):   # one run may load the parameters several times
            text = " ".join(str(msg).split())   # one line: scipy's IntegrationWarning spans three
            if text not in shown:
                shown.add(text)
                logger.warning(text)

        with warnings.catch_warnings(), _sigterm_unwinds():
            warnings.simplefilter("default", RangeWarning)  # each distinct warning once
            warnings.showwarning = show_once
            args = None
            try:
                args = build_parser().parse_args(argv)
                if not args.uses_material:
                    warnings.simplefilter("ignore", MaterialWarning)
                logger.debug("strainwave %s: %s", _version(), " ".join(argv))
                _check_outputs(args)
                status = _run(args)
                handler.show_held()
                return status
            except StrainwaveError as exc:
                if _TERMINATED:   # a stage failure SIGTERM caused (a child it stopped): still a termination
                    return _terminated()
                # a refused input is its one line; a stage failure keeps the warnings that may explain it
                if isinstance(exc, InputError):
                    handler.drop_held()
                else:
                    handler.show_held()
                print(f"error: {printable(str(exc))}", file=sys.stderr)
                if debug:
                    traceback.print_exc()
                return exc.exit_status
            except SystemExit as exc:   # --help / --version: argparse prints and exits 0
                return exc.code if isinstance(exc.code, int) else 0
            except Terminated:
                return _terminated()
            except KeyboardInterrupt:
                print("error: interrupted", file=sys.stderr)
                return 130
            except BrokenPipeError:   # the reader (e.g. `| head`) went away: stop quietly, as shell tools do
                import os
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
                return 141
            except Exception as exc:  # noqa: BLE001 - last line of defence: one line, no traceback
                return _unexpected(exc, args, debug)
    finally:
        logger.removeHandler(handler)
        logger.setLevel(saved_level)
        logger.propagate = saved_propagate


if __name__ == "__main__":
    sys.exit(main())
