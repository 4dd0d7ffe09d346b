# Two commands do all set-up on a fresh machine with only python3:
#   make run   - create .venv, install, run the main job (see README)
#   make test  - create .venv, install, run the tests
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: run test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -e '.[test]'
	touch $(STAMP)

run: $(STAMP)
	mkdir -p out
	$(PY) examples/creep_curves.py
	$(PY) examples/fastsim_traction_map.py
	$(PY) examples/exact_traction_map.py
	$(PY) examples/fmu_demo.py
	$(PY) examples/run_hunting.py
	$(PY) -m contact_core.bench --out out

test: $(STAMP)
	$(PY) -m pytest -q

bench: $(STAMP)
	$(PY) examples/bench_closed_form.py
	$(PY) examples/bench_fastsim.py
	$(PY) examples/bench_exact.py
	$(PY) examples/bench_fmu.py
	$(PY) examples/bench_fmu_startup.py
	$(PY) examples/bench_fmu_leaks.py

clean:
	rm -rf $(VENV) out dist build *.egg-info
