# Two commands do all set-up on a fresh machine: `make validate` and `make test`.
# Each bootstraps .venv from pyproject.toml on first use (and again when pyproject changes).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# One BLAS thread per process: the two cores are shared with gmsh, AMG and Dask workers.
export OMP_NUM_THREADS ?= 1
export OPENBLAS_NUM_THREADS ?= 1
export MKL_NUM_THREADS ?= 1

.PHONY: validate test test-heavy bench clean-venv

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

# Both shipped parameter files must pass with the same coefficients: the embedded default (the seeds'
# examples) and strainwave/data/second_gear.toml (another module, tooth count, rim ratio and shaft bore).
validate: $(STAMP)
	$(BIN)/strainwave validate --out reports/validate
	$(BIN)/strainwave validate --params strainwave/data/second_gear.toml --out reports/validate-second-gear

# The suite on both cores, one file per worker (its module fixtures run once); the end-to-end runs of minutes
# (validate --quick, sweeps on Dask, the CLI under strace) are the heavy set, which CI runs after it.
test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadfile -m "not heavy" --durations=25 tests

test-heavy: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadfile -m heavy --durations=25 tests

bench: $(STAMP)
	$(BIN)/python benchmarks/run_all.py

clean-venv:
	rm -rf $(VENV)
