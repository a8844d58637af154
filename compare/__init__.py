"""Comparison jobs, one package each: ``validate`` (FEA against closed forms -> reports),
``diagnose`` (recordings against the simulation -> verdict and named physics) and ``sweep``
(parameter grids on Dask). The three share no code with each other; shared plumbing lives in
``strainwave`` (cache, atomic writes, params)."""
