"""What a sweep leaves behind: a tidy table (Parquet + CSV), plots of each output against each varied
input, and a Markdown summary naming where the closed forms depart from FEA by more than a tolerance.

Tidy means one row per (point, FEA quantity): the varied inputs, the FEA value and its uncertainty,
the published and corrected closed forms beside it, and their relative errors ``(fea - ref) / |ref|``
(the closed form is the reference, as in validate's checks). A failed point is one row with its error
message and no quantity.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd

from strainwave.io_atomic import atomic_path, atomic_write_text

VARIANTS = ("published", "corrected")
MAX_LINES = 8        # lines per plot: more values of the second input would not be readable
MAX_LISTED = 20      # departures listed one by one in the Markdown summary


def _rel(analytic, fea) -> float:
    """(fea - ref) / |ref|, the closed form as reference: the relative error validate reports."""
    if analytic is None or fea is None or not math.isfinite(float(analytic)) or float(analytic) == 0:
        return math.nan
    return (fea - float(analytic)) / abs(float(analytic))


# each design factor's closed-form n at the point (compare/sweep/task.design_n)
N_COLUMNS = ("ring", "cup_tooth_root", "wg_inner_ring", "wg_outer_ring", "cup_diaphragm")


def records_frame(records: list[dict], varied: list[str]) -> pd.DataFrame:
    """The tidy table of a sweep, one row per (point, quantity), in point order."""
    rows = []
    for rec in records:
        head = {"point": rec["index"], "status": rec["status"], "error": rec.get("error"),
                "cached": rec.get("cached", False), "elapsed_s": rec.get("elapsed_s"), "dofs": rec.get("dofs")}
        head.update({key: rec["inputs"].get(key) for key in varied})
        head.update({f"n_{name}": (rec.get("design_n") or {}).get(name) for name in N_COLUMNS})
        if rec["status"] != "ok" or not rec.get("fea"):
            rows.append({**head, "quantity": None})
            continue
        for name, q in rec["fea"].items():
            beside = rec.get("analytic", {}).get(name, {})
            row = {**head, "quantity": name, "unit": q["unit"], "fea": q["value"],
                   "fea_uncertainty": q.get("uncertainty"), "analytic_key": beside.get("key")}
            for variant in VARIANTS:
                row[variant] = beside.get(variant)
                row[f"{variant}_rel_error"] = _rel(beside.get(variant), q["value"])
            rows.append(row)
    columns = (["point", "status", "error", "cached", "elapsed_s", "dofs", *varied,
                *(f"n_{name}" for name in N_COLUMNS), "quantity", "unit", "fea",
                "fea_uncertainty", "analytic_key"] + [c for v in VARIANTS for c in (v, f"{v}_rel_error")])
    frame = pd.DataFrame(rows, columns=columns)
    for col in ("fea", "fea_uncertainty", "elapsed_s", *(f"n_{n}" for n in N_COLUMNS), *VARIANTS, *(f"{v}_rel_error" for v in VARIANTS)):
        frame[col] = pd.to_numeric(frame[col], errors="coerce")
    return frame


def write_table(frame: pd.DataFrame, out_dir: Path) -> list[Path]:
    parquet, csv = Path(out_dir) / "sweep.parquet", Path(out_dir) / "sweep.csv"
    with atomic_path(parquet) as tmp:
        frame.to_parquet(tmp, index=False)
    atomic_write_text(csv, frame.to_csv(index=False))
    return [parquet, csv]


def write_records(records: list[dict], out_dir: Path) -> Path:
    """Every record in full (warnings, hosts, timings): what the table flattens."""
    return atomic_write_text(Path(out_dir) / "points.json", json.dumps(records, indent=1, default=str) + "\n")


def _slug(text: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in text).strip("_")


def import_plotting() -> None:
    """Load matplotlib (Agg) and pyplot while the workers start, not after the points, where ``plot_sweep``
    would pay it (docs/decisions/013-sweep-worker-start-up.md)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot  # noqa: F401


def plot_sweep(frame: pd.DataFrame, varied: list[str], out_dir: Path, *, lines: bool = True,
               value_label: str = "FEA") -> list[Path]:
    """One PNG per (quantity, varied input): FEA solid, published dashed, corrected dotted; one colour per
    value of a second varied input. Further inputs are held at their first value. ``lines=False`` draws
    markers only (sample files are not grids)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = frame[frame["status"].eq("ok") & frame["quantity"].notna()]
    written = []
    for quantity, rows in ok.groupby("quantity", sort=True):
        unit = rows["unit"].iloc[0]
        for x in varied:
            # A grid: colours per value of a second input, the remaining inputs held at their first value.
            # Sample rows are no grid: all points in one colour.
            others = [k for k in varied if k != x] if lines else []
            second = others[0] if others else None
            held = rows
            for key in others[1:]:
                held = held[held[key] == held[key].iloc[0]]
            groups = list(held.groupby(second, sort=True)) if second else [(None, held)]
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            style = "-o" if lines else "o"
            for color_index, (value, group) in enumerate(groups[:MAX_LINES]):
                group = group.sort_values(x)
                color = f"C{color_index}"
                label = value_label if second is None else f"{value_label}, {second} = {value:g}" if isinstance(
                    value, (int, float)) else f"{value_label}, {second} = {value}"
                ax.plot(group[x], group["fea"], style, color=color, label=label)
                for variant, dash in (("published", "--"), ("corrected", ":")):
                    if group[variant].notna().any():
                        ax.plot(group[x], group[variant], dash if lines else "x", color=color,
                                label=variant if color_index == 0 else None)
            ax.set_xlabel(x)
            ax.set_ylabel(f"{quantity} [{unit}]")
            held_text = ", ".join(f"{k} = {held[k].iloc[0]}" for k in others[1:])
            ax.set_title(quantity + (f"\n({held_text})" if held_text else ""), fontsize=9)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
            fig.tight_layout()
            target = Path(out_dir) / "plots" / f"{_slug(quantity)}__vs__{_slug(x)}.png"
            with atomic_path(target) as tmp:
                fig.savefig(tmp, format="png", dpi=110)
            plt.close(fig)
            written.append(target)
    return written


def departures(frame: pd.DataFrame, varied: list[str], tolerance: float) -> list[str]:
    """One line per (quantity, closed-form variant) whose relative error exceeds ``tolerance`` somewhere,
    naming how often, the worst case and the input ranges where it happens."""
    lines = []
    ok = frame[frame["status"].eq("ok") & frame["quantity"].notna()]
    for quantity, rows in ok.groupby("quantity", sort=True):
        for variant in VARIANTS:
            err = rows[f"{variant}_rel_error"]
            if err.isna().all():
                continue
            beyond = rows[err.abs() > tolerance]
            if beyond.empty:
                lines.append(f"{quantity}: {variant} within {tolerance:.3g} of FEA at all {err.notna().sum()} points "
                             f"(worst {err.abs().max():+.3g})")
                continue
            worst = beyond.loc[beyond[f"{variant}_rel_error"].abs().idxmax()]
            where = ", ".join(f"{k} in [{beyond[k].min():g}, {beyond[k].max():g}]" if pd.api.types.is_numeric_dtype(
                beyond[k]) else f"{k} in {sorted(set(beyond[k]))}" for k in varied)
            lines.append(f"{quantity}: {variant} departs by more than {tolerance:.3g} at {len(beyond)}/{err.notna().sum()}"
                         f" points ({where}); worst {worst[f'{variant}_rel_error']:+.3g} at point {int(worst['point'])}")
    return lines


def write_markdown(frame: pd.DataFrame, varied: list[str], tolerance: float, header: dict, out_dir: Path) -> Path:
    text = [f"# Sweep of `{header['study']}`", ""]
    text += [f"- {k}: {v}" for k, v in header.items() if k != "study"]
    text += ["", f"## Closed forms against FEA (relative tolerance {tolerance:.3g})", ""]
    named = departures(frame, varied, tolerance)
    text += [f"- {line}" for line in named] or ["- no FEA quantity of this study has a closed form beside it"]
    ok = frame[frame["status"].eq("ok") & frame["quantity"].notna()]
    listed = []
    for variant in VARIANTS:
        bad = ok[ok[f"{variant}_rel_error"].abs() > tolerance]
        for _, row in bad.iterrows():
            listed.append(f"| {int(row['point'])} | " + " | ".join(f"{row[k]}" for k in varied) +
                          f" | {row['quantity']} | {variant} | {row['fea']:.6g} | {row[variant]:.6g} | "
                          f"{row[f'{variant}_rel_error']:+.3g} |")
    if listed:
        text += ["", "| point | " + " | ".join(varied) + " | quantity | variant | FEA | closed form | rel. error |",
                 "|" + "---|" * (len(varied) + 6)] + listed[:MAX_LISTED]
        if len(listed) > MAX_LISTED:
            text.append(f"\n... and {len(listed) - MAX_LISTED} more rows in sweep.csv")
    failed = frame[frame["status"].ne("ok")]
    text += ["", f"## Failed points ({len(failed)})", ""]
    for _, row in failed.iterrows():
        inputs = ", ".join(f"{k} = {row[k]}" for k in varied)
        text.append(f"- point {int(row['point'])} ({inputs}): {row['error']}")
    return atomic_write_text(Path(out_dir) / "summary.md", "\n".join(text) + "\n")
