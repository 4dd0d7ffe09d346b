# Two commands do all set-up on a fresh machine with only python3:
#   make run   - create .venv, install, run the main job (see README)
#   make test  - create .venv, install, check the layers' imports (lint-imports), run the tests
#                and the docstrings' doctests (all tiers; `.venv/bin/python -m pytest -m "not slow"`
#                is the quick loop)
# and: make docs (the documentation site into build/docs, Sphinx with warnings as errors), make
# gallery (make run, then the example plots copied small into docs/gallery), make bench.
# Each target installs what it needs (pyproject extras): run and bench the FMU build (fmu), fmpy
# (host) and the tooling (bench: contact_tools); test those and pytest, libcosimpy,
# import-linter (test); docs Sphinx, numpydoc, myst-parser (docs).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
EXTRAS_run  := fmu,host,bench
EXTRAS_test := test
EXTRAS_docs := docs

.PHONY: run test docs gallery bench clean

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
	$(PY) examples/run_implicit_coupling.py
	$(PY) examples/run_real_profiles.py
	$(PY) examples/adhesion.py
	$(PY) -m contact_tools.bench --out out

test: $(VENV)/.installed-test
	$(VENV)/bin/lint-imports
	$(PY) -m pytest -q

docs: $(VENV)/.installed-docs
	$(PY) -m sphinx -W --keep-going -q -b html docs build/docs

gallery: run
	$(PY) examples/contact_geometry.py
	$(PY) -m contact_tools.gallery --src out --dest docs/gallery

bench: $(VENV)/.installed-run
	$(PY) -m contact_tools.bench_closed_form
	$(PY) -m contact_tools.bench_fastsim
	$(PY) -m contact_tools.bench_exact
	$(PY) -m contact_tools.bench_fmu
	$(PY) -m contact_tools.bench_fmu_startup
	$(PY) -m contact_tools.bench_fmu_leaks
	$(PY) -m contact_tools.bench_geometry

clean:
	rm -rf $(VENV) out dist build *.egg-info
