# Two commands (see README): `make demo` sets up and runs the demo (the hexapod's tripod gait on poppy seeds,
# logged to mjrft-demo.rrd; open it with `rerun mjrft-demo.rrd`), `make test` sets up and runs the tests in two
# processes (pytest-xdist; TEST_WORKERS=N for another number, 0 for one process) and lists the 25 slowest.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
TEST_WORKERS ?= 2

.PHONY: setup demo test bench

setup: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q torch==2.13.0
	$(PY) -m pip install -q -e ".[all]"
	touch $@

demo: setup
	$(VENV)/bin/mjrft demo

test: setup
	$(PY) -m pytest -q -n $(TEST_WORKERS) --durations=25

bench: setup
	$(PY) benchmarks/bench_step.py
