"""Step 7 (explanation): the picture: data, baseline, augmented model (top) and residuals before/after (bottom).

Uses matplotlib's object API with the Agg canvas (no pyplot state, no display) and writes atomically.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from strainwave.io_atomic import atomic_path


def plot_diagnosis(path: Path, *, load: np.ndarray, response: np.ndarray, baseline: np.ndarray,
                   augmented: np.ndarray, load_label: str, response_label: str, title: str,
                   model_label: str) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 7.0), dpi=110)
    FigureCanvasAgg(fig)
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    step = max(1, len(load) // 4000)   # keep the PNG light for long recordings
    top.plot(load[::step], response[::step], ".", ms=2, color="0.45", label="recording")
    top.plot(load, baseline, "-", lw=1.0, color="tab:blue", label="baseline (+ offsets)")
    top.plot(load, augmented, "-", lw=1.2, color="tab:red", label=model_label)
    top.set_ylabel(response_label)
    top.set_title(title.replace("$", r"\$"), fontsize=10)   # a file name's $...$ is text, not math
    top.legend(loc="best", fontsize=8)
    bottom.plot(load[::step], (response - baseline)[::step], ".", ms=2, color="tab:blue", label="residual, baseline")
    bottom.plot(load[::step], (response - augmented)[::step], ".", ms=2, color="tab:red", label="residual, augmented")
    bottom.axhline(0.0, color="k", lw=0.6)
    bottom.set_xlabel(load_label)
    bottom.set_ylabel("residual")
    bottom.legend(loc="best", fontsize=8)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path
