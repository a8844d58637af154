"""Parse a self-describing recording: a TOML header in ``#`` lines, then CSV in acquisition order.

Format (docs/recordings.md)::

    # [test]
    # kind = "torsion"              # torsion | ring_compression
    # specimen = "output_shaft"     # torsion: output_shaft | flexspline_cup | gear; ring_compression: ewg_ring
    # baseline_uncertainty = 0.02   # relative uncertainty of the simulated linear stiffness
    # [params.output_shaft]         # optional overrides of the parameter schema
    # outer_diameter_mm = 50.0
    torque_Nmm,twist_rad
    0.0,1.2e-7

Every defect raises ``InputError`` whose key is ``<file>:<line>`` so the user can go straight to it.
Rig and spreadsheet exports are accepted as they are written: their layout (metadata before the column row, the
separator and the decimal mark) is ``table.py``'s, their column names and units ``units.py``'s.
"""
from __future__ import annotations

import csv
import dataclasses
import enum
import math
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from strainwave.errors import InputError, RangeWarning
from strainwave.params import load_params, read_limited
from strainwave.compare.diagnose import table
from strainwave.compare.diagnose.units import column_names, flag_value, read_columns

MIN_ROWS = 20
# Size limits, so a mistaken path (/dev/zero, a day of raw DAQ data) is refused before it takes the
# machine's memory: diagnose fits on at most 2,500 strided rows, and 200,000 rows are over an hour of
# a 50 Hz test; a data row is a few numbers, well under 150 bytes (docs/decisions/019-diagnose-speed.md).
MAX_ROWS = 200_000
MAX_BYTES = 150 * MAX_ROWS
# Magnitudes a rig can record, per column. Beyond them the fits' sums of squares overflow to inf and the
# JSON would carry Infinity; below the response floor (1e-12 rad or mm, orders under any sensor's
# resolution) the stiffness would overflow. A response column of exact zeros is allowed (a rigid fixture).
MAX_ABS = {"torque_Nmm": 1e10, "force_N": 1e8, "twist_rad": 10.0, "delta_cd_mm": 1e3, "delta_ab_mm": 1e3,
           "input_angle_rad": 1e9, "time_s": 1e9}
MIN_LOAD_FULL_SCALE = 1e-6      # N*mm or N: a load range below it is float noise, not a test
MIN_RESPONSE_FULL_SCALE = 1e-12
BASELINE_UNCERTAINTY_RANGE = (1e-6, 1.0)   # relative; below 1e-6 no simulation is that certain
BASELINE_STIFFNESS_RANGE = (1e-6, 1e15)    # N*mm/rad or N/mm: a rubber coupling to a solid steel block


class RecordingKind(enum.Enum):
    TORSION = "torsion"
    RING_COMPRESSION = "ring_compression"


SPECIMENS = {RecordingKind.TORSION: ("output_shaft", "flexspline_cup", "gear"),
             RecordingKind.RING_COMPRESSION: ("ewg_ring",)}
# (load column, response column), optional columns
COLUMNS = {RecordingKind.TORSION: (("torque_Nmm", "twist_rad"), ("time_s", "input_angle_rad")),
           RecordingKind.RING_COMPRESSION: (("force_N", "delta_cd_mm"), ("delta_ab_mm", "time_s"))}
TEST_KEYS = {"kind", "specimen", "baseline_uncertainty", "baseline_stiffness_Nmm_per_rad",
             "baseline_stiffness_N_per_mm", "description", "rated_torque_Nmm", "unit"}
# a catalogue unit's table gives average values: the whole gear's uncertainty (docs/recordings.md) unless stated
UNIT_UNCERTAINTY = 0.3
TOP_TABLES = {"test", "params", "meta"}


@dataclass(frozen=True)
class Recording:
    """One parsed recording. ``load`` drives the test (torque or force), ``response`` is measured."""

    source: str
    kind: RecordingKind
    specimen: str
    load: np.ndarray
    response: np.ndarray
    time_s: np.ndarray | None
    load_name: str
    response_name: str
    baseline_uncertainty: float = 0.02
    baseline_stiffness: float | None = None     # N*mm/rad (torsion) or N/mm (ring), replaces the simulation
    param_overrides: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)   # optional channels, e.g. delta_ab_mm
    description: str = ""
    rated_torque: float | None = None           # N*mm (torsion): the catalogue's loss and lost motion are read at it
    units: dict = field(default_factory=dict)   # canonical column -> the unit the file wrote it in ("" canonical)
    unit: str | None = None                     # a catalogue unit (CHA-20A-100): its curve is the baseline

    @property
    def n(self) -> int:
        return len(self.load)

    @property
    def load_unit(self) -> str:
        return "N*mm" if self.kind is RecordingKind.TORSION else "N"

    @property
    def response_unit(self) -> str:
        return "rad" if self.kind is RecordingKind.TORSION else "mm"


@dataclass(frozen=True)
class TestFlags:
    """[test] keys given on the command line (``--kind --specimen --stiffness --rated-torque``): they describe a
    recording without a header, and override the header's keys where it has one."""

    kind: str | None = None
    specimen: str | None = None
    stiffness: str | None = None       # a number with an optional unit (units.flag_value)
    rated_torque: str | None = None
    columns: str | None = None         # ``torque=2,twist=3:deg``: columns read by position (units.read_columns)
    unit: str | None = None            # a catalogue unit, e.g. CHA-20A-100 (drive_curve.unit_curve)

    def __bool__(self) -> bool:
        return any(v is not None for v in dataclasses.astuple(self))

    def table(self, header_kind: object) -> dict:
        """The flags as [test] entries in canonical units; a bad value: InputError naming the flag."""
        kinds = [k.value for k in RecordingKind]
        if self.kind is not None and self.kind not in kinds:
            raise InputError("--kind", self.kind, f"one of {kinds}")
        kind_name = self.kind if self.kind is not None else header_kind
        if kind_name not in kinds:
            raise InputError("--kind", "not set", f"a recording without a valid [test] kind needs --kind, one of {kinds}")
        kind = RecordingKind(kind_name)
        out = {} if self.kind is None else {"kind": self.kind}
        if self.specimen is not None:
            if self.specimen not in SPECIMENS[kind]:
                raise InputError("--specimen", self.specimen, f"for {kind.value} one of {list(SPECIMENS[kind])}")
            out["specimen"] = self.specimen
        if self.stiffness is not None:
            torsion = kind is RecordingKind.TORSION
            key = "baseline_stiffness_Nmm_per_rad" if torsion else "baseline_stiffness_N_per_mm"
            out[key] = flag_value("--stiffness", self.stiffness, "torsional_stiffness" if torsion else "ring_stiffness")
        if self.rated_torque is not None:
            if kind is not RecordingKind.TORSION:
                raise InputError("--rated-torque", self.rated_torque, "only for a torsion recording")
            out["rated_torque_Nmm"] = flag_value("--rated-torque", self.rated_torque, "torque")
        if self.unit is not None:
            out["unit"] = _unit_value("--unit", self.unit, kind)
        return out


def parse_recording(path: Path | str, flags: TestFlags | None = None) -> Recording:
    """Read and parse one recording file; any defect is an ``InputError`` naming the file and line."""
    path = Path(path)
    return parse_bytes(read_limited(path, MAX_BYTES, str(path)), path.name, flags)


def parse_bytes(raw: bytes, name: str = "recording.csv", flags: TestFlags | None = None) -> Recording:
    return parse_text(decode(raw, name), name, flags)


def decode(raw: bytes, name: str) -> str:
    """UTF-8 (with or without BOM), UTF-16 with its BOM (a spreadsheet's "Unicode text"), else Windows-1252, the
    Latin-1 superset a Western European Windows rig PC writes (``[°]``, ``[µm]``)."""
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            raise InputError(f"{name}:1", "undecodable bytes", "a UTF-16 file with a byte-order mark must be UTF-16") \
                from None
    if b"\x00" in raw[:4096]:
        raise InputError(f"{name}:1", "binary data", "a recording must be a text file (CSV with # header)")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    try:
        return raw.decode("cp1252")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise InputError(f"{name}:{line}", "undecodable bytes",
                         "a recording must be a text file in UTF-8 or Windows-1252 (Latin-1)") from None


def parse_text(text: str, name: str = "recording.csv", flags: TestFlags | None = None) -> Recording:
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    header_lines, body_start = _hash_block(lines)
    header = _with_flags(_parse_header(header_lines, name, headless_ok=bool(flags)), flags)
    kind, specimen, test = _parse_test(header, header_lines or [(1, "")], name)
    _check_overrides(header.get("params", {}), header_lines, name)
    (load_col, resp_col), _ = COLUMNS[kind]
    if body_start >= len(lines):
        raise InputError(f"{name}:{len(lines)}", "end of file", f"expected a CSV header row '{load_col},{resp_col}'")
    layout, columns = _table(lines, body_start, kind, name, flags.columns if flags else None)
    data = _parse_rows(lines, layout, columns, name)
    if data.shape[0] < MIN_ROWS:
        raise InputError(f"{name}:{len(lines)}", f"{data.shape[0]} data rows", f"need at least {MIN_ROWS} rows")
    col = {c: data[:, j] for j, (_, c, _, _) in enumerate(columns)}
    first = layout.data_start - 1       # _row_line counts data rows after this line
    hline = layout.data_start
    for c, values in col.items():
        if np.any(np.abs(values) > MAX_ABS[c]):
            bad = int(np.argmax(np.abs(values) > MAX_ABS[c]))
            raise InputError(f"{name}:{_row_line(lines, first, bad)}", float(values[bad]),
                             f"|{c}| must be <= {MAX_ABS[c]:g} (beyond any rig; the fit would overflow)")
    load, resp = col[load_col], col[resp_col]
    if np.max(np.abs(load)) < MIN_LOAD_FULL_SCALE:
        raise InputError(f"{name}:{hline + 1}", float(np.max(np.abs(load))),
                         f"the {load_col} full scale must be >= {MIN_LOAD_FULL_SCALE:g} (float noise, not a test)")
    if 0.0 < np.max(np.abs(resp)) < MIN_RESPONSE_FULL_SCALE:
        raise InputError(f"{name}:{hline + 1}", float(np.max(np.abs(resp))),
                         f"the {resp_col} full scale must be 0 or >= {MIN_RESPONSE_FULL_SCALE:g} "
                         "(below any sensor's resolution)")
    if np.ptp(load) <= 0:
        raise InputError(f"{name}:{hline + 1}", load_col, "the load column is constant; nothing to compare")
    if kind is RecordingKind.RING_COMPRESSION and np.any(load < -0.01 * np.max(np.abs(load))):
        bad = int(np.argmax(load < -0.01 * np.max(np.abs(load))))
        raise InputError(f"{name}:{_row_line(lines, first, bad)}", float(load[bad]),
                         "force_N is a compression force and must be >= 0 (beyond 1 % of full scale noise)")
    time_s = col.get("time_s")
    if time_s is not None and np.any(np.diff(time_s) < 0):
        bad = int(np.argmax(np.diff(time_s) < 0)) + 1
        raise InputError(f"{name}:{_row_line(lines, first, bad)}", float(time_s[bad]),
                         "time_s must not decrease (rows are in acquisition order)")
    return Recording(source=name, kind=kind, specimen=specimen, load=load, response=resp, time_s=time_s,
                     load_name=load_col, response_name=resp_col,
                     baseline_uncertainty=test["baseline_uncertainty"],
                     baseline_stiffness=test.get("baseline_stiffness"),
                     param_overrides=header.get("params", {}),
                     extra={c: v for c, v in col.items() if c not in (load_col, resp_col, "time_s")},
                     description=str(test.get("description", "")), rated_torque=test.get("rated_torque"),
                     units={c: unit for _, c, _, unit in columns}, unit=test.get("unit"))


def _hash_block(lines: list[str]) -> tuple[list[tuple[int, str]], int]:
    """The leading ``#`` lines as (file line, text) and the index of the first other non-blank line. Lines of a
    block without a TOML table (``# exported by RigSoft``) are comments, not a header."""
    block, body_start = [], len(lines)
    for i, line in enumerate(lines):
        if line.startswith("#"):
            # spreadsheets pad every row with commas, the header rows included
            text = line.rstrip().rstrip(",;").rstrip()
            block.append((i + 1, text[2:] if text.startswith("# ") else text[1:]))
        elif line.strip() != "":
            body_start = i
            break
    is_toml = any(text.strip().startswith("[") for _, text in block)
    return (block if is_toml else []), body_start


def _table(lines: list[str], start: int, kind: RecordingKind, name: str, mapping: str | None):
    """The file's layout (table.py) and the columns read from it (units.read_columns)."""
    (load_col, resp_col), optional = COLUMNS[kind]

    def names_both(cells: list[str]) -> bool:
        try:
            found = {c for _, c, _, _ in read_columns(cells, kind.value, "", None)}
        except InputError:
            return False
        return {load_col, resp_col} <= found

    layout = table.find_layout(lines, start, names_both)
    row = layout.column_row
    where = f"{name}:{(row if row is not None else layout.data_start) + 1}"
    if row is None and mapping is None:
        raise InputError(where, lines[layout.data_start].strip()[:60],
                         f"expected a column row naming {load_col} and {resp_col} before the data, or --columns")
    try:
        cells = table.split_header(lines[row], layout.delimiter) if row is not None else []
    except csv.Error as exc:   # e.g. a cell beyond csv's field-size limit
        raise InputError(where, lines[row][:60], f"not a CSV row ({exc})") from None
    columns = read_columns(cells, kind.value, where, mapping)
    found = [c for _, c, _, _ in columns]
    for col in (load_col, resp_col):
        if col not in found:
            allowed = ", ".join((load_col, resp_col) + optional)
            raise InputError(where, (lines[row] if row is not None else "").strip()[:60],
                             f"no {col} column (kind {kind.value!r}); name it {allowed} or "
                             f"'<quantity> [<unit>]' with quantity one of: {column_names(kind.value)}; "
                             f"or map it: --columns {col.rsplit('_', 1)[0]}=N:<unit>")
    return layout, columns


def _with_flags(header: dict, flags: TestFlags | None) -> dict:
    """The header with the command line's [test] keys over its own."""
    if not flags:
        return header
    test = header.get("test", {})
    test = test if isinstance(test, dict) else {}
    header["test"] = {**test, **flags.table(test.get("kind"))}
    if "specimen" not in header["test"]:
        raise InputError("--specimen", "not set", "a recording without a [test] specimen needs --specimen")
    return header


def _parse_header(header_lines: list[tuple[int, str]], name: str, headless_ok: bool = False) -> dict:
    if not header_lines:
        if headless_ok:
            return {}
        raise InputError(f"{name}:1", "no header", "a recording starts with '# [test]' lines (kind, specimen), "
                                                   "or give --kind and --specimen")
    doc = "\n".join(text for _, text in header_lines)
    try:
        header = tomllib.loads(doc)
    except RecursionError:
        raise InputError(f"{name}:{header_lines[0][0]}", "header",
                         "arrays or tables in the '#' header are nested too deeply") from None
    except ValueError as exc:   # not TOMLDecodeError: an integer beyond Python's 4300-digit limit
        if isinstance(exc, tomllib.TOMLDecodeError):
            raise _header_syntax(exc, header_lines, name) from None
        raise InputError(f"{name}:{header_lines[0][0]}", "header", f"a number in the '#' header is unusable ({exc})") \
            from None
    for key in header:
        if key not in TOP_TABLES:
            raise InputError(f"{name}:{_find(header_lines, key)}", key,
                             f"unknown header table; allowed: {', '.join(sorted(TOP_TABLES))}")
    return header


def _header_syntax(exc: tomllib.TOMLDecodeError, header_lines, name: str) -> InputError:
    """tomllib reports "(at line N, column M)" counted inside the header document: map N to the file line."""
    msg = str(exc)
    lineno = header_lines[0][0]
    if "line " in msg:
        try:
            k = int(msg.rsplit("line ", 1)[1].split(",")[0].split(")")[0])
            lineno = header_lines[min(k, len(header_lines)) - 1][0]
        except ValueError:
            pass
    return InputError(f"{name}:{lineno}", "header", f"the '#' header is not valid TOML ({msg})")


def _check_overrides(overrides: object, header_lines, name: str) -> None:
    """The header's [params.*] tables against the parameter schema, refused at their own file line."""
    if not isinstance(overrides, dict):
        raise InputError(f"{name}:{_find(header_lines, 'params')}", overrides,
                         "params must be [params.<section>] tables of parameter keys")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RangeWarning)   # the pipeline loads them again and warns there
            load_params(overrides=overrides)
    except InputError as exc:
        section, _, key = str(exc.key).strip("[]").partition(".")
        raise InputError(f"{name}:{_find_param(header_lines, section, key)}", exc.value,
                         f"[params.{section}]{'.' + key if key else ''}: {exc.allowed}") from None


def _find_param(header_lines, section: str, key: str) -> int:
    """File line of ``key`` inside ``[params.<section>]`` (or of the table itself)."""
    inside, table_line = False, None
    for lineno, text in header_lines:
        stripped = text.strip()
        if stripped.startswith("["):
            inside = stripped.replace(" ", "").startswith(f"[params.{section}]")
            if inside:
                table_line = lineno
            continue
        if inside and key and stripped.split("=", 1)[0].strip() == key:
            return lineno
    return table_line if table_line is not None else _find(header_lines, "params")


def _number_in(value: object, lo: float, hi: float) -> bool:
    """A TOML number within [lo, hi]; huge integers are compared as integers (float() would overflow)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    return lo <= value <= hi


def _parse_test(header: dict, header_lines, name: str):
    test = header.get("test")
    if not isinstance(test, dict):
        raise InputError(f"{name}:{header_lines[0][0]}", "header", "missing the [test] table (kind, specimen)")
    for key in test:
        if key not in TEST_KEYS:
            raise InputError(f"{name}:{_find(header_lines, key)}", key,
                             f"unknown [test] key; allowed: {', '.join(sorted(TEST_KEYS))}")
    kinds = [k.value for k in RecordingKind]
    if test.get("kind") not in kinds:
        raise InputError(f"{name}:{_find(header_lines, 'kind')}", test.get("kind"), f"test.kind must be one of {kinds}")
    kind = RecordingKind(test["kind"])
    if test.get("specimen") not in SPECIMENS[kind]:
        raise InputError(f"{name}:{_find(header_lines, 'specimen')}", test.get("specimen"),
                         f"test.specimen for {kind.value} must be one of {list(SPECIMENS[kind])}")
    out = {"baseline_uncertainty": 0.02, "description": test.get("description", "")}
    u = test.get("baseline_uncertainty", 0.02)
    lo, hi = BASELINE_UNCERTAINTY_RANGE
    if not _number_in(u, lo, hi) or u == hi:
        raise InputError(f"{name}:{_find(header_lines, 'baseline_uncertainty')}", u,
                         f"test.baseline_uncertainty must be a relative uncertainty in [{lo:g}, {hi:g})")
    out["baseline_uncertainty"] = float(u)
    stiff_key = "baseline_stiffness_Nmm_per_rad" if kind is RecordingKind.TORSION else "baseline_stiffness_N_per_mm"
    wrong_key = "baseline_stiffness_N_per_mm" if kind is RecordingKind.TORSION else "baseline_stiffness_Nmm_per_rad"
    if wrong_key in test:
        raise InputError(f"{name}:{_find(header_lines, wrong_key)}", wrong_key, f"for {kind.value} use {stiff_key}")
    if stiff_key in test:
        k = test[stiff_key]
        lo, hi = BASELINE_STIFFNESS_RANGE
        if not _number_in(k, lo, hi):
            raise InputError(f"{name}:{_find(header_lines, stiff_key)}", k,
                             f"test.{stiff_key} must be a number in [{lo:g}, {hi:g}]")
        out["baseline_stiffness"] = float(k)
    if "rated_torque_Nmm" in test:
        t = test["rated_torque_Nmm"]
        if kind is not RecordingKind.TORSION or not _number_in(t, 1e-6, MAX_ABS["torque_Nmm"]) or t <= 0:
            raise InputError(f"{name}:{_find(header_lines, 'rated_torque_Nmm')}", t,
                             f"test.rated_torque_Nmm (torsion only) must be a torque in (0, {MAX_ABS['torque_Nmm']:g}]")
        out["rated_torque"] = float(t)
    if "unit" in test:
        where = f"{name}:{_find(header_lines, 'unit')}"
        out["unit"] = _unit_value(where, test["unit"], kind)
        if stiff_key in test:
            raise InputError(where, test["unit"], f"a catalogue unit's curve is the baseline: give test.unit or "
                             f"test.{stiff_key} (--stiffness), not both")
        if "baseline_uncertainty" not in test:
            out["baseline_uncertainty"] = UNIT_UNCERTAINTY
    return kind, test["specimen"], out


def _unit_value(where: str, value, kind: RecordingKind) -> str:
    """A catalogue unit the shipped tables hold (drive_curve.unit_curve), for a torsion test; else InputError."""
    from strainwave.compare.diagnose.drive_curve import known_units, unit_curve
    if kind is not RecordingKind.TORSION:
        raise InputError(where, value, "a catalogue unit is a drive: only for a torsion recording")
    if not isinstance(value, str) or unit_curve(value) is None:
        units = known_units()
        raise InputError(where, value, f"a catalogue unit of the shipped table, CHA-<size>A-<ratio>: "
                         f"{units[0]} ... {units[-1]} ({len(units)} units)")
    return value.strip().upper()


def _find(header_lines, key: str) -> int:
    for lineno, text in header_lines:
        stripped = text.strip()
        if stripped.startswith(key) or stripped.startswith(f"[{key}"):
            return lineno
    return header_lines[0][0] if header_lines else 1


def _parse_rows(lines: list[str], layout: table.Layout, columns: list, name: str) -> np.ndarray:
    """The read columns of every data row, each converted to its canonical unit."""
    rows = []
    picks = [j for j, _, _, _ in columns]
    names = ",".join(c for _, c, _, _ in columns)
    row = layout.column_row
    ncol = len(table.split_header(lines[row], layout.delimiter)) if row is not None else None
    for i in range(layout.data_start, len(lines)):
        line = lines[i]
        if line.strip() == "" or line.startswith("#"):
            continue
        try:
            cells = table.split(line, layout.delimiter)
        except csv.Error as exc:
            raise InputError(f"{name}:{i + 1}", line.strip()[:60], f"not a CSV row ({exc})") from None
        cells = table.check_cells(cells, ncol, f"{name}:{i + 1}", line, layout, names)
        picked = [cells[j] if j < len(cells) else "" for j in picks]
        for (j, col, _, _), cell in zip(columns, picked):
            if cell == "":
                raise InputError(f"{name}:{i + 1}", line.strip()[:60],
                                 f"no value in column {j + 1} ({col}); every data row needs a number there "
                                 f"(cells separated by {layout.separator})")
        try:
            values = [table.number(c, layout.decimal) for c in picked]
        except ValueError:
            bad = next(c for c in picked if not table.is_number(c, layout.decimal))
            raise InputError(f"{name}:{i + 1}", bad, "every cell must be a number") from None
        if not all(math.isfinite(v) for v in values):
            raise InputError(f"{name}:{i + 1}", line.strip()[:60], "NaN or infinite values are not allowed")
        rows.append(values)
        if len(rows) > MAX_ROWS:
            raise InputError(f"{name}:{i + 1}", f"more than {MAX_ROWS} data rows",
                             "decimate the recording (diagnose fits on at most 2,500 strided rows)")
    return np.asarray(rows, dtype=float).reshape(-1, len(columns)) * np.array([f for _, _, f, _ in columns])


def _row_line(lines: list[str], start: int, row: int) -> int:
    """1-based line number of data row ``row`` (0-based) after the CSV header at ``start``."""
    seen = -1
    for i in range(start + 1, len(lines)):
        if lines[i].strip() == "" or lines[i].startswith("#"):
            continue
        seen += 1
        if seen == row:
            return i + 1
    return len(lines)


def format_recording(kind: RecordingKind, specimen: str, load: np.ndarray, response: np.ndarray, *,
                     baseline_uncertainty: float | None = None, baseline_stiffness: float | None = None,
                     params: dict | None = None, time_s: np.ndarray | None = None, description: str = "",
                     input_angle_rad: np.ndarray | None = None) -> str:
    """Write a recording in the documented format (the inverse of ``parse_text``)."""
    (load_col, resp_col), _ = COLUMNS[kind]
    head = ["[test]", f'kind = "{kind.value}"', f'specimen = "{specimen}"']
    if description:
        head.append(f"description = {_toml_value(description)}")
    if baseline_uncertainty is not None:
        head.append(f"baseline_uncertainty = {baseline_uncertainty!r}")
    if baseline_stiffness is not None:
        key = "baseline_stiffness_Nmm_per_rad" if kind is RecordingKind.TORSION else "baseline_stiffness_N_per_mm"
        head.append(f"{key} = {float(baseline_stiffness)!r}")
    for section, table in (params or {}).items():
        head.append(f"[params.{section}]")
        head.extend(f"{k} = {_toml_value(v)}" for k, v in table.items())
    cols = [load_col, resp_col] + (["time_s"] if time_s is not None else [])
    stack = [load, response] + ([time_s] if time_s is not None else [])
    if input_angle_rad is not None:
        cols.append("input_angle_rad")
        stack.append(input_angle_rad)
    out = ["# " + h for h in head] + [",".join(cols)]
    out.extend(",".join(f"{v:.9g}" for v in row) for row in zip(*stack))
    return "\n".join(out) + "\n"


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, float) else repr(v)
