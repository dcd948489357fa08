# Two commands do all set-up on a machine with Python 3.11+ and pip:
#   make demo   - creates .venv, installs pounding, runs the paper example
#   make test   - creates .venv, installs pounding with its test extra, runs pytest
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q
DEMO_OUT ?= demo_output

.PHONY: demo test bench clean

$(VENV)/.stamp-base: pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip
	$(PIP) install -e ".[viz]"
	@touch $@

$(VENV)/.stamp-test: pyproject.toml $(VENV)/.stamp-base
	$(PIP) install -e ".[test]"
	$(PIP) install -e examples/plugin_element
	@touch $@

demo: $(VENV)/.stamp-base
	$(VENV)/bin/pounding demo --out $(DEMO_OUT)

# The openseespy 3.7.1 wheel (Python 3.11) needs BLAS/LAPACK; tests load the
# copies it bundles (pounding.peer.opensees), so no system package is needed.
test: $(VENV)/.stamp-test
	$(PY) -m pytest -q -p no:cacheprovider $(PYTEST_ARGS)

bench: $(VENV)/.stamp-test
	$(PY) benchmarks/run.py

clean:
	rm -rf $(VENV) $(DEMO_OUT) .pytest_cache
