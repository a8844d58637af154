"""`strainwave size-crack`: diagnose a recording, size the crack its compliance change implies in each
component of the specimen, and integrate its remaining life (seed 000's predictive-maintenance use)."""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.compare.diagnose.crack_sizing import size_diagnosis
from strainwave.compare.diagnose.remaining_life import (BS7910_STEEL, LoadSpectrum, ParisLaw, life_lines,
                                                        life_of_sizing, plot_life, spectrum_from_history)
from strainwave.errors import InputError

__all__ = ["LifeOptions", "CrackLifeReport", "size_and_life", "read_torque_history"]

MAX_HISTORY_ROWS = 1_000_000


@dataclass(frozen=True)
class LifeOptions:
    paris_C: float = BS7910_STEEL.C
    paris_m: float = BS7910_STEEL.m
    stiffness_loss: float = 0.1
    cycles_per_hour: float | None = None
    torque_history: Path | None = None
    curves: Path | None = None           # a validate results.json holding the cup's crack sweep
    cache_dir: Path | None = None

    def law(self) -> ParisLaw:
        if (self.paris_C, self.paris_m) == (BS7910_STEEL.C, BS7910_STEEL.m):
            return BS7910_STEEL
        return ParisLaw(self.paris_C, self.paris_m, "user-given Paris law (N, mm)")


@dataclass(frozen=True)
class CrackLifeReport:
    recording: str
    verdict: str
    named: tuple[str, ...]
    sizing: dict | None
    lives: list
    tooth_crack: dict | None = None      # the tooth-root crack through the mesh (compare/diagnose/tooth_crack.py)

    def summary(self) -> str:
        head = f"{self.recording}: {self.verdict}" + (f" ({' + '.join(self.named)})" if self.named else "")
        tooth = [] if self.tooth_crack is None else ["tooth-root crack through the mesh:", *self.tooth_crack["lines"]]
        if self.sizing is None:
            return "\n".join([head + ("\nno crack-type change to size: the diagnosis names neither crack_closure, a "
                                      "compliance change nor a stiffness ripple at twice the input angle"), *tooth])
        s = self.sizing
        lines = [head, f"measured {s.get('quantity', 'compliance change')} {s['delta']:.4g} +/- {s['sigma']:.2g} "
                       f"{s['unit']} (1 sigma, from {s['effect']})", *s["lines"], *life_lines(self.lives), *tooth]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        sizing = None if self.sizing is None else {k: v for k, v in self.sizing.items() if not k.startswith("_")}
        tooth = None if self.tooth_crack is None else {k: v for k, v in self.tooth_crack.items()
                                                        if not k.startswith("_")}
        return {"recording": self.recording, "verdict": self.verdict, "named": list(self.named), "sizing": sizing,
                "remaining_life": self.lives, "tooth_crack": tooth}


def read_torque_history(path: Path) -> np.ndarray:
    """A torque history: one number per line (N mm), or a CSV with a ``torque_Nmm`` column; '#' lines skipped."""
    from strainwave.input_guard import read_regular
    values = []
    raw = read_regular(path, 64 * MAX_HISTORY_ROWS, "--torque-history")   # a regular file, bounded
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError("--torque-history", str(path), "a UTF-8 text file") from None
    rows = csv.reader(line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#"))
    col = 0
    try:
        for lineno, row in enumerate(rows, 1):
            if lineno == 1 and "torque_Nmm" in row:
                col = row.index("torque_Nmm")
                continue
            try:
                value = float(row[col])
            except (ValueError, IndexError):
                raise InputError(f"{path}:{lineno}", ",".join(row)[:60], "a torque in N mm per line") from None
            if not math.isfinite(value):
                raise InputError(f"{path}:{lineno}", row[col], "a finite torque in N mm")
            values.append(value)
            if len(values) > MAX_HISTORY_ROWS:
                raise InputError("--torque-history", str(path), f"at most {MAX_HISTORY_ROWS} rows")
    except csv.Error as exc:   # e.g. a cell beyond csv's field-size limit
        raise InputError("--torque-history", str(path), f"not a CSV file ({exc})") from None
    if len(values) < 3:
        raise InputError("--torque-history", str(path), "at least 3 torque values (one load cycle)")
    return np.asarray(values)


def size_and_life(recording: Path, options: LifeOptions, *, params_path=None, baseline: str = "analytic",
                  plot_out: Path | None = None, progress=lambda m: None) -> CrackLifeReport:
    """Diagnose, size, and integrate the life; the plot is written only when there is a life to draw."""
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.recording import parse_recording
    from strainwave.params import load_params

    law = options.law()
    if not 0.0 < options.stiffness_loss < 1.0:
        raise InputError("--stiffness-loss", options.stiffness_loss, "a fraction in (0, 1)")
    spectrum = None
    if options.torque_history is not None:
        spectrum = spectrum_from_history(read_torque_history(options.torque_history))
    if options.curves is not None:   # read before any work (issue 53: a wrong file was never read)
        from strainwave.compare.diagnose.crack_sizing import read_results
        read_results(options.curves)
    rec = parse_recording(recording)
    params = load_params(params_path, overrides=rec.param_overrides or None, origin=f"{recording} [params]")
    from strainwave.progress import ticking
    now = [f"the {baseline} baseline"]
    with ticking(lambda: f"size-crack {Path(recording).name}: diagnosing, {now[0]}", progress,
                 done=f"size-crack {Path(recording).name}: diagnosis"):
        diag, _ = diagnose(rec, params, baseline, stage=lambda s: now.__setitem__(0, s))
    sizing = size_diagnosis(diag, params, rec.load, rec.response, results=options.curves, cache_dir=options.cache_dir, progress=progress)
    lives = [] if sizing is None else life_of_sizing(
        sizing, diag.baseline.compliance, params, law=law, spectrum=spectrum or LoadSpectrum.constant(
            params.gear.rated_output_torque_Nmm), stiffness_loss=options.stiffness_loss,
        cycles_per_hour=options.cycles_per_hour)
    if plot_out is not None and lives:
        plot_life(plot_out, lives)
    tooth = None
    angle = rec.extra.get("input_angle_rad")
    if angle is not None and rec.specimen == "gear":   # a drive turning: the cracked tooth's passes through the mesh
        from strainwave.compare.diagnose.tooth_crack import mesh_curve_record, size_tooth_crack
        tooth = size_tooth_crack(rec.load, rec.response, angle, params, time_s=rec.time_s,
                                 curve_record=lambda: mesh_curve_record(params, options.cache_dir, progress))
    return CrackLifeReport(diag.recording, diag.verdict.value, tuple(diag.named), sizing, lives, tooth)
