# cshape: two commands on a fresh machine (Python >= 3.10 and the package index only).
#   make demo   - the main job (sets up .venv first)
#   make test   - the test suite (sets up .venv first)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench lint setup clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade "pip>=25.1"
	$(PY) -m pip install --quiet -e ".[notebooks,distributed,download]" --group test --group bench
	touch $(STAMP)

demo: $(STAMP)
	$(PY) -m cshape demo

test: $(STAMP)
	$(PY) -m pytest $(PYTEST_ARGS)

bench: $(STAMP)
	$(PY) benchmarks/bench_spectrum.py

lint: $(STAMP)
	$(VENV)/bin/ruff check .

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info
