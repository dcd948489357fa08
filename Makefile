# Two commands do all set-up on a machine with Python 3.11+ and pip:
#   make demo   - creates .venv, installs pounding, runs the paper example
#   make test   - creates .venv, installs pounding with its test extra, runs pytest
# Both then compile the numerical core once, in two processes (python -m pounding.warmup
# --warm; skipped when this version of the compiled modules is already in the cache), so
# that the first run loads machine code instead of compiling it, and build it as an extension
# module where a C compiler is present (python -m pounding.aot; runs then need neither numba
# nor its cache: a run of the paper pair takes 0.40 s instead of 0.86 s). Without a compiler
# that step says so and the runs use numba's cache.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q
DEMO_OUT ?= demo_output

.PHONY: demo test bench clean warm

$(VENV)/.stamp-base: pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip
	$(PIP) install -e ".[viz,data]"
	@touch $@

$(VENV)/.stamp-test: pyproject.toml $(VENV)/.stamp-base
	$(PIP) install -e ".[test]"
	$(PIP) install -e examples/plugin_element
	@touch $@

warm: $(VENV)/.stamp-base
	$(PY) -m pounding.warmup --warm --if-needed
	$(PY) -m pounding.aot --if-needed

demo: $(VENV)/.stamp-base warm
	$(VENV)/bin/pounding demo --out $(DEMO_OUT)

# The openseespy 3.7.1 wheel (Python 3.11) needs BLAS/LAPACK; tests load the
# copies it bundles (pounding.peer.opensees), so no system package is needed.
# The tests run in TEST_JOBS processes (pytest-xdist), each test file whole in one of them (its
# module fixtures, such as the OpenSees runs, computed once); TEST_JOBS=0 runs them in this process.
TEST_JOBS ?= 2
test: $(VENV)/.stamp-test warm
	$(PY) -m pytest -q -p no:cacheprovider -n $(TEST_JOBS) --dist loadfile $(PYTEST_ARGS)

bench: $(VENV)/.stamp-test warm
	$(PY) benchmarks/run.py

clean:
	rm -rf $(VENV) $(DEMO_OUT) .pytest_cache
