# cshape: two commands on a fresh machine (Python >= 3.10 and the package index only).
#   make demo   - the main job: runs every walkthrough notebook into out/notebooks/
#   make test   - the whole test suite, both tiers (what CI runs); installs Debian's Chromium
#                 for the browser tests when it is missing and we are root (else they skip)
#   make test-fast - the fast tier only (plain `pytest`: the developer's loop, under 2 minutes)
#   make notebooks - after editing a lesson's source notebooks/NN_topic.py: rewrite its .ipynb
#   make assignments - nbgrader's student versions of the graded lessons into notebooks/student/
#   make docs    - the documentation site into out/docs/ (renders the executed lessons of
#                  out/notebooks/, running at small size those that are missing or stale)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# Python keeps the compiled modules of cshape and of the tests (__pycache__/, ignored by git)
# for every command here: `make test` starts about 140 interpreters and notebook kernels, and
# where the environment sets PYTHONDONTWRITEBYTECODE each of them would compile the package again
unexport PYTHONDONTWRITEBYTECODE

.PHONY: demo test test-fast bench reproduce notebooks assignments docs lint setup clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade "pip>=25.1"
	$(PY) -m pip install --quiet -e ".[all]" --group test --group bench --group docs
	@# JupyterLab of this venv lists each lesson once: its .ipynb, not the source NN_topic.py
	mkdir -p $(VENV)/etc/jupyter
	cp tools/jupyter_server_config.json $(VENV)/etc/jupyter/jupyter_server_config.json
	touch $(STAMP)

demo: $(STAMP)
	$(PY) -m cshape notebooks --out out/notebooks

test: $(STAMP)
	bash tools/ensure_browser.sh
	$(PY) -m pytest -m "slow or not slow" -n auto --dist loadscope $(PYTEST_ARGS)

test-fast: $(STAMP)
	$(PY) -m pytest $(PYTEST_ARGS)

reproduce: $(STAMP)
	$(PY) -m cshape reproduce --out out/reproduce

notebooks: $(STAMP)
	$(PY) tools/sync_notebooks.py

assignments: $(STAMP)
	$(PY) tools/sync_notebooks.py
	$(PY) -m cshape assignments

docs: $(STAMP)
	@stale="$$($(PY) docs/_ext/lessonpages.py stale out/notebooks)"; \
	if [ -n "$$stale" ]; then $(PY) -m cshape notebooks --small --out out/notebooks $$stale; fi
	$(PY) -m sphinx -W --keep-going -q -b html docs out/docs
	@echo "the site is in out/docs/ ; open out/docs/index.html"

bench: $(STAMP)
	$(PY) benchmarks/bench_sweep.py --sizes 10k,40k,160k --no-real

lint: $(STAMP)
	$(VENV)/bin/ruff check .

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info out test-artifacts docs/api/generated \
		docs/api/*.rst docs/lessons/[0-9][0-9]_*.ipynb docs/jupyter_execute
	find cshape tests tools docs benchmarks -name __pycache__ -type d -prune -exec rm -rf {} +
