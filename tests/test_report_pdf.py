"""report.pdf is printed wherever the output folder sits: Chromium puts its singleton socket under TMPDIR, and a
deep output folder's scratch space (TMPDIR during a run) passed the 108-byte limit of a socket path."""
from __future__ import annotations

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
