"""The table of a rig's export file: where its column row and data start, its separator and decimal mark.

Rig software and spreadsheets write a few lines of metadata (``Date: ...``, ``Operator;...``) before the column
row, separate cells by a comma, a semicolon, a tab or runs of spaces, and write decimal commas and thousands
separators in the exporting locale. This module finds each of these from the file itself; what the columns
mean is ``units.py``'s.
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass

from strainwave.errors import InputError
from strainwave.input_guard import SNIFF_CHARS, sniff_sample

WHITESPACE = " "                 # the delimiter of a table separated by runs of spaces or tabs
MAX_PREAMBLE_LINES = 100         # metadata lines before the column row; rig software writes a dozen
_NUMERIC = re.compile(r"^[-+]?(?:[\d.,]*\d[\d.,]*(?:[eE][-+]?\d+)?|nan|inf|infinity)$", re.IGNORECASE)
# thousands grouped by the mark that is not the decimal one: 1.234.567,8 or 1,234,567.8
_GROUPED = {",": re.compile(r"^[-+]?[1-9]\d{0,2}(?:\.\d{3})+(?:,\d*)?(?:[eE][-+]?\d+)?$"),
            ".": re.compile(r"^[-+]?[1-9]\d{0,2}(?:,\d{3})+(?:\.\d*)?(?:[eE][-+]?\d+)?$")}
_NAMES = {"\t": "tab", ";": "';'", ",": "','", WHITESPACE: "spaces"}


@dataclass(frozen=True)
class Layout:
    """Where the table is in a file's lines (0-based) and how its cells are written."""

    column_row: int | None       # None: the file has no column row (columns mapped by position)
    data_start: int
    delimiter: str               # ",", ";", "\t" or WHITESPACE
    decimal: str                 # "." or ","

    @property
    def separator(self) -> str:
        return _NAMES[self.delimiter]


def find_layout(lines: list[str], start: int, recognised) -> Layout:
    """The column row, the first data row, the separator and the decimal mark of ``lines[start:]``.

    The data start at the first line of two or more numbers; the column row is the first line before it in which
    ``recognised(cells)`` (the load and the response columns are named), else the line just before the data;
    the lines above it are the export's metadata and are not read."""
    candidates, first_data = [], None
    for i in range(start, len(lines)):
        line = lines[i]
        if not line.strip() or line.startswith("#"):
            continue
        if _is_data(line):
            first_data = i
            break
        candidates.append(i)
        if len(candidates) > MAX_PREAMBLE_LINES:
            break
    if first_data is None:    # no data row near the top: the first line is the column row; rows are checked later
        first = candidates[0] if candidates else len(lines)
        head = lines[first:first + 1]
        delimiter = _sniff(head, head[0] if head else "")
        return Layout(first if candidates else None, first + 1, delimiter, ".")
    data = [ln for ln in lines[first_data:first_data + 40] if ln.strip() and not ln.startswith("#")][:21]
    column_row = None
    if candidates:
        delimiter = _sniff([lines[candidates[-1]]] + data, lines[candidates[-1]])
        column_row = next((i for i in candidates if recognised(_header_or_none(lines[i], delimiter))), candidates[-1])
    else:
        delimiter = _sniff(data, data[0])
    body = lines[first_data if column_row is None else column_row + 1:]
    return Layout(column_row, first_data if column_row is None else column_row + 1, delimiter,
                  _decimal(body, delimiter))


def _is_data(line: str) -> bool:
    """Two or more numbers under some separator (empty cells and NaN allowed: the rows say what is wrong)."""
    for delimiter in (";", "\t", ",", WHITESPACE):
        try:
            cells = [c for c in split(line, delimiter) if c]
        except csv.Error:
            return False
        if len(cells) >= 2 and all(_NUMERIC.match(c) for c in cells):
            return True
    return False


def _sniff(sample: list[str], head: str) -> str:
    """Comma, semicolon or tab (csv.Sniffer on the column row and the first data rows), else runs of spaces."""
    if sample and not any(d in ln for ln in sample[1:] or sample for d in ",;\t") and len(sample[-1].split()) >= 2:
        return WHITESPACE
    try:
        return csv.Sniffer().sniff(sniff_sample(sample), delimiters=",;\t").delimiter
    except csv.Error:
        # one-column or irregular text: the most frequent candidate of the column row, else a comma
        head = head[:SNIFF_CHARS]
        counts = {d: head.count(d) for d in (";", "\t", ",")}
        best = max(counts, key=counts.get)
        return best if counts[best] else ","


def _decimal(body: list[str], delimiter: str) -> str:
    """The decimal mark: a point in a comma-separated file; else a number grouped by one mark and ending in the
    other names both, and a comma in a cell is a decimal comma."""
    if delimiter == ",":
        return "."
    text = "\n".join(body)
    if re.search(r"\d\.\d{3},\d", text):
        return ","
    if re.search(r"\d,\d{3}\.\d", text):
        return "."
    return "," if "," in text else "."


def split(line: str, delimiter: str) -> list[str]:
    """The cells of one row, trailing separators (spreadsheets pad every row) dropped."""
    if delimiter == WHITESPACE:
        cells = [c.strip('"') for c in line.split()]
    else:
        cells = [c.strip() for c in next(csv.reader([line], delimiter=delimiter, quotechar='"'))]
    while cells and cells[-1] == "":
        cells.pop()
    return cells


def _header_or_none(line: str, delimiter: str) -> list[str]:
    """A candidate column row's cells; none when csv cannot split it (the reader names that line later)."""
    try:
        return split_header(line, delimiter)
    except csv.Error:
        return []


def split_header(line: str, delimiter: str) -> list[str]:
    """The column row's cells; separated by spaces, a name keeps its unit (``Torque [Nm]``, ``Angle (deg)``) and
    names of several words are kept where the columns stand two or more spaces apart."""
    if delimiter != WHITESPACE:
        return split(line, delimiter)
    wide = [c for c in re.split(r"\s{2,}|\t", line.strip()) if c]
    if len(wide) > 1:
        return wide
    return re.findall(r"[^\s\[(]+(?:\s*[\[(][^\])]*[\])])?", line)


def number(cell: str, decimal: str) -> float:
    """A numeric cell in the file's decimal mark, thousands grouped by the other mark (``1.234,5``)."""
    if "_" in cell or not cell.isascii():   # float() reads 1_000 and Arabic-Indic digits; no spreadsheet writes those
        raise ValueError(cell)
    other = "." if decimal == "," else ","
    if other in cell and _GROUPED[decimal].match(cell):
        cell = cell.replace(other, "")
    elif decimal == "," and "." in cell and "," in cell:
        raise ValueError(cell)
    return float(cell.replace(",", ".") if decimal == "," else cell)


def is_number(cell: str, decimal: str) -> bool:
    try:
        number(cell, decimal)
        return True
    except ValueError:
        return False


def check_cells(cells: list[str], ncol: int | None, where: str, line: str, layout: Layout, names: str) -> list[str]:
    """The row's cells padded to the column row's count; a row with more cells: InputError."""
    if ncol is None:
        return cells
    if len(cells) > ncol:
        raise InputError(where, line.strip()[:60], f"expected {ncol} cells separated by {layout.separator} ({names})")
    return cells + [""] * (ncol - len(cells))


__all__ = ["Layout", "MAX_PREAMBLE_LINES", "WHITESPACE", "check_cells", "find_layout", "is_number", "number",
           "split", "split_header"]
