"""`strainwave sweep`: a parameter grid -> one Dask task per point -> tidy table and plots."""

__all__ = ["Outcome", "run_sweep"]


def __getattr__(name: str):
    # Loaded on first use: every worker imports this package to unpickle its task (``sweep.task``), and the
    # driver-side pipeline would cost each of them pandas (~0.3 s of its start-up) that no point needs.
    if name in __all__:
        from . import pipeline
        return getattr(pipeline, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
