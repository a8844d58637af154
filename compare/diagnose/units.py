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

_BRACKETED = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[\s*(?P<unit>[^\[\]]+?)\s*\]\s*$")
# allowed spellings -> pint expression, per canonical unit
_TORQUE = {"N m": "N*m", "Nm": "N*m", "N*m": "N*m", "N.m": "N*m", "kN m": "kN*m", "kNm": "kN*m", "kN*m": "kN*m",
           "N mm": "N*mm", "Nmm": "N*mm", "N*mm": "N*mm"}
_ANGLE = {"rad": "rad", "mrad": "mrad", "urad": "urad", "deg": "deg", "°": "deg", "arcmin": "arcmin",
          "arcsec": "arcsec"}
_FORCE = {"N": "N", "kN": "kN"}
_LENGTH = {"mm": "mm", "um": "um", "µm": "um", "m": "m"}
_TIME = {"s": "s", "ms": "ms", "min": "min"}
# (name prefixes, canonical column, canonical pint unit, allowed spellings) per kind
QUANTITIES = {
    "torsion": ((("torque", "moment"), "torque_Nmm", "N*mm", _TORQUE),
                (("input angle", "input_angle", "wave generator", "input"), "input_angle_rad", "rad", _ANGLE),
                (("angle", "twist", "output angle"), "twist_rad", "rad", _ANGLE),
                (("time",), "time_s", "s", _TIME)),
    "ring_compression": ((("force", "load"), "force_N", "N", _FORCE),
                         (("delta_ab", "delta ab"), "delta_ab_mm", "mm", _LENGTH),
                         (("delta_cd", "delta cd", "deflection", "displacement", "delta"), "delta_cd_mm", "mm",
                          _LENGTH),
                         (("time",), "time_s", "s", _TIME)),
}


def canonical_column(column: str, kind: str, where: str) -> tuple[str, float, str]:
    """(canonical column, factor to its unit, the recording's own unit) of a column; a column without a
    bracketed unit is returned as it is (factor 1). An unknown quantity or unit: InputError at ``where``."""
    m = _BRACKETED.match(column)
    if m is None:
        return column, 1.0, ""
    name, unit = m.group("name").strip().lower(), m.group("unit").strip()
    for prefixes, canonical, target, spellings in QUANTITIES[kind]:
        if any(name.startswith(p) for p in prefixes):
            if unit not in spellings:
                raise InputError(where, unit, f"unknown unit for {m.group('name').strip()!r}; allowed: "
                                              f"{', '.join(spellings)}")
            return canonical, _factor(spellings[unit], target), unit
    names = sorted({p for q in QUANTITIES[kind] for p in q[0]})
    raise InputError(where, column, f"unknown quantity for kind {kind!r}; a column '<quantity> [<unit>]' starts "
                                    f"with one of: {', '.join(names)}")


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
_COLUMN_QUANTITY = {"torque_Nmm": "torque", "twist_rad": "angle", "force_N": "force", "delta_cd_mm": "length"}


@dataclass(frozen=True)
class Display:
    """The recording's own units (its column row's spellings) for text, JSON and plot; canonical where the file
    wrote canonical columns."""

    spelling: tuple[tuple[str, str], ...] = ()      # (quantity, the file's spelling)

    @classmethod
    def of(cls, units: dict) -> "Display":
        """From Recording.units (canonical column -> the file's unit, "" for canonical)."""
        return cls(tuple((_COLUMN_QUANTITY[c], u) for c, u in sorted(units.items()) if c in _COLUMN_QUANTITY and u))

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


__all__ = ["Display", "FLAG_QUANTITIES", "QUANTITIES", "canonical_column", "flag_value"]
