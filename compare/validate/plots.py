"""Report plots with matplotlib's Agg backend (no display): convergence, crack sweeps, the ring's mid-layer.

Each function takes plain arrays and writes one PNG through a temporary name.
"""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from strainwave.io_atomic import atomic_write_bytes
from strainwave.compare.validate.ring_shape import radial_displacement_mm


def nice_scale(raw: float) -> float:
    """The largest of 1, 2, 5 x 10^k not above ``raw`` (an exaggeration factor a reader can use)."""
    exponent = np.floor(np.log10(raw))
    mantissa = raw / 10 ** exponent
    return float((5.0 if mantissa >= 5 else 2.0 if mantissa >= 2 else 1.0) * 10 ** exponent)


LEGEND_BELOW_IN = 0.5     # a legend under the axes: its top this far below the axes' bottom (ticks, x label)


def _figure(width: float = 7.0, height: float = 4.5):
    """A figure of fixed size laid out by constrained layout (it makes room for every label and legend)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    from matplotlib.figure import Figure  # a Figure without pyplot keeps no global state

    return Figure(figsize=(width, height), dpi=110, facecolor="white", layout="constrained")


def _save(fig, png: Path) -> Path:
    """One draw (constrained layout runs inside it) encoded as PNG: ``savefig`` would draw twice."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    buffer = io.BytesIO()
    Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3]).save(buffer, format="PNG")
    return atomic_write_bytes(png, buffer.getvalue())


def _legend_below(ax, **kwargs) -> list[str]:
    """``legend_of_shown`` under the axes, LEGEND_BELOW_IN below them whatever the axes' size."""
    from matplotlib.transforms import ScaledTranslation

    below = ax.transAxes + ScaledTranslation(0.0, -LEGEND_BELOW_IN, ax.figure.dpi_scale_trans)
    return legend_of_shown(ax, loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=below,
                           borderaxespad=0.0, **kwargs)


def convergence_plot(png: Path, **kwargs) -> Path:
    """``convergence_figure`` written to ``png``."""
    return _save(convergence_figure(**kwargs), png)


def convergence_figure(*, title: str, unit: str, h_mm, values, extrapolated: float, gci_fine: float,
                       observed_order: float, analytic: dict[str, float] | None = None,
                       flags: tuple[str, ...] = ()):
    """Left: the FEA against element size on its own y-scale (Richardson value at h = 0, GCI band on the fine
    value). Right: the fine FEA value with its GCI band beside the closed forms, each labelled with its number
    and its difference from the FEA (a closed form far away would otherwise flatten the FEA points). ``flags``:
    why the meshes are not in the asymptotic range (gci_table.asymptotic_flags), said on the left panel."""
    fig = _figure(10.0, 4.2)
    ax, cmp_ax = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    h = np.asarray(h_mm, dtype=float)
    v = np.asarray(values, dtype=float)
    fine = float(v[np.argmin(h)])
    refused = not np.isfinite(gci_fine)         # three identical values: no band is drawn, none is claimed
    band = 0.0 if refused else abs(gci_fine * fine)
    ax.plot(h, v, "o-", color="tab:blue", label="FEA (three refinements)")
    if np.isfinite(extrapolated):
        ax.plot([0.0], [extrapolated], "s", color="tab:blue", mfc="white",
                label=f"Richardson extrapolated (p = {observed_order:.2f})")
    ax.errorbar([h.min()], [fine], yerr=[band], color="tab:red", capsize=5, label="GCI refused (identical values)" if refused else f"GCI fine = {100 * gci_fine:.3g} %")
    ax.set_xlim(left=-0.05 * h.max())
    ax.set_xlabel("element size h (mm)")
    ax.set_ylabel(unit)
    ax.set_title("FEA on three meshes (own scale)" + ("\nnot asymptotic: " + ", ".join(flags) if flags else ""),
                 fontsize=10, color="firebrick" if flags else "black")
    ax.grid(True, alpha=0.3)
    legend_of_shown(ax, fontsize=8)
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useOffset=False)
    styles = {"published": "tab:orange", "corrected": "tab:green"}
    names, numbers, colors = ["FEA (fine)"], [fine], ["tab:blue"]
    for variant, value in (analytic or {}).items():
        if value is not None and np.isfinite(value):
            names.append(f"{variant}")
            numbers.append(float(value))
            colors.append(styles.get(variant, "gray"))
    y = np.arange(len(names))[::-1]
    cmp_ax.barh(y, numbers, color=colors, alpha=0.8)
    cmp_ax.errorbar([fine], [y[0]], xerr=[band], fmt="none", ecolor="tab:red", capsize=5)   # the GCI band
    for yi, name, value in zip(y, names, numbers):
        diff = "" if name.startswith("FEA") or fine == 0 else f" (FEA {100 * (fine - value) / value:+.3g} %)"
        cmp_ax.annotate(f"{value:.5g}{diff}", (0, yi), xytext=(4, 0), textcoords="offset points", va="center",
                        fontsize=8, color="black")
    cmp_ax.set_yticks(y, names)
    cmp_ax.set_xlabel(unit)
    cmp_ax.set_title("fine FEA vs closed forms")
    cmp_ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle(title, fontsize=11)
    return fig


def _line_shown(line, log_y: bool) -> bool:
    x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
    ok = np.isfinite(x) & np.isfinite(y) & ((y > 0) if log_y else True)
    drawn_line = line.get_linestyle() not in ("None", "", " ") and ok.sum() >= 2
    return bool(drawn_line or line.get_marker() not in ("None", "", " ", None) and ok.any())


def _shown(artist, log_y: bool) -> bool:
    """Whether a legend entry's artist draws anything: a line of two finite points or a marker on one (positive on
    a log axis); error bars by their data line or a finite bar. Anything else (bars, patches) is kept."""
    if hasattr(artist, "lines"):        # ErrorbarContainer: (data line, caplines, barlinecols)
        data, _, bar_cols = artist.lines
        bars = [seg for col in bar_cols for seg in col.get_segments()]
        finite_bar = any(np.isfinite(seg).all() and (not log_y or (seg[:, 1] > 0).all()) for seg in bars)
        return (data is not None and _line_shown(data, log_y)) or finite_bar
    if hasattr(artist, "get_ydata"):
        return _line_shown(artist, log_y)
    return True


def legend_of_shown(ax, **kwargs):
    """A legend of only the entries that draw something on ``ax`` (issue 40: an entry never shown is dropped)."""
    handles, labels = ax.get_legend_handles_labels()
    log_y = ax.get_yscale() == "log"
    kept = [(h, lb) for h, lb in zip(handles, labels) if _shown(h, log_y)]
    if kept:
        ax.legend(*zip(*kept), **kwargs)
    return [lb for _, lb in kept]


def crack_sweep_plot(png: Path, **kwargs) -> Path:
    """``crack_sweep_figure`` written to ``png``."""
    return _save(crack_sweep_figure(**kwargs), png)


def crack_sweep_figure(*, title: str, unit: str, depths_mm, fea, fea_uncertainty,
                       curves: dict[str, tuple[np.ndarray, np.ndarray]], fit_label: str = "", log_y: bool = True,
                       styles: dict[str, tuple[str, str]] | None = None, curve_suffix: str = " closed form"):
    """The swept quantity against crack depth (log-log, or a linear y with ``log_y`` False): FEA points with
    error bars against each closed form's curve (marked at every depth, so a one-depth sweep shows them too).
    FEA values a log axis cannot show (<= 0) are said in a note, never as an empty legend entry."""
    fig = _figure(7.0, 5.4)     # the legend below takes about 1 inch of it
    ax = fig.add_subplot(1, 1, 1)
    a = np.asarray(depths_mm, dtype=float)
    y = np.asarray(fea, dtype=float)
    err = np.nan_to_num(np.asarray(fea_uncertainty, dtype=float))
    shown = y > 0 if log_y else np.isfinite(y)
    bars = np.minimum(err[shown], 0.999 * y[shown]) if log_y else err[shown]
    ax.errorbar(a[shown], y[shown], yerr=bars, fmt="o", color="tab:blue", capsize=3, zorder=3,
                label="FEA (GCI bars)" + (f", {fit_label}" if fit_label else ""))
    if np.any(~shown):
        ax.text(0.02, 0.02, f"FEA <= 0 (unresolved) at a = {', '.join(f'{d:g}' for d in a[~shown])} mm: not on a "
                "log axis", transform=ax.transAxes, fontsize=8, color="tab:blue")
    styles = {"published": ("--s", "tab:orange"), "corrected": ("-^", "tab:green"), **(styles or {})}
    others = iter((("-.d", "gray"), (":v", "tab:purple"), ("--p", "tab:brown"), ("-.h", "tab:olive")) * 4)
    for name, (xa, ya) in curves.items():
        style, color = styles[name] if name in styles else next(others)   # every curve its own marker
        # open markers larger than the FEA's: a curve on top of the FEA point still shows around it
        ax.plot(xa, ya, style, color=color, label=f"{name}{curve_suffix}", mfc="none", ms=11, mew=1.5)
    ax.set_xscale("log")
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel("crack depth a (mm)")
    ax.set_ylabel(unit)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    _legend_below(ax, fontsize=8)   # below: hides no point
    return fig


def ring_midlayer_plot(png: Path, *, r_m_mm: float, theta, u_r_fea, delta_cd_fea: float, delta_ab_fea: float,
                       delta_cd_analytic: float, delta_ab_analytic: float, load_angle_rad: float) -> Path:
    """The ring's deformed mid-layer, FEA against the thin-ring shape, radial displacements exaggerated."""
    u_max = max(np.max(np.abs(u_r_fea)), abs(delta_cd_analytic) / 2, 1e-30)
    scale = nice_scale(0.2 * r_m_mm / u_max)
    fig = _figure(6.0, 6.6)
    ax = fig.add_subplot(1, 1, 1)
    t = np.linspace(0, 2 * np.pi, 721)
    ax.plot(r_m_mm * np.cos(t), r_m_mm * np.sin(t), color="lightgray", lw=1, label="undeformed mid-layer")
    r_an = r_m_mm + scale * radial_displacement_mm(t, delta_cd_analytic, load_angle_rad)
    ax.plot(r_an * np.cos(t), r_an * np.sin(t), "--", color="tab:green",
            label=f"thin ring (eqs 3-4): dCD {delta_cd_analytic:.4g}, dAB {delta_ab_analytic:.4g} mm")
    order = np.argsort(theta)
    th = np.append(np.asarray(theta)[order], np.asarray(theta)[order][0] + 2 * np.pi)
    ur = np.append(np.asarray(u_r_fea)[order], np.asarray(u_r_fea)[order][0])
    r_fea = r_m_mm + scale * ur
    ax.plot(r_fea * np.cos(th), r_fea * np.sin(th), color="tab:blue",
            label=f"FEA: dCD {delta_cd_fea:.4g}, dAB {delta_ab_fea:.4g} mm")
    for angle, name in ((load_angle_rad, "D"), (load_angle_rad + np.pi, "C"),
                        (load_angle_rad + np.pi / 2, "A"), (load_angle_rad - np.pi / 2, "B")):
        ax.annotate(name, (1.12 * r_m_mm * np.cos(angle), 1.12 * r_m_mm * np.sin(angle)), ha="center",
                    va="center", fontsize=12, fontweight="bold")
    for angle in (load_angle_rad, load_angle_rad + np.pi / 2):
        ax.plot([-r_m_mm * np.cos(angle), r_m_mm * np.cos(angle)], [-r_m_mm * np.sin(angle),
                r_m_mm * np.sin(angle)], ":", color="gray", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlim(-1.3 * r_m_mm, 1.3 * r_m_mm)
    ax.set_ylim(-1.3 * r_m_mm, 1.3 * r_m_mm)
    ax.set_title(f"ring mid-layer r_m = {r_m_mm:.4g} mm, radial displacement x {scale:g}")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    _legend_below(ax, fontsize=8)
    return _save(fig, png)
