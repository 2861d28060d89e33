# mtcal — two commands on a fresh machine: `make reproduce` and `make test`.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.mtcal-installed
NOTEBOOK_SRC := $(sort $(wildcard notebooks/[0-9][0-9]_*.py))
NOTEBOOKS := $(NOTEBOOK_SRC:.py=.ipynb)
export MPLBACKEND := Agg
export PYTHONHASHSEED := 0
export MTCAL_PROGRESS := 0

.PHONY: venv reproduce test bench clean

$(STAMP): pyproject.toml constraints.txt
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev]'
	touch $(STAMP)

venv: $(STAMP)

## Execute every notebook in order at full paper size; rewrites figures/ and data/.
reproduce: $(STAMP)
	$(BIN)/python tools/py_to_ipynb.py $(NOTEBOOK_SRC)
	MTCAL_SIZE=full $(BIN)/python tools/run_notebooks.py $(NOTEBOOKS)

## Unit tests plus nbval over every notebook at CI size (outputs go to build/ci/).
test: $(STAMP)
	MTCAL_SIZE=ci MTCAL_OUTPUT_DIR=$(CURDIR)/build/ci $(BIN)/python -m pytest -q -p no:cacheprovider \
		--doctest-modules mtcal tests $(NOTEBOOKS) --nbval-lax --nbval-current-env

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev,bench]'
	$(BIN)/python benchmarks/run.py $(BENCH_ARGS)

clean:
	rm -rf build $(VENV)
