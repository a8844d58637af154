"""Step 6 (location): where is the mismatch? Ranges of the load and the branches on which the residual is significant.

The baseline-fit residual is averaged in 20 load bins separately for each branch (loading/unloading x
positive/negative load). A bin is significant when its mean exceeds 3 sigma/sqrt(n) (3 standard errors)
and half the largest bin mean, so a strong effect is not reported as "everywhere" because of
its tails. ``peak_at`` is the load of the largest deviation.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.effects.base import Context

N_BINS = 20


@dataclass(frozen=True)
class Located:
    variable: str
    ranges: tuple[tuple[float, float], ...]
    branch: str
    description: str
    peak_at: float | None = None

    def to_dict(self) -> dict:
        return {"variable": self.variable, "ranges": [list(r) for r in self.ranges], "branch": self.branch,
                "description": self.description, "peak_at": self.peak_at}


def locate(ctx: Context, residual: np.ndarray, sigma: float, variable: str, mismatch: bool) -> Located:
    """Significant load ranges (physical units) and a branch label; empty when there is no mismatch."""
    if not mismatch:
        return Located(variable, (), "none", "no residual beyond the noise and the baseline uncertainty")
    edges = np.linspace(ctx.u.min(), ctx.u.max(), N_BINS + 1)
    idx = np.clip(np.digitize(ctx.u, edges) - 1, 0, N_BINS - 1)
    loading = ctx.direction * np.sign(ctx.u) >= 0
    groups = {("loading", "positive"): loading & (ctx.u >= 0), ("unloading", "positive"): ~loading & (ctx.u >= 0),
              ("loading", "negative"): loading & (ctx.u < 0), ("unloading", "negative"): ~loading & (ctx.u < 0)}
    means = {}
    for key, mask in groups.items():
        for b in range(N_BINS):
            sel = mask & (idx == b)
            cnt = int(sel.sum())
            if cnt >= 2:
                means[(key, b)] = (float(residual[sel].mean()), cnt)
    if not means:
        return Located(variable, (), "none", "too few samples per load bin to locate the residual")
    peak = max(abs(m) for m, _ in means.values())
    hits = {(key, b): m for (key, b), (m, cnt) in means.items()
            if abs(m) > 3.0 * sigma / np.sqrt(cnt) and abs(m) >= 0.5 * peak}
    bins = sorted({b for (_, b) in hits})
    ranges = []
    for b in bins:
        lo, hi = edges[b] * ctx.X, edges[b + 1] * ctx.X
        if ranges and abs(ranges[-1][1] - lo) < 1e-12 * ctx.X:
            ranges[-1] = (ranges[-1][0], hi)
        else:
            ranges.append((lo, hi))
    dirs = sorted({k[0] for (k, _) in hits})
    signs = sorted({k[1] for (k, _) in hits})
    direction = dirs[0] if len(dirs) == 1 else "loading and unloading"
    sign = f"{signs[0]} load" if len(signs) == 1 else "both load signs"
    branch = f"{direction}, {sign}" if hits else "none"
    (pk, pb), pm = max(hits.items(), key=lambda kv: abs(kv[1])) if hits else ((None, 0), 0.0)
    where = ", ".join(f"[{lo:.4g}, {hi:.4g}]" for lo, hi in ranges)
    desc = (f"residual significant for {variable} in {where} {ctx.load_unit} ({branch}); largest mean deviation "
            f"{pm * ctx.Y:.3g} {ctx.response_unit} = {abs(pm) / sigma:.1f} x noise near {variable} = "
            f"{0.5 * (edges[pb] + edges[pb + 1]) * ctx.X:.4g} {ctx.load_unit}" if hits
            else "mismatch spread thinly over the whole range (no single bin stands out)")
    peak_at = float(0.5 * (edges[pb] + edges[pb + 1]) * ctx.X) if hits else None
    return Located(variable, tuple(ranges), branch, desc, peak_at)


def locate_effect(ctx: Context, effects, thetas, binned: Located, variable: str) -> Located:
    """Where the fitted effect acts (knee above T1, the open side of a crack, the band of a backlash), in
    physical units, cross-checked with the binned residual of the baseline fit: the description says
    whether the residual's significant bins fall inside the effect's ranges."""
    ranges, texts = [], []
    for e, th in zip(effects, thetas):
        if e.where is None:
            texts.append(f"{e.id}: whole load range" + (", branch-dependent" if e.loop else ""))
            ranges.append((float(ctx.u.min()), float(ctx.u.max())))
            continue
        rr, text = e.where(ctx, np.asarray(th))
        ranges.extend(rr)
        where = ", ".join(f"[{lo * ctx.X:.4g}, {hi * ctx.X:.4g}]" for lo, hi in rr)
        texts.append(f"{e.id}: {variable} in {where} {ctx.load_unit} ({text})")
    phys = tuple((lo * ctx.X, hi * ctx.X) for lo, hi in _merge(ranges))
    if binned.ranges:
        inside = all(any(lo - 0.1 * ctx.X <= b_lo and b_hi <= hi + 0.1 * ctx.X for lo, hi in phys)
                     for b_lo, b_hi in binned.ranges)
        check = ("the binned residual agrees (its significant bins lie in these ranges)" if inside
                 else "the binned residual is significant also outside them ("
                 + ", ".join(f"[{lo:.4g}, {hi:.4g}]" for lo, hi in binned.ranges) + ")")
    else:
        check = "no single bin of the binned residual stands out"
    branch = "; ".join(t.split("(", 1)[1].rstrip(")") if "(" in t else t for t in texts)
    return Located(variable, phys, branch, "; ".join(texts) + "; " + check, binned.peak_at)


def _merge(ranges):
    out = []
    for lo, hi in sorted(ranges):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out
