"""`strainwave validate`: study results and closed forms -> checks -> reports (HTML, Markdown, JSON)."""
from .pipeline import Outcome, run_validate

__all__ = ["Outcome", "run_validate"]
