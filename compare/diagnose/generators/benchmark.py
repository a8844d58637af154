"""Score the diagnosis blind on concealed recordings of two independent generator families
(`strainwave benchmark-diagnose [--family 1|2|both]`).

Family 1: generate_recordings (hifi_torsion / hifi_ring). Family 2: generate_family2 (independent
physics, coloured noise, out-of-catalogue recordings). Both families also carry the CHA table
(real catalogue stiffness curves, cha.py / generate_family2.cha_recording).

Targets, each printed PASS/MISS with its number, per family:
- in-catalogue, signal >= 3x noise: primary effect >= 95 %, exactly the right set >= 90 %;
- clean recordings: false alarms <= 5 %, white and coloured noise reported separately;
- physical hysteresis (signal >= 3x noise): named with its loss within 10 % in >= 90 % (the issue gives
  no rate; 90 % is the set-accuracy target applied to the loop);
- out of catalogue: `unexplained` (or a named effect flagged ambiguous) >= 80 %, confidently naming a
  catalogue effect <= 10 %;
- CHA table: every row exactly nonlinear_stiffness with K1/K2/K3 within 2 %; with a loop, exactly
  nonlinear_stiffness + hysteresis.
"""
from __future__ import annotations

import json
import math
import time
import warnings
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from strainwave.errors import RangeWarning
from strainwave.io_atomic import atomic_write_text, json_ready
from strainwave.compare.diagnose.generators import generate_family2 as gen2
from strainwave.compare.diagnose.generators import generate_recordings as gen1
from strainwave.compare.diagnose.generators.cha import cha_recording as cha_recording_f1
from strainwave.compare.diagnose.generators.cha import cha_rows
from strainwave.compare.diagnose.generators.concealed import Concealed
from strainwave.compare.diagnose.explain import LOSS_PRECISION
from strainwave.compare.diagnose.recording import parse_text

FAMILIES = (1, 2)
SNR_SCORED = 3.0
PRIMARY_TARGET = 0.95
SET_TARGET = 0.90
FALSE_ALARM_TARGET = 0.05
LOSS_TOLERANCE = 0.10
HYSTERESIS_TARGET = 0.90
OOC_FLAGGED_TARGET = 0.80
OOC_WRONG_TARGET = 0.10
STIFFNESS_TOLERANCE = 0.02
CHA_TARGET = 1.0
CLASSES = {1: gen1.CLASSES, 2: gen2.CLASSES}


@dataclass(frozen=True)
class Outcome:
    family: int
    name: str
    cls: str
    truth: tuple[str, ...]
    out_of_catalogue: str
    noise: str
    snr: float
    n_samples: int
    verdict: str                    # agrees | explained | unexplained | error
    named: tuple[str, ...]
    ambiguous: bool
    loss_true_arcmin: float | None
    loss_arcmin: float | None
    stiffness_true: tuple[float, float, float] | None
    stiffness: tuple[float | None, float | None, float | None] | None
    rms_before: float
    rms_after: float
    noise_std: float
    seconds: float
    error: str = ""
    loss_std_error_arcmin: float | None = None   # the loss's standard error as the diagnosis reported it
    events: tuple[str, ...] = ()     # events named beside the verdict (a slip, creep, a drift, mains pick-up)

    @property
    def cha(self) -> bool:
        return self.stiffness_true is not None

    @property
    def clean(self) -> bool:
        return not self.truth and not self.out_of_catalogue

    @property
    def primary_ok(self) -> bool:
        return self.verdict == "explained" and bool(self.named) and self.named[0] in self.truth

    @property
    def set_ok(self) -> bool:
        return self.verdict == "explained" and set(self.named) == set(self.truth)

    @property
    def false_alarm(self) -> bool:
        return self.verdict != "agrees" or bool(self.events)

    @property
    def ooc_flagged(self) -> bool:
        # an event named beside the verdict (time_events.py) says what outside the catalogue the recording holds
        return self.verdict == "unexplained" or (bool(self.named) and self.ambiguous) or bool(self.events)

    @property
    def ooc_confident_wrong(self) -> bool:
        return self.verdict == "explained" and bool(self.named) and not self.ambiguous

    @property
    def loss_error(self) -> float | None:
        if self.loss_true_arcmin is None or self.loss_arcmin is None:
            return None
        return self.loss_arcmin / self.loss_true_arcmin - 1.0

    @property
    def loss_within_3se(self) -> bool | None:
        """Does the reported error bar cover the truth (3 standard errors)? None without both."""
        e = self.loss_error
        if e is None or self.loss_std_error_arcmin is None:
            return None
        return abs(self.loss_arcmin - self.loss_true_arcmin) <= 3.0 * self.loss_std_error_arcmin

    @property
    def loss_flagged_imprecise(self) -> bool:
        """The diagnosis said the recording fixes the loss only beyond 10 % (explain.LOSS_PRECISION)."""
        return (self.loss_std_error_arcmin is not None and self.loss_arcmin is not None
                and self.loss_std_error_arcmin > LOSS_PRECISION * self.loss_arcmin)

    @property
    def loss_ok(self) -> bool:
        e = self.loss_error
        return "hysteresis" in self.named and e is not None and abs(e) <= LOSS_TOLERANCE

    @property
    def stiffness_errors(self) -> tuple[float, ...]:
        if not self.cha or self.stiffness is None:
            return (math.nan,) * 3
        return tuple(math.nan if est is None else est / true - 1.0
                     for est, true in zip(self.stiffness, self.stiffness_true))

    @property
    def stiffness_ok(self) -> bool:
        return all(abs(e) <= STIFFNESS_TOLERANCE for e in self.stiffness_errors)   # nan compares False

    @property
    def predicted(self) -> str:
        """One label for the confusion matrix: agrees, unexplained, error, or the named set (? = ambiguous)."""
        if self.verdict in ("agrees", "unexplained", "error") or not self.named:
            return self.verdict
        return "+".join(sorted(self.named)) + ("?" if self.ambiguous else "")


def _frac(items, pred) -> tuple[float, int]:
    items = list(items)
    return (float(np.mean([bool(pred(o)) for o in items])) if items else math.nan), len(items)


@dataclass(frozen=True)
class Target:
    name: str
    value: float
    n: int
    threshold: float
    upper: bool            # True: value must be <= threshold

    @property
    def status(self) -> str:
        if self.n == 0 or math.isnan(self.value):
            return "n/a"
        ok = self.value <= self.threshold if self.upper else self.value >= self.threshold
        return "PASS" if ok else "MISS"

    def cell(self) -> str:
        if self.n == 0:
            return "n/a"
        return f"{self.status} {100 * self.value:5.1f} % (n={self.n})"


def family_targets(outcomes) -> list[Target]:
    """The issue-12 targets for the outcomes of one family."""
    gen = [o for o in outcomes if not o.cha]
    strong = [o for o in gen if o.truth and o.snr >= SNR_SCORED]
    loops = [o for o in strong if o.loss_true_arcmin is not None]
    clean_white = [o for o in gen if o.clean and o.noise == "white"]
    clean_col = [o for o in gen if o.clean and o.noise != "white"]
    ooc = [o for o in gen if o.out_of_catalogue]
    cha_plain = [o for o in outcomes if o.cha and "hysteresis" not in o.truth]
    cha_loop = [o for o in outcomes if o.cha and "hysteresis" in o.truth]
    t = []
    for name, items, pred, thr, upper in (
            ("primary effect, signal >= 3x noise", strong, lambda o: o.primary_ok, PRIMARY_TARGET, False),
            ("exactly the right set, signal >= 3x noise", strong, lambda o: o.set_ok, SET_TARGET, False),
            ("false alarms, clean, white noise", clean_white, lambda o: o.false_alarm, FALSE_ALARM_TARGET, True),
            ("false alarms, clean, coloured noise", clean_col, lambda o: o.false_alarm, FALSE_ALARM_TARGET, True),
            ("hysteresis named, loss within 10 %", loops, lambda o: o.loss_ok, HYSTERESIS_TARGET, False),
            ("out of catalogue: unexplained or ambiguous", ooc, lambda o: o.ooc_flagged, OOC_FLAGGED_TARGET, False),
            ("out of catalogue: confidently wrong effect", ooc, lambda o: o.ooc_confident_wrong, OOC_WRONG_TARGET, True),
            ("CHA: exactly nonlinear_stiffness, K within 2 %", cha_plain,
             lambda o: o.set_ok and o.stiffness_ok, CHA_TARGET, False),
            ("CHA + loop: exactly nonlinear_stiffness + hysteresis", cha_loop, lambda o: o.set_ok, CHA_TARGET, False)):
        value, n = _frac(items, pred)
        t.append(Target(name, value, n, thr, upper))
    return t


def confusion(outcomes) -> dict[str, dict[str, int]]:
    table: dict[str, Counter] = {}
    for o in outcomes:
        table.setdefault(o.cls, Counter())[o.predicted] += 1
    return {k: dict(sorted(v.items())) for k, v in table.items()}


def ooc_table(outcomes) -> dict[str, dict[str, int]]:
    return confusion([o for o in outcomes if o.out_of_catalogue])


@dataclass(frozen=True)
class BenchmarkReport:
    outcomes: tuple[Outcome, ...]
    seed: int
    n_per_class: int
    families: tuple[int, ...]
    elapsed_s: float

    def of(self, family: int) -> list[Outcome]:
        return [o for o in self.outcomes if o.family == family]

    def targets(self) -> dict[int, list[Target]]:
        return {f: family_targets(self.of(f)) for f in self.families}

    @property
    def meets_targets(self) -> bool:
        return all(t.status != "MISS" for ts in self.targets().values() for t in ts)

    def summary(self) -> str:
        targets = self.targets()
        errors = [o for o in self.outcomes if o.verdict == "error"]
        lines = [f"benchmark-diagnose: {len(self.outcomes)} concealed recordings ({self.n_per_class} per class, "
                 f"families {', '.join(map(str, self.families))}, seed {self.seed}), {self.elapsed_s:.1f} s"
                 + (f"; {len(errors)} diagnosis errors (scored as misses)" if errors else "")]
        head = f"  {'target':<54s}" + "".join(f" {'family ' + str(f):<26s}" for f in self.families)
        lines.append(head)
        names = [t.name for t in next(iter(targets.values()))]
        for i, name in enumerate(names):
            lines.append(f"  {name:<54s}" + "".join(f" {targets[f][i].cell():<26s}" for f in self.families))
        for f in self.families:
            outs = self.of(f)
            errs = [abs(o.loss_error) for o in outs
                    if not o.cha and o.loss_error is not None and o.snr >= SNR_SCORED]
            secs = [o.seconds for o in outs]
            lines.append(f"  family {f}: median |loss error| {100 * float(np.median(errs)) if errs else math.nan:.1f} %"
                         f" ({len(errs)} loops with an estimate); mean time per recording "
                         f"{float(np.mean(secs)) if secs else 0.0:.2f} s")
            # the error bar's honesty: the truth inside 3 reported standard errors, and the loss misses the
            # diagnosis itself said it could not fix to 10 %
            loops = [o for o in outs if not o.cha and o.loss_within_3se is not None and o.snr >= SNR_SCORED]
            if loops:
                misses = [o for o in loops if not o.loss_ok]
                lines.append(f"  family {f}: loss inside 3 reported standard errors "
                             f"{sum(o.loss_within_3se for o in loops)}/{len(loops)}; loss misses the text called "
                             f"imprecise (SE > 10 %) {sum(o.loss_flagged_imprecise for o in misses)}/{len(misses)}")
            lines.append(f"  confusion, family {f} (class -> verdict / named set, ? = ambiguous):")
            for cls, row in confusion([o for o in outs if not o.cha and not o.out_of_catalogue]).items():
                lines.append(f"    {cls:<34s} " + ", ".join(f"{k}: {v}" for k, v in row.items()))
            ooc = ooc_table(outs)
            if ooc:
                lines.append(f"  out of catalogue, family {f} (label -> verdict / named set):")
                for cls, row in ooc.items():
                    lines.append(f"    {cls:<34s} " + ", ".join(f"{k}: {v}" for k, v in row.items()))
            cha = [o for o in outs if o.cha]
            if cha:
                lines.append(f"  CHA table, family {f}: named set, K1/K2/K3 error %, loss error %")
                for o in cha:
                    ks = " ".join(f"{100 * e:+6.1f}" for e in o.stiffness_errors)
                    le = f"{100 * o.loss_error:+6.1f}" if o.loss_error is not None else "   -  "
                    lines.append(f"    {o.name:<22s} {o.predicted:<40s} {ks} {le}")
        lines.append(f"  targets met: {'yes' if self.meets_targets else 'NO'}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """Plain JSON-able data (NaN, e.g. a target with no recordings, becomes null)."""
        out = {"seed": self.seed, "n_per_class": self.n_per_class, "families": list(self.families),
               "elapsed_s": self.elapsed_s, "meets_targets": self.meets_targets, "family": {}}
        for f, ts in self.targets().items():
            outs = self.of(f)
            out["family"][str(f)] = {
                "targets": [dict(asdict(t), status=t.status) for t in ts],
                "confusion": confusion([o for o in outs if not o.cha and not o.out_of_catalogue]),
                "out_of_catalogue": ooc_table(outs),
                "outcomes": [dict(asdict(o), predicted=o.predicted, primary_ok=o.primary_ok, set_ok=o.set_ok,
                                  loss_error=o.loss_error) for o in outs]}
        return json_ready(out)


def _quantity(diag, effect, name: str) -> float | None:
    """A reported quantity: the Diagnosis contract first, else the named model's parameter ``name``."""
    try:
        v = diag.quantity(name)
    except (KeyError, ValueError):
        v = None
    if v is not None:
        return float(v)
    if effect is None:
        return None
    for key, (value, _unit) in effect.parameters.items():
        if key == name or key.endswith("." + name):
            return float(value)
    return None


def diagnose_concealed(c: Concealed, name: str, default_params) -> Outcome:
    """Diagnose one concealed recording from its file text only, and score it against its truth."""
    from strainwave.params import load_params
    from strainwave.compare.diagnose.pipeline import diagnose
    rec = parse_text(c.text, f"{name}.csv")
    params = load_params(overrides=rec.param_overrides) if rec.param_overrides else default_params
    t = time.perf_counter()
    try:
        diag, _ = diagnose(rec, params)
    except Exception as exc:       # a crash of the model under test is a scored miss, not a benchmark crash
        return Outcome(c.family, name, c.name, c.truth, c.out_of_catalogue, c.noise, c.snr, rec.n, "error", (),
                       False, c.loss_arcmin, None, c.stiffness_Nmm_per_rad, None, math.nan, math.nan, math.nan,
                       time.perf_counter() - t, f"{type(exc).__name__}: {exc}")
    dt = time.perf_counter() - t
    named = tuple(diag.named)
    effect = next((e for e in diag.effects if tuple(e.components) == named), diag.effects[0] if diag.effects else None)
    effect = effect if named else None
    loss = _quantity(diag, effect, "hysteresis_loss_arcmin") if "hysteresis" in named else None
    loss_se = _quantity(diag, None, "hysteresis_loss_std_error_arcmin") if loss is not None else None
    stiff = None
    if c.stiffness_Nmm_per_rad is not None:
        stiff = tuple(_quantity(diag, effect, k) for k in ("K1", "K2", "K3"))
    return Outcome(c.family, name, c.name, c.truth, c.out_of_catalogue, c.noise, c.snr, rec.n,
                   diag.verdict.value, named, bool(diag.ambiguous), c.loss_arcmin, loss, c.stiffness_Nmm_per_rad,
                   stiff, diag.rms_before, diag.rms_after, diag.noise_std, dt, loss_std_error_arcmin=loss_se,
                   events=tuple(diag.events))


def concealed_recordings(family: int, n_per_class: int, seed: int, params, *, rows=None, classes=None,
                         cha: int | None = None):
    """Yield (name, Concealed) for one family: ``n_per_class`` of each class, then the CHA rows."""
    rng = np.random.default_rng([seed, family])
    table = None
    for cls in classes or CLASSES[family]:
        for i in range(n_per_class):
            if family == 1:
                if table is None and cls in ("large_deflection", "clean_ring", "clean_ring_coloured"):
                    from strainwave.compare.diagnose.generators.hifi_ring import elastica_curve
                    table = elastica_curve(max_delta_over_R=0.3, n=25)
                c = gen1.generate(cls, rng, params, rows=rows or (200, 2000), elastica_table=table)
            else:
                c = gen2.generate(cls, rng, params, rows=rows or (300, 2000))
            yield f"f{family}-{cls}-{i:03d}", c
    all_rows = cha_rows()
    picked = all_rows if cha is None else all_rows[::max(1, len(all_rows) // max(cha, 1))][:cha]
    for row in picked:
        for loop in (False, True):
            tag = f"f{family}-CHA-{row.size}-{row.ratio.replace('>', 'gt')}{'-loop' if loop else ''}"
            if family == 1:
                text = cha_recording_f1(row, hysteresis=loop)
                truth = ("nonlinear_stiffness", "hysteresis") if loop else ("nonlinear_stiffness",)
                loss = 0.8 * row.hysteresis_limit_arcmin if loop else None
                c = Concealed("cha+loop" if loop else "cha", text, truth, 0.0, "torsion", family=1,
                              loss_arcmin=loss,
                              stiffness_Nmm_per_rad=(row.K1_Nmm_per_rad, row.K2_Nmm_per_rad, row.K3_Nmm_per_rad))
            else:
                c = gen2.cha_recording(row, loop=loop, rng=rng)
            yield tag, c


def run_benchmark(n_per_class: int = 10, seed: int = 0, out_dir: Path | None = None, *,
                  families: tuple[int, ...] = FAMILIES, rows: tuple[int, int] | None = None,
                  classes: dict[int, tuple[str, ...]] | None = None, cha: int | None = None,
                  progress=None) -> BenchmarkReport:
    """Generate and diagnose every family's recordings blind, score, and write text + JSON to ``out_dir``.

    ``cha``: number of CHA table rows per family (None = all 21), each with and without a loop."""
    if n_per_class < 1:
        raise ValueError("n_per_class must be >= 1")
    if not families or any(f not in FAMILIES for f in families):
        raise ValueError(f"families must be a non-empty subset of {FAMILIES}")
    from strainwave.params import load_params
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)   # thick rims are outside seed 003's range on purpose
        params = load_params()
        outcomes = []
        for f in families:
            for name, c in concealed_recordings(f, n_per_class, seed, params, rows=rows,
                                                classes=(classes or {}).get(f), cha=cha):
                outcomes.append(diagnose_concealed(c, name, params))
                if progress is not None:
                    progress(outcomes[-1])
    report = BenchmarkReport(tuple(outcomes), seed, n_per_class, tuple(families), time.perf_counter() - t0)
    if out_dir is not None:
        out_dir = Path(out_dir)
        atomic_write_text(out_dir / "benchmark_diagnose.json", json.dumps(report.to_dict(), indent=2, allow_nan=False) + "\n")
        atomic_write_text(out_dir / "benchmark_diagnose.txt", report.summary() + "\n")
    return report


__all__ = ["BenchmarkReport", "Outcome", "Target", "concealed_recordings", "confusion", "diagnose_concealed",
           "family_targets", "ooc_table", "run_benchmark"]
