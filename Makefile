# Two commands do all set-up on a fresh machine with only python3:
#   make run   - create .venv, install, run the main job (see README)
#   make test  - create .venv, install, run the tests
# Each target installs what it needs (pyproject extras): run and bench the FMU build (fmu), fmpy
# (host) and the reports (bench); test those and pytest, libcosimpy (test).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
EXTRAS_run  := fmu,host,bench
EXTRAS_test := test

.PHONY: run test bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)

$(VENV)/.installed-%: pyproject.toml | $(PY)
	$(PY) -m pip install -e '.[$(EXTRAS_$*)]'
	touch $@

run: $(VENV)/.installed-run
	mkdir -p out
	$(PY) examples/creep_curves.py
	$(PY) examples/fastsim_traction_map.py
	$(PY) examples/exact_traction_map.py
	$(PY) examples/fmu_demo.py
	$(PY) examples/run_hunting.py
	$(PY) -m contact_core.bench --out out

test: $(VENV)/.installed-test
	$(PY) -m pytest -q

bench: $(VENV)/.installed-run
	$(PY) examples/bench_closed_form.py
	$(PY) examples/bench_fastsim.py
	$(PY) examples/bench_exact.py
	$(PY) examples/bench_fmu.py
	$(PY) examples/bench_fmu_startup.py
	$(PY) examples/bench_fmu_leaks.py

clean:
	rm -rf $(VENV) out dist build *.egg-info
