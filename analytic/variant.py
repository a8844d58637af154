"""The two readings of a seed formula: exactly as printed, or as re-derived."""
from __future__ import annotations

import enum


class Variant(enum.Enum):
    """Which version of a seed formula to evaluate.

    PUBLISHED is the formula exactly as printed in the seed (reconstructed where the
    PDF text is garbled); CORRECTED is the one re-derived in
    the project's seed formula audit (seed-formula-audit.md, kept with the seed papers; its items are
    data in ``analytic/audit.py``) and confirmed by this package's tests.
    """

    PUBLISHED = "published"
    CORRECTED = "corrected"
