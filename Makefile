# flexgear set-up and entry points. Every target installs what it needs first.
# Tested on Debian 12 with Python 3.11 (root or passwordless sudo for system packages).
SHELL := /bin/bash
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
# Shared libraries the gmsh and vtk wheels load (off-screen rendering uses EGL, no X server),
# SuiteSparse headers for the optional CHOLMOD speed-up (scikit-sparse), and OpenBLAS as the
# system BLAS that CHOLMOD calls: a 50k-DOF Craig-Bampton reduction took 14.7 s on Debian's
# reference BLAS and 4.9 s with OpenBLAS (factorization 7.4 -> 1.2 s) on 2 cores.
SYSTEM_PKGS := libglu1-mesa libgl1 libegl1 libxcursor1 libxft2 libxinerama1 libgomp1 \
               libsuitesparse-dev libopenblas0-pthread build-essential
STAMP := $(VENV)/.flexgear-installed

.PHONY: setup sysdeps run test test-fast fuzz mutate bench clean clean-cache

sysdeps:
	@if ! dpkg -s $(SYSTEM_PKGS) >/dev/null 2>&1 || ! $(PYTHON) -c 'import ensurepip' >/dev/null 2>&1; then \
	  SUDO=; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  echo "installing system packages: $(SYSTEM_PKGS) python3-venv"; \
	  $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(SYSTEM_PKGS) python3-venv >/dev/null; \
	fi

$(STAMP): pyproject.toml | sysdeps
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	@# Optional CHOLMOD backend: flexgear falls back to SciPy if it does not build.
	$(PY) -m pip install -q -e '.[fast]' || echo "note: scikit-sparse not installed; using SciPy solvers"
	@# Optional compiled time step (numba): flexgear falls back to its Python step if it does not install.
	$(PY) -m pip install -q -e '.[speed]' || echo "note: numba not installed; time-domain runs use the Python step"
	@# ROSCO's package for its compiled controller and performance tables, without its toolbox's
	@# dependencies (WISDEM, Jupyter: ~1.4 GB); the turbine's runs need it, nothing else does.
	$(PY) -m pip install -q --no-deps 'rosco==2.9.0' || echo "note: rosco not installed; turbine runs unavailable"
	$(PY) -m pip install -q -e '.[wind]' || echo "note: pyconturb not installed; no IEC turbulence"
	@# Bytecode of the package compiled once here (an editable install compiles none): the first
	@# `flexgear modes` of a small scene then starts like every later one, ~0.1 s sooner.
	$(PY) -m compileall -q assembly cms fe_components
	touch $(STAMP)

setup: sysdeps $(STAMP)

DEMO ?= hs_parallel_stage.toml
run: setup
	$(VENV)/bin/flexgear run $(DEMO) --out results
	@echo "flexgear: results written; open $(CURDIR)/results/index.html"

# On every core this process may use (pytest-xdist; TEST_WORKERS=0 for one process; not `-n auto`,
# which counts physical cores), a test file per worker at a time so that a file's module
# fixtures are built once (tests/conftest.py: one BLAS thread per worker).
TEST_WORKERS ?= $(shell $(PY) -c 'import os; print(len(os.sched_getaffinity(0)))')
TEST_PARALLEL = -n $(TEST_WORKERS) --dist loadfile
test: setup
	$(PY) -m pytest -q $(TEST_PARALLEL)

# Everything but the tests marked slow (over 5 s each): a quick check while developing.
test-fast: setup
	$(PY) -m pytest -q $(TEST_PARALLEL) -m "not slow"

# The fuzz tests with 20x their CI examples, freshly random (CI draws a fixed set).
fuzz: setup
	FLEXGEAR_FUZZ_SCALE=20 HYPOTHESIS_PROFILE=explore $(PY) -m pytest -q tests/hard_cases/test_fuzz_scenes.py \
	  tests/hard_cases/test_fuzz_solve.py tests/hard_cases/test_scene_files.py tests/hard_cases/test_magnitudes.py \
	  tests/cms/test_cms_persistence.py tests/fe_components/test_fe_mesh_cache.py

# Mutation pass over the physics modules (tests/mutation/mutate.py): one small wrong change at
# a time, the quick tests that cover it; a table of kill rates and the survivors. CPU-heavy:
# by default 30 mutants per module (seeded; about an hour on 2 cores), MUTATE_ARGS="--module frf"
# for one module, MUTATE_ARGS= for every mutant.
MUTATE_ARGS ?= --sample 30
mutate: setup
	nice -n 10 $(PY) tests/mutation/mutate.py $(MUTATE_ARGS)

bench: setup
	$(PY) -m pip install -q -e '.[bench]' || echo "note: exudyn not installed; cms bench runs without the Exudyn columns"
	$(VENV)/bin/flexgear bench all

# meshes/cache: where versions before the user cache folder kept generated meshes.
clean:
	rm -rf $(VENV) meshes/cache results

# The generated meshes and reductions (FLEXGEAR_CACHE_DIR, else the user's cache folder).
clean-cache:
	rm -rf "$${FLEXGEAR_CACHE_DIR:-$${XDG_CACHE_HOME:-$$HOME/.cache}/flexgear}"
