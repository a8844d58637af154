"""What a validation run ran: the gear's name (its parameter file, or the embedded default), the command line,
and every parameter that differs from the embedded default. The reports' titles and parameter echo read it.
"""
from __future__ import annotations

import shlex
import sys
from pathlib import Path

__all__ = ["DEFAULT_GEAR", "params_diff", "run_record", "report_title", "PARAM_COLUMNS", "param_rows", "run_lines"]

DEFAULT_GEAR = "embedded default gear (seed examples)"
PARAM_COLUMNS = ("parameter", "this run", "embedded default")


def params_diff(values: dict, default: dict) -> list[dict]:
    """[{key, value, default}] of every dotted key whose value differs from the default's, in the file's order."""
    out = []
    for section, table in values.items():
        for key, value in table.items():
            base = default.get(section, {}).get(key)
            if value != base:
                out.append({"key": f"{section}.{key}", "value": value, "default": base})
    return out


def _command_line(argv: list[str] | None) -> str:
    argv = list(sys.argv if argv is None else argv)
    if argv and argv[0].endswith(("strainwave", "__main__.py", "strainwave/cli.py")):
        argv[0] = "strainwave"   # the command as a user types it, not the venv's absolute path
    return shlex.join(argv)


def run_record(params, params_file: str | Path | None = None, argv: list[str] | None = None) -> dict:
    """The run's identity for results.json's metadata.run: gear name, parameter file, command line, diff."""
    from strainwave.params import load_params
    default = load_params().to_dict()
    gear = DEFAULT_GEAR if params_file is None else Path(params_file).stem
    return {"gear": gear, "params_file": None if params_file is None else str(params_file),
            "command_line": _command_line(argv), "changed_from_default": params_diff(params.to_dict(), default)}


def report_title(doc: dict) -> str:
    """'strainwave validation report: <gear>' (a run without a run record keeps the plain title)."""
    run = doc.get("metadata", {}).get("run")
    return "strainwave validation report" + (f": {run['gear']}" if run else "")


def _cell(value) -> str:
    return "-" if value is None else f"{value:g}" if isinstance(value, float) else str(value)


def param_rows(doc: dict) -> list[tuple[str, str, str]]:
    """(key, this run, default) of every parameter the run changed from the embedded default."""
    run = doc.get("metadata", {}).get("run") or {}
    return [(d["key"], _cell(d["value"]), _cell(d["default"])) for d in run.get("changed_from_default", ())]


def run_lines(doc: dict) -> list[str]:
    """The run's identity as sentences: parameter file, command line, how many keys differ from the default."""
    run = doc.get("metadata", {}).get("run")
    if not run:
        return []
    changed = len(run["changed_from_default"])
    source = f" (parameter file {run['params_file']})" if run["params_file"] else ""
    diff = (f"{changed} parameter(s) differ from the embedded default, listed below" if changed
            else "every parameter is the embedded default's")
    return [f"Gear: {run['gear']}{source}; {diff}", f"Command line: {run['command_line']}"]
