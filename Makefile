# hybrid: continuum -> discrete geomechanics.  Two commands for users:
#   make demo   runs the main job (installs what is missing first)
#   make test   lints (ruff, mypy) and runs the default test set (installs what is missing first)
# Everything goes through Debian's /usr/bin/python3 and the project venv .venv
# (never the `python3` first on PATH, which lacks dolfinx).

SHELL := /bin/bash
SYS_PY := /usr/bin/python3
VENV := .venv
PY := $(VENV)/bin/python
DEB_PKGS := python3-dolfinx python3-petsc4py python3-mpi4py python3-gmsh python3-meshio \
            python3-numba python3-matplotlib python3-pytest python3-venv python3-h5py
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
export NUMBA_CACHE_DIR ?= $(CURDIR)/.cache/numba
export OMP_WAIT_POLICY ?= passive
export MPLBACKEND ?= Agg

.PHONY: deps setup demo test lint typecheck verify test-slow bench clean

# --- set-up (idempotent) ------------------------------------------------------
deps:
	@missing=""; for p in $(DEB_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -q --no-install-recommends $$missing; \
	fi

$(PY): | deps
	$(SYS_PY) -m venv --system-site-packages $(VENV)

$(VENV)/.installed: pyproject.toml | $(PY)
	$(PY) -m pip install -q --disable-pip-version-check -e '.[test]'
	@touch $@

setup: deps $(VENV)/.installed

# --- user commands -------------------------------------------------------------
demo: setup
	$(PY) -m hybrid run cases/footing_failure.py --out results/footing_failure --overwrite

lint: setup typecheck
	$(PY) -m ruff check hybrid tests cases meshes

typecheck: setup
	$(PY) -m mypy

test: lint
	$(PY) -m pytest -q -m "not slow"

test-slow: setup
	$(PY) -m pytest -q -m slow

verify: setup
	$(PY) -m hybrid verify --full

bench: setup
	$(PY) -m hybrid bench --json results/bench.json

clean:
	rm -rf results .cache .pytest_cache
