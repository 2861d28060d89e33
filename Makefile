# mtcal — two commands on a fresh machine: `make reproduce` and `make test`.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.mtcal-installed
NOTEBOOK_SRC := $(sort $(wildcard notebooks/[0-9][0-9]_*.py))
NOTEBOOKS    := $(NOTEBOOK_SRC:.py=.ipynb)
# notebooks with output-compared cells ...
CHECKED_NOTEBOOKS = $(patsubst %.py,%.ipynb,$(shell grep -l '^\# NBVAL_CHECK_OUTPUT' $(NOTEBOOK_SRC)))
# ... of which those whose checked outputs come from LAPACK, optimisers or transcendental functions are
# re-checked under the CPU's native code paths in `make test` (21 and 30 print closed forms and table
# constants; CROSS_CHECK=all re-checks every one)
CROSS_CHECK ?= 00 10 20 40
CROSS_NOTEBOOKS = $(if $(filter all,$(CROSS_CHECK)),$(CHECKED_NOTEBOOKS),\
	$(filter $(foreach n,$(CROSS_CHECK),notebooks/$(n)_%),$(CHECKED_NOTEBOOKS)))
# the most capable OpenBLAS kernel of this CPU (the pinned runs use Nehalem)
NATIVE_CORETYPE ?= $(shell if grep -qw avx512f /proc/cpuinfo 2>/dev/null; then echo SkylakeX; \
	elif grep -qw avx2 /proc/cpuinfo 2>/dev/null; then echo Haswell; else echo Sandybridge; fi)

export MPLBACKEND := Agg
export PYTHONHASHSEED := 0
export MTCAL_PROGRESS := 0
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# CPU-independent floating point, the same on every x86-64 CPU (docs: ENVIRONMENT.md;
# equal to mtcal.runs.environment.numerics_env(), tested): one BLAS thread, one OpenBLAS
# kernel set, numpy's baseline loops (no AVX-512 SVML), glibc's SSE2 libm (no FMA variants).
export OPENBLAS_NUM_THREADS := 1
export OMP_NUM_THREADS := 1
export MKL_NUM_THREADS := 1
export OPENBLAS_CORETYPE := Nehalem
export NPY_DISABLE_CPU_FEATURES := X86_V3 X86_V4 AVX512_ICL AVX512_SPR
export GLIBC_TUNABLES := glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4
# numba kernels compiled for a generic x86-64 target (no AVX/FMA), the same code on every CPU
export NUMBA_CPU_NAME := generic
NATIVE_ENV = env -u NPY_DISABLE_CPU_FEATURES -u GLIBC_TUNABLES -u NUMBA_CPU_NAME OPENBLAS_CORETYPE=$(NATIVE_CORETYPE)
# benchmarks measure the machine as a user runs it: native code paths, all BLAS threads
BENCH_ENV = env -u NPY_DISABLE_CPU_FEATURES -u GLIBC_TUNABLES -u NUMBA_CPU_NAME -u OPENBLAS_CORETYPE \
	-u OPENBLAS_NUM_THREADS -u OMP_NUM_THREADS -u MKL_NUM_THREADS

PYTEST := $(BIN)/python -m pytest -q -p no:cacheprovider
# notebooks executed at the same time by `make reproduce` (outputs do not depend on it)
JOBS ?= 2
# numba threads per notebook kernel in `make reproduce`: JOBS notebooks already fill the cores (2 kernels x 2
# threads on 2 cores only oversubscribe); the numbers do not depend on it (the Monte Carlo kernels give each
# trial the same numbers on any thread count, tested). Fresh clone, 2 cores: notebooks 184.8 -> 179.9 s wall,
# peak RSS notebook 10 1991 -> 1495 MiB, notebook 11 1763 -> 982 MiB. Empty: numba's default (all cores).
NOTEBOOK_THREADS ?= 1

.PHONY: venv reproduce report artifact sync test measure bench clean

$(STAMP): pyproject.toml constraints.txt
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev]'
	$(BIN)/python -c "from mtcal.filters.kernels import warm_up_all; warm_up_all(); \
		from mtcal.studies.wang2022sensors import _sim_kernels; _sim_kernels.warm_up()"
	touch $(STAMP)

venv: $(STAMP)

## .ipynb inputs from the py:percent sources (jupytext), outputs of unchanged cells kept.
sync: $(STAMP)
	$(BIN)/python tools/notebooks.py sync $(NOTEBOOK_SRC)

# Monte Carlo results of the studies' expensive entry points (mtcal.core.cache), keyed by
# parameters, seed and code hash; `make artifact` rebuilds one figure/table from it
CACHE := $(CURDIR)/build/cache

## Every notebook at full paper size (papermill), JOBS at a time, each in its own process:
## rewrites notebooks/*.ipynb, figures/, data/ (byte-identical when nothing changed), then the site
## (built beside the catalogue's check: both read only committed files; either failing fails the target).
reproduce: $(STAMP)
	$(BIN)/python tools/notebooks.py sync $(NOTEBOOK_SRC)
	$(if $(NOTEBOOK_THREADS),NUMBA_NUM_THREADS=$(NOTEBOOK_THREADS)) \
	MTCAL_SIZE=full MTCAL_OUTPUT_DIR=$(CURDIR) MTCAL_CACHE_DIR=$(CACHE) $(BIN)/python tools/notebooks.py execute --jobs $(JOBS) \
		--resources $(CURDIR)/build/reproduce/resources.csv $(NOTEBOOK_SRC)
	$(BIN)/python -m mtcal.reporting.fidelity data
	$(BIN)/python tools/artifact_catalogue.py
	$(BIN)/python -m mtcal.reporting.artifact_verdicts data docs/artifacts.md
	$(BIN)/python tools/artifact_catalogue.py --check & check=$$!; \
	$(BIN)/python tools/reviewer_site.py --out build/report; site=$$?; \
	wait $$check && test $$site -eq 0

## The reviewer's site (build/report/index.html; Sphinx + MyST-NB, not committed) from the committed results:
## data/verdicts.csv, docs/, notebooks/*.ipynb, figures/, data/. Fails when data/verdicts.csv is missing.
report: $(STAMP)
	$(BIN)/python tools/reviewer_site.py --out build/report

## One figure or table from the Monte Carlo cache: make artifact ID=wang2023cja_fig07
artifact: $(STAMP)
	@test -n "$(ID)" || { echo "make artifact: set ID=<artifact id> (see docs/artifacts.md)" >&2; exit 2; }
	MTCAL_CACHE_DIR=$(CACHE) $(BIN)/python -m mtcal reproduce $(ID) --cache $(CACHE)

## Unit tests + doctests + nbval over every notebook at CI size (outputs go to build/ci/), then the
## output-checked notebooks again with the CPU's native BLAS kernel and SIMD/FMA code paths.
test: $(STAMP)
	MTCAL_SIZE=ci MTCAL_OUTPUT_DIR=$(CURDIR)/build/ci $(PYTEST) \
		--doctest-modules mtcal tests $(NOTEBOOKS) --nbval-lax --nbval-current-env
	$(NATIVE_ENV) MTCAL_SIZE=ci MTCAL_OUTPUT_DIR=$(CURDIR)/build/ci-native $(PYTEST) \
		$(CROSS_NOTEBOOKS) --nbval-lax --nbval-current-env

## Wall time and peak RSS of every notebook at full size (→ build/measure/resources.csv).
measure: $(STAMP)
	MTCAL_SIZE=full $(BIN)/python tools/notebooks.py measure --out build/measure $(NOTEBOOK_SRC)

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev,bench]'
	$(BENCH_ENV) $(BIN)/python benchmarks/run.py $(BENCH_ARGS)
	$(BENCH_ENV) $(BIN)/python benchmarks/bench_sweep.py --csv data/bench_sweep.csv $(BENCH_SWEEP_ARGS)
	$(BENCH_ENV) $(BIN)/python benchmarks/broad_accuracy.py --csv build/bench/broad2021_accuracy.csv

clean:
	rm -rf build $(VENV)
