"""report.pdf is printed wherever the output folder sits: Chromium puts its singleton socket under TMPDIR, and a
deep output folder's scratch space (TMPDIR during a run) passed the 108-byte limit of a socket path."""
from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest

from strainwave.compare.validate.report_pdf import chromium, print_pdf


@pytest.mark.skipif(chromium() is None, reason="no Chromium (.ci/run installs it)")
def test_a_pdf_is_printed_under_a_deep_temporary_folder(tmp_path, monkeypatch):
    deep = tmp_path / ("d" * 60) / ("e" * 60)
    deep.mkdir(parents=True)
    monkeypatch.setenv("TMPDIR", str(deep))
    html = tmp_path / "page.html"
    html.write_text("<html><body><h1>strainwave</h1></body></html>", encoding="utf-8")
    pdf = print_pdf(html, tmp_path / "page.pdf")
    assert pdf.read_bytes().startswith(b"%PDF")


def _undated(pdf: bytes) -> bytes:
    return re.sub(rb"/(Creation|Mod)Date \(D:[^)]*\)", b"", pdf)


@pytest.mark.skipif(chromium() is None, reason="no Chromium (.ci/run installs it)")
def test_printing_without_3d_apis_gives_the_same_pdf(tmp_path, monkeypatch):
    """The print hides the WebGL canvases, so PRINT_FLAGS (no 3D APIs) change nothing on paper: the same PDF, bar
    its dates, as a print whose page did draw its 3D view."""
    from strainwave.compare.validate import report_pdf
    from strainwave.compare.validate.report_html import CSS, _view
    from strainwave.compare.validate.view3d import viewer_script

    b64 = lambda a: base64.b64encode(np.ascontiguousarray(a).tobytes()).decode("ascii")   # noqa: E731
    payload = json.dumps({"positions": b64(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)),
                          "scalars": b64(np.array([0, 1, 2], np.float32)), "indices": b64(np.array([0, 1, 2], np.uint32)),
                          "range": [0.0, 2.0], "home": [0.0, 0.0]})
    view = _view("ring", {"caption": "one triangle", "range_MPa": [0.0, 2.0]}, payload, "red")
    html = tmp_path / "page.html"
    html.write_text(f"<html><head><style>{CSS}</style></head><body><h1>view</h1>{view}<script>{viewer_script()}"
                    "</script></body></html>", encoding="utf-8")
    fast = print_pdf(html, tmp_path / "fast.pdf").read_bytes()
    monkeypatch.setattr(report_pdf, "PRINT_FLAGS", ())
    drawn = print_pdf(html, tmp_path / "drawn.pdf").read_bytes()
    assert _undated(fast) == _undated(drawn)
