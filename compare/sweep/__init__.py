"""`strainwave sweep`: a parameter grid -> one Dask task per point -> tidy table and plots."""
from .pipeline import Outcome, run_sweep

__all__ = ["Outcome", "run_sweep"]
