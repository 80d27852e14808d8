# cshape: two commands on a fresh machine (Python >= 3.10 and the package index only).
#   make demo   - the main job: runs every walkthrough notebook into out/notebooks/
#   make test   - the whole test suite, both tiers (what CI runs); installs Debian's Chromium
#                 for the browser tests when it is missing and we are root (else they skip)
#   make test-fast - the fast tier only (plain `pytest`: the developer's loop, under 2 minutes)
#   make notebooks - after editing a lesson's source notebooks/NN_topic.py: rewrite its .ipynb
#   make assignments - nbgrader's student versions of the graded lessons into notebooks/student/
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test test-fast bench reproduce notebooks assignments lint setup clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade "pip>=25.1"
	$(PY) -m pip install --quiet -e ".[all]" --group test --group bench
	touch $(STAMP)

demo: $(STAMP)
	$(PY) -m cshape notebooks --out out/notebooks

test: $(STAMP)
	bash tools/ensure_browser.sh
	$(PY) -m pytest -m "slow or not slow" $(PYTEST_ARGS)

test-fast: $(STAMP)
	$(PY) -m pytest $(PYTEST_ARGS)

reproduce: $(STAMP)
	$(PY) -m cshape reproduce --out out/reproduce

notebooks: $(STAMP)
	$(PY) tools/sync_notebooks.py

assignments: $(STAMP)
	$(PY) tools/sync_notebooks.py
	$(PY) -m cshape assignments

bench: $(STAMP)
	$(PY) benchmarks/bench_spectrum.py

lint: $(STAMP)
	$(VENV)/bin/ruff check .

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info out test-artifacts
