"""The points of a sweep: ``--vary`` axes, their full grid, and CSV sample files of parameter rows.

Only the *syntax* and the *type* of each value are checked here, against the parameter schema
(``Params.to_dict()`` of the base parameters). Whether a point is physically possible (a crack
deeper than the wall, a bore wider than the shaft) needs the merged parameters: the driver checks
every point with the parameter schema before any worker starts and refuses the grid (exit 2) naming
the impossible points (``pipeline.refuse_impossible``).
"""
from __future__ import annotations

import csv
import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.errors import InputError
from strainwave.params import REMOVED_KEYS, read_limited, schema_types

VARY_FORMS = "KEY=START:STOP:N (N >= 1 evenly spaced values) or KEY=v1,v2,..."
# A point is at least one FEA study: 10,000 are a day of two cores (docs/decisions/021-sweep-grid-limit.md).
MAX_POINTS = 10_000
MAX_SAMPLES_BYTES = 200 * MAX_POINTS   # a sample row is a few numbers; 2 MB holds 10,000 generous rows


@dataclass(frozen=True)
class VaryAxis:
    """One varied dotted key and the values it takes, in order."""

    key: str
    values: tuple


def schema_kinds(base: dict) -> dict[str, type]:
    """Dotted key -> the type the parameter schema declares for each key of ``base`` (float, int, bool, str,
    list), not the type of the literal in ``base`` (the default file writes ``gear_ratio = 100``, a float key)."""
    declared = schema_types()
    return {f"{section}.{key}": declared.get(f"{section}.{key}", type(value))
            for section, table in base.items() for key, value in table.items()}


def _check_key(key: str, kinds: dict[str, type], where: str) -> type:
    if key in REMOVED_KEYS:
        raise InputError(where, key, REMOVED_KEYS[key])
    if key not in kinds:
        sections = sorted({k.partition(".")[0] for k in kinds})
        section = key.partition(".")[0]
        allowed = (f"unknown key; {section} has {', '.join(k for k in kinds if k.startswith(section + '.'))}"
                   if section in sections else f"unknown key; sections are {', '.join(sections)}")
        raise InputError(where, key, allowed)
    kind = kinds[key]
    if kind is list:
        raise InputError(where, key, "a list-valued key cannot be swept; vary a scalar key")
    return kind


def coerce_value(key: str, text: str, kind: type, where: str) -> object:
    """Convert one textual value to the schema's type of ``key``; refuse it in one line if impossible."""
    text = text.strip()
    if kind is bool:
        if text.lower() not in ("true", "false"):
            raise InputError(where, text, f"{key} takes true or false")
        return text.lower() == "true"
    if kind is str:
        if not text:
            raise InputError(where, text, f"{key} takes a non-empty word")
        return text
    try:
        # float() also reads 1_00 and non-ASCII digits (Arabic-Indic, full-width): no CSV writer means those
        number = float(text) if text.isascii() and "_" not in text else float("")
    except ValueError:
        raise InputError(where, text, f"{key} takes a number (ASCII digits)") from None
    if not math.isfinite(number):
        raise InputError(where, text, f"{key} takes a finite number")
    if kind is int:
        if not number.is_integer():
            raise InputError(where, text, f"{key} takes an integer")
        return int(number)
    return number


def _linspace(key: str, spec: str, kind: type, where: str) -> tuple:
    parts = spec.split(":")
    if len(parts) != 3:
        raise InputError(where, spec, f"expected {VARY_FORMS}")
    if kind not in (int, float):
        raise InputError(where, spec, f"{key} is not numeric; list its values as v1,v2")
    start = coerce_value(key, parts[0], float, where)
    stop = coerce_value(key, parts[1], float, where)
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError(where, spec, "N after the second ':' must be an integer >= 1") from None
    if n < 1:
        raise InputError(where, spec, "N after the second ':' must be an integer >= 1")
    if n > MAX_POINTS:
        raise InputError(where, spec, f"N after the second ':' must be <= {MAX_POINTS} (points of one sweep)")
    if n > 1 and start == stop:
        raise InputError(where, spec, "START equals STOP with N > 1: every point would be the same")
    values = np.linspace(start, stop, n)
    if kind is int:
        if not np.allclose(values, np.round(values)):
            raise InputError(where, spec, f"{key} is an integer; choose START, STOP, N giving whole steps")
        return tuple(int(round(v)) for v in values)
    return tuple(float(v) for v in values)


def parse_vary(text: str, base: dict) -> VaryAxis:
    """Parse ``KEY=START:STOP:N`` or ``KEY=v1,v2,...`` against the schema of ``base`` (a ``Params.to_dict()``)."""
    where = "--vary"
    key, sep, spec = text.partition("=")
    key, spec = key.strip(), spec.strip()
    if not sep or not key or not spec:
        raise InputError(where, text, f"expected {VARY_FORMS}")
    kind = _check_key(key, schema_kinds(base), where)
    if ":" in spec:
        values = _linspace(key, spec, kind, f"--vary {key}")
    else:
        items = spec.split(",")
        if len(items) > MAX_POINTS:
            raise InputError(f"--vary {key}", f"{len(items)} values", f"at most {MAX_POINTS} points per sweep")
        if any(not item.strip() for item in items):
            raise InputError(f"--vary {key}", spec, f"empty value in the list; expected {VARY_FORMS}")
        values = tuple(coerce_value(key, item, kind, f"--vary {key}") for item in items)
    if len(set(values)) != len(values):
        raise InputError(f"--vary {key}", spec, "values repeat; each point must differ")
    return VaryAxis(key, values)


def full_grid(axes: list[VaryAxis]) -> list[dict]:
    """Every combination of the axes' values, the first axis varying slowest."""
    keys = [axis.key for axis in axes]
    if len(set(keys)) != len(keys):
        raise InputError("--vary", ", ".join(keys), "each key may be varied only once")
    size = math.prod(len(axis.values) for axis in axes)
    if size > MAX_POINTS:
        raise InputError("--vary", " x ".join(str(len(axis.values)) for axis in axes) + f" = {size} points",
                         f"a sweep may have at most {MAX_POINTS} points")
    return [dict(zip(keys, combo)) for combo in itertools.product(*(axis.values for axis in axes))]


def read_samples(path: Path, base: dict) -> list[dict]:
    """Rows of a CSV whose header names dotted keys (Latin hypercube or measured designs)."""
    path = Path(path)
    raw = read_limited(path, MAX_SAMPLES_BYTES, "--samples")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError("--samples", str(path), "must be a UTF-8 CSV text file") from None
    try:
        rows = list(csv.reader(line for line in text.splitlines() if line.strip() and not line.startswith("#")))
    except csv.Error as exc:   # e.g. a cell beyond csv's field-size limit
        raise InputError("--samples", str(path), f"not a CSV file ({exc})") from None
    if len(rows) < 2:
        raise InputError("--samples", str(path), "needs a header of dotted keys and at least one row")
    header = [cell.strip() for cell in rows[0]]
    kinds = schema_kinds(base)
    for key in header:
        _check_key(key, kinds, f"{path}:1")
    if len(set(header)) != len(header):
        raise InputError(f"{path}:1", ",".join(header), "a column appears twice")
    points = []
    for number, row in enumerate(rows[1:], start=2):
        where = f"{path}:{number}"
        if len(row) != len(header):
            raise InputError(where, ",".join(row), f"has {len(row)} cells, the header has {len(header)}")
        points.append({key: coerce_value(key, cell, kinds[key], where) for key, cell in zip(header, row)})
    return points


def build_points(vary: list[str], sample_file: Path | None, base: dict) -> tuple[list[str], list[dict]]:
    """The varied keys and the list of points (dotted key -> value) of one sweep.

    With both ``--vary`` axes and a sample file, every sample row is combined with every grid point.
    """
    axes = [parse_vary(text, base) for text in vary]
    grid = full_grid(axes) if axes else []
    samples = read_samples(sample_file, base) if sample_file is not None else []
    if len(samples) * max(1, len(grid)) > MAX_POINTS:
        raise InputError("--samples", f"{len(samples)} rows x {max(1, len(grid))} grid points",
                         f"a sweep may have at most {MAX_POINTS} points")
    if not grid and not samples:
        raise InputError("--vary", "", f"give at least one --vary {VARY_FORMS} or --samples FILE.csv")
    if grid and samples:
        overlap = set(samples[0]) & {axis.key for axis in axes}
        if overlap:
            raise InputError("--samples", ", ".join(sorted(overlap)), "a key is both in --vary and the sample file")
        points = [{**row, **point} for row in samples for point in grid]
    else:
        points = grid or samples
    keys = list(points[0])
    return keys, points
