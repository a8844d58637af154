"""`strainwave sweep`: a parameter grid -> one Dask task per point -> tidy table and plots."""

__all__ = ["Outcome", "run_sweep"]


def __getattr__(name: str):
    # Loaded on first use: workers unpickling tasks need no pandas (docs/decisions/013-sweep-worker-start-up.md).
    if name in __all__:
        from strainwave.compare.sweep import pipeline
        return getattr(pipeline, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
