"""Column rows in the engineer's units: ``Torque [Nm];Angle [arcmin]``.

A column named ``<quantity> [<unit>]`` is mapped to the recording's canonical column (``torque_Nmm``,
``twist_rad``, ...) and its values converted by pint, a maintained units library. The quantity is read from
the name's first word(s); the unit must be one of the allowed spellings of that quantity (pint alone would
read ``Nm`` as a nanometre, so the spellings are listed, and pint converts them).
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from strainwave.errors import InputError

# a column's unit in brackets, in parentheses or after a slash (DIN 1313: "Torque / Nm")
_UNIT_FORMS = (re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[\s*(?P<unit>[^\[\]]+?)\s*\]\s*$"),
               re.compile(r"^\s*(?P<name>[^()]*?)\s*\(\s*(?P<unit>[^()]+?)\s*\)\s*$"),
               re.compile(r"^\s*(?P<name>[^/]*?[^/\s])\s+/\s*(?P<unit>[^/]+?)\s*$"))
# allowed spellings -> pint expression, per canonical unit
_TORQUE = {"N m": "N*m", "Nm": "N*m", "N*m": "N*m", "N.m": "N*m", "N·m": "N*m", "kN m": "kN*m", "kNm": "kN*m",
           "kN*m": "kN*m", "kN·m": "kN*m", "N mm": "N*mm", "Nmm": "N*mm", "N*mm": "N*mm", "N·mm": "N*mm"}
_ANGLE = {"rad": "rad", "mrad": "mrad", "urad": "urad", "µrad": "urad", "deg": "deg", "°": "deg",
          "arcmin": "arcmin", "'": "arcmin", "′": "arcmin", "arcsec": "arcsec", '"': "arcsec", "″": "arcsec"}
_FORCE = {"N": "N", "kN": "kN"}
_LENGTH = {"mm": "mm", "um": "um", "µm": "um", "m": "m"}
_TIME = {"s": "s", "ms": "ms", "min": "min"}
# (name prefixes, canonical column, canonical pint unit, allowed spellings) per kind; German as rig software
# in German writes it (Drehmoment, Verdrehwinkel, Zeit, Kraft, Weg)
QUANTITIES = {
    "torsion": ((("torque", "moment", "drehmoment"), "torque_Nmm", "N*mm", _TORQUE),
                (("input angle", "input_angle", "wave generator", "input", "antriebswinkel"), "input_angle_rad",
                 "rad", _ANGLE),
                (("angle", "twist", "output angle", "verdrehwinkel", "verdrehung", "winkel", "torsionswinkel"),
                 "twist_rad", "rad", _ANGLE),
                (("time", "zeit"), "time_s", "s", _TIME)),
    "ring_compression": ((("force", "load", "kraft"), "force_N", "N", _FORCE),
                         (("delta_ab", "delta ab"), "delta_ab_mm", "mm", _LENGTH),
                         (("delta_cd", "delta cd", "deflection", "displacement", "delta", "weg"), "delta_cd_mm",
                          "mm", _LENGTH),
                         (("time", "zeit"), "time_s", "s", _TIME)),
}
# the --columns flag's quantity names: the canonical column without its unit
MAPPED = {kind: {q[1].rsplit("_", 1)[0]: q for q in table} for kind, table in QUANTITIES.items()}


def _micro(unit: str) -> str:
    """The Greek mu is the micro sign (U+00B5, what Latin-1 keyboards type)."""
    return unit.replace("\u03bc", "\u00b5")


def split_unit(column: str) -> tuple[str, str | None]:
    """(name, unit) of a column cell: ``Torque [Nm]``, ``Torque (Nm)``, ``Torque / Nm``; unit None if none."""
    for form in _UNIT_FORMS:
        m = form.match(column)
        if m is not None:
            return m.group("name").strip(), _micro(m.group("unit").strip())
    return column.strip(), None


def canonical_column(column: str, kind: str, where: str) -> tuple[str, float, str] | None:
    """(canonical column, factor to its unit, the recording's own unit) of a column cell, None for a column
    that is no quantity of ``kind`` (another channel: temperature, speed). A canonical name (``torque_Nmm``) is
    itself (factor 1). A known quantity with an unknown unit, or without a unit: InputError at ``where``."""
    if column in {q[1] for q in QUANTITIES[kind]}:
        return column, 1.0, ""
    name, unit = split_unit(column)
    quantity = _quantity(name, kind)
    if quantity is None:
        return None
    if quantity[1] in _OPTIONAL and unit not in quantity[3] and _other_dimension(unit, quantity[2]):
        return None
    return unit_of(quantity, unit, where, name, f"write it in the column row ('{name} [<unit>]') or give it with "
                                                f"--columns {quantity[1].rsplit('_', 1)[0]}=N:<unit>")


_OPTIONAL = ("input_angle_rad", "time_s", "delta_ab_mm")


def _other_dimension(unit: str | None, target: str) -> bool:
    """True where pint reads ``unit`` as another dimension than ``target``: "Input speed [rpm]" is a speed channel
    beside the input angle, not a misspelt angle."""
    import pint
    if unit is None:
        return False
    try:
        registry = _registry(pint)
        return registry.Quantity(1.0, unit).dimensionality != registry.Quantity(1.0, target).dimensionality
    except Exception:   # pint raises several unrelated types on text that is no unit: then it is no other dimension
        return False


def _quantity(name: str, kind: str):
    low = name.lower()
    # a whole word: "Timestamp" is no time in seconds, "Torque1" and "Angle_out" still name their quantity
    return next((q for q in QUANTITIES[kind] if any(re.match(re.escape(p) + r"(?![a-z])", low) for p in q[0])), None)


def unit_of(quantity, unit: str | None, where: str, name: str, hint: str) -> tuple[str, float, str]:
    """(canonical column, factor, unit) of ``quantity`` written in ``unit``; None or an unknown unit: InputError."""
    _, canonical, target, spellings = quantity
    if unit is None:
        raise InputError(where, name, f"no unit; allowed: {', '.join(spellings)}; {hint}")
    if unit not in spellings:
        raise InputError(where, unit, f"unknown unit for {name!r}; allowed: {', '.join(spellings)}")
    return canonical, _factor(spellings[unit], target), unit


def column_names(kind: str) -> str:
    """The quantity names a column row is recognised by, for messages."""
    return ", ".join(sorted({p for q in QUANTITIES[kind] for p in q[0]}))


_CANONICAL_LIKE = re.compile(r"^[a-z][a-z_]*_(?:Nmm|rad|s|N|mm)$")


def read_columns(cells: list[str], kind: str, where: str, mapping: str | None) -> list[tuple[int, str, float, str]]:
    """(cell index, canonical column, factor, the file's unit) of every column read from a column row's ``cells``
    (or, with ``mapping`` = the ``--columns`` value, of the mapped columns only). A column naming no quantity
    of ``kind`` (temperature, speed) is not read; one spelled like a canonical column of another kind is refused."""
    if mapping is not None:
        return _mapped(cells, kind, mapping)
    known = {q[1] for q in QUANTITIES[kind]}
    out = []
    for j, cell in enumerate(cells):
        if _CANONICAL_LIKE.match(cell) and cell not in known:
            raise InputError(where, cell, f"unknown column for kind {kind!r}; allowed: {', '.join(sorted(known))}")
        read = canonical_column(cell, kind, where)
        if read is not None:
            out.append((j, *read))
    names = [c for _, c, _, _ in out]
    if len(set(names)) != len(names):
        raise InputError(where, ",".join(cells), f"two columns name the same quantity ({', '.join(names)})")
    return out


def _mapped(cells: list[str], kind: str, mapping: str) -> list[tuple[int, str, float, str]]:
    """``--columns torque=2,twist=3:deg``: 1-based positions, the unit after a colon or from the column row."""
    allowed = f"QUANTITY=N[:UNIT],... with QUANTITY one of {', '.join(MAPPED[kind])} and N a 1-based column number"
    out, seen = [], set()
    for part in str(mapping).split(","):
        quantity, _, ref = part.partition("=")
        position, _, unit = ref.partition(":")
        quantity = MAPPED[kind].get(quantity.strip())
        if quantity is None or not position.strip().isdigit() or int(position) < 1 or quantity[1] in seen:
            raise InputError("--columns", mapping, allowed)
        j = int(position) - 1
        seen.add(quantity[1])
        cell = cells[j] if j < len(cells) else ""
        if unit.strip():
            read = unit_of(quantity, _micro(unit.strip()), "--columns", part.strip(), "")
        elif cell == quantity[1]:
            read = (cell, 1.0, "")
        else:
            read = unit_of(quantity, split_unit(cell)[1], "--columns", part.strip(),
                           f"column {j + 1} of the column row names none; give it: {part.strip()}:<unit>")
        out.append((j, *read))
    return out


_NUMBER = re.compile(r"^\s*(?P<value>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(?P<unit>.*?)\s*$")
# what a flag's value measures: (numerator spellings, canonical unit, denominator spellings, canonical unit)
FLAG_QUANTITIES = {"torque": (_TORQUE, "N*mm", None, ""),
                   "torsional_stiffness": (_TORQUE, "N*mm", _ANGLE, "rad"),
                   "ring_stiffness": (_FORCE, "N", _LENGTH, "mm")}


def flag_value(flag: str, text: str, quantity: str) -> float:
    """A positive number with an optional unit (``7.8 Nm``, ``1.9e3 Nm/rad``; a bare number is in the canonical
    unit, N*mm, N*mm/rad or N/mm) in the canonical unit; anything else: InputError naming the flag."""
    num, target, den, den_target = FLAG_QUANTITIES[quantity]
    canonical = target + (f"/{den_target}" if den else "")
    allowed = ", ".join(num) if den is None else f"<{'|'.join(num)}>/<{'|'.join(den)}>"
    m = _NUMBER.match(str(text))
    if m is None:
        raise InputError(flag, text, f"a positive number with an optional unit ({allowed}; bare: {canonical})")
    value, unit = float(m.group("value")), m.group("unit")
    if not (value > 0.0 and value < float("inf")):
        raise InputError(flag, text, "must be a positive finite number")
    if not unit:
        return value
    top, _, bottom = unit.partition("/")
    top, bottom = top.strip(), bottom.strip()
    if top not in num or (den is None) != (not bottom) or (den is not None and bottom not in den):
        raise InputError(flag, text, f"unknown unit {unit!r}; allowed: {allowed} (bare number: {canonical})")
    factor = _factor(num[top], target) / (_factor(den[bottom], den_target) if den is not None else 1.0)
    return value * factor


def _factor(unit: str, target: str) -> float:
    import pint
    registry = _registry(pint)
    return float(registry.Quantity(1.0, unit).to(target).magnitude)


# a report's canonical units as (numerator quantity, denominator quantity), "*" for a product
_COMPOSITE = {"N*mm": ("torque", None), "rad": ("angle", None), "N*mm/rad": ("torque", "angle"),
              "rad/N*mm": ("angle", "torque"), "N*mm*rad": ("torque", "*angle"), "N": ("force", None),
              "mm": ("length", None), "N/mm": ("force", "length"), "mm/N": ("length", "force"),
              "N*mm*mm": ("force", "*length")}
_CANONICAL = {"torque": "N*mm", "angle": "rad", "force": "N", "length": "mm"}
_SPELLINGS = {"torque": _TORQUE, "angle": _ANGLE, "force": _FORCE, "length": _LENGTH}
# a report names the minute and second of arc by name, not by a bare quote mark
_SHOWN = {"'": "arcmin", "′": "arcmin", '"': "arcsec", "″": "arcsec"}
_COLUMN_QUANTITY = {"torque_Nmm": "torque", "twist_rad": "angle", "force_N": "force", "delta_cd_mm": "length"}


@dataclass(frozen=True)
class Display:
    """The recording's own units (its column row's spellings) for text, JSON and plot; canonical where the file
    wrote canonical columns."""

    spelling: tuple[tuple[str, str], ...] = ()      # (quantity, the file's spelling)

    @classmethod
    def of(cls, units: dict) -> "Display":
        """From Recording.units (canonical column -> the file's unit, "" for canonical)."""
        return cls(tuple((_COLUMN_QUANTITY[c], _SHOWN.get(u, u)) for c, u in sorted(units.items())
                         if c in _COLUMN_QUANTITY and u))

    def _one(self, quantity: str) -> tuple[float, str]:
        spelled = dict(self.spelling).get(quantity)
        if not spelled:
            return 1.0, _CANONICAL[quantity]
        return 1.0 / _factor(_SPELLINGS[quantity][spelled], _CANONICAL[quantity]), spelled

    def convert(self, value, unit: str) -> tuple[object, str]:
        """(value, unit) in the recording's units; a unit that is no torque, angle, force or length (or a product
        or ratio of two) is returned as it is."""
        if not self.spelling or unit not in _COMPOSITE or value is None or isinstance(value, (str, bool)):
            return value, unit
        num, den = _COMPOSITE[unit]
        f, name = self._one(num)
        if den is None:
            return value * f, name
        g, other = self._one(den.lstrip("*"))
        if den.startswith("*"):
            return value * f * g, f"{name}*{other}"
        return value * f / g, f"{name}/{other}"

    def to_dict(self) -> dict:
        return {q: u for q, u in self.spelling}

    def text(self, value: float, unit: str) -> str:
        """``value`` formatted in the recording's unit, the unit named only where the file spelled one."""
        v, u = self.convert(value, unit)
        return f"{v:.3g}" + (f" {u}" if self.spelling else "")


_REGISTRY = []


def _registry(pint):
    if not _REGISTRY:
        _REGISTRY.append(pint.UnitRegistry())
    return _REGISTRY[0]


__all__ = ["Display", "FLAG_QUANTITIES", "MAPPED", "QUANTITIES", "canonical_column", "column_names", "flag_value",
           "read_columns", "split_unit", "unit_of"]
