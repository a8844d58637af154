"""`strainwave validate`: study results and closed forms -> checks -> reports (HTML, Markdown, JSON)."""
from strainwave.compare.validate.pipeline import Outcome, run_validate

__all__ = ["Outcome", "run_validate"]
