# hybrid: continuum -> discrete geomechanics.  Two commands for users:
#   make demo   runs the main job (installs what is missing first)
#   make test   lints (ruff, mypy) and runs the default test set (installs what is missing first)
# make verify regenerates the committed verification report (docs/verification) from a full run.
# Everything goes through Debian's /usr/bin/python3 and the project venv .venv
# (never the `python3` first on PATH, which lacks dolfinx).

SHELL := /bin/bash
SYS_PY := /usr/bin/python3
VENV := .venv
PY := $(VENV)/bin/python
# libopenblas0-serial: an optimised BLAS/LAPACK in place of the reference one that the others
# pull in (MUMPS factorises the continuum's stiffness about twice as fast with it: docs/
# performance.md); the serial build, so that it adds no threads beside numba's
DEB_PKGS := python3-dolfinx python3-petsc4py python3-mpi4py python3-gmsh python3-meshio \
            python3-numba python3-matplotlib python3-pytest python3-venv python3-h5py \
            libopenblas0-serial
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
export NUMBA_CACHE_DIR ?= $(CURDIR)/.cache/numba
export OMP_WAIT_POLICY ?= passive
export MPLBACKEND ?= Agg

.PHONY: deps setup demo test lint typecheck verify docs test-slow bench clean

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
	$(PY) -m hybrid verify --full --update-docs

# the hybrid cases behind docs/hybrid.md and docs/carsington.md: their summaries (docs/summaries/,
# every figure the docs quote; tests/test_docs_numbers.py checks the quotes) and figures
# (docs/figures/). Nine independent parts (`make -j2 docs` runs two at once), then the quoted
# figures rewritten from the new summaries.
DOCS_RUN := results/docs
CARS := $(PY) -m hybrid run cases/carsington.py --set progress=false --overwrite
.PHONY: docs-h2 docs-h2-settlement docs-h3-d10 docs-carsington-construction \
	docs-carsington-sensitivity docs-carsington-slide docs-r1 docs-r1-assumptions \
	docs-r1-grain-size

docs: docs-h2 docs-h2-settlement docs-h3-d10 docs-carsington-construction \
	docs-carsington-sensitivity docs-carsington-slide docs-r1 docs-r1-assumptions \
	docs-r1-grain-size
	# R1's deposits on the two floors: summaries of two parts (docs-r1, docs-r1-assumptions)
	$(PY) -c "import json, runpy; f = runpy.run_path('cases/granular_collapse.py')['plot_deposits']; \
	  f('docs/figures/hybrid/r1_floor.png', [json.load(open(f'docs/summaries/r1_a{a}{r}.json')) \
	  for a in ('0.5', '1', '2') for r in ('', '_rough')])"
	# and on grains fine enough for the run-out to stop growing (docs-r1-grain-size)
	$(PY) -c "import json, runpy; f = runpy.run_path('cases/granular_collapse.py')['plot_deposits']; \
	  f('docs/figures/hybrid/r1_fine.png', [json.load(open(f'docs/summaries/r1_{r}.json')) \
	  for r in ('a0.5_nx60', 'a0.5_nx60_rough', 'a1_nx60', 'a1_nx60_rough')])"
	# every figure the docs quote rewritten from the new summaries (the changes are printed:
	# read them, and mend the words around a figure that changed its meaning)
	$(PY) tests/test_docs_numbers.py

docs-h2: setup
	mkdir -p docs/summaries docs/figures/hybrid
	$(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/h2 --set progress=false --overwrite
	# the far side as a plain roller that reflects the waves (docs/hybrid.md)
	$(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/h2_reflecting \
	    --set progress=false --set far_boundary=reflecting --overwrite
	# H2's mesh sensitivity (docs/hybrid.md): every mesh followed to rest; a discrete run that
	# stops unstable (exit 3) is reported as such (docs/summaries/h2_*.unstable.txt, its
	# message) beside the mesh's continuum summary; the displacement-controlled punch on the
	# default mesh, its refinement, the 0.12 m and the structured meshes, the default mesh
	# and its refinement at half the speed, and the default mesh with half and twice the
	# softening slip u_r; the structured mesh refined to 0.04 m, under load control and the
	# punch, in 48 increments (in the default 24 its continuum stalls before the collapse)
	for run in "fine0.16 --set fine=0.16" "fine0.12 --set fine=0.12" "fine0.04 --set fine=0.04" \
	    "structured --set structured=true" "punch --set control=punch" \
	    "punch_fine0.04 --set control=punch --set fine=0.04" \
	    "punch_fine0.12 --set control=punch --set fine=0.12" \
	    "punch_structured --set control=punch --set structured=true" \
	    "structured_fine0.04 --set structured=true --set fine=0.04 --set continuum_steps=48" \
	    "punch_structured_fine0.04 --set control=punch --set structured=true --set fine=0.04 --set continuum_steps=48" \
	    "punch_v0.125 --set control=punch --set punch_speed=0.125" \
	    "punch_v0.125_fine0.04 --set control=punch --set punch_speed=0.125 --set fine=0.04" \
	    "punch_ur0.1 --set control=punch --set softening_displacement=0.1" \
	    "punch_ur0.4 --set control=punch --set softening_displacement=0.4"; do set -- $$run; name=$$1; shift; \
	    rm -f docs/summaries/h2_$$name.unstable.txt; \
	    $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/h2_$$name --overwrite \
	    --set progress=false "$$@" 2> $(DOCS_RUN)/h2_$$name.stderr; rc=$$?; \
	    cat $(DOCS_RUN)/h2_$$name.stderr >&2; \
	    if [ $$rc -eq 3 ]; then \
	    grep "unstable" $(DOCS_RUN)/h2_$$name.stderr > docs/summaries/h2_$$name.unstable.txt; \
	    $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/h2_$$name --overwrite \
	    --set progress=false --set discrete=false "$$@" || exit 1; \
	    elif [ $$rc -ne 0 ] && [ $$rc -ne 4 ]; then exit 1; fi; done
	# the default and the structured mesh with the half-width 0.1 % smaller and larger: how far
	# small changes of the set-up move the footing (the default mesh 0.1 % wider stalls in the
	# continuum before the collapse: not run here, the docs say so)
	for run in "W4.7952 --set width=4.7952" "structured_W4.7952 --set structured=true \
	    --set width=4.7952" "structured_W4.8048 --set structured=true --set width=4.8048"; do \
	    set -- $$run; name=$$1; shift; $(PY) -m hybrid run cases/footing_failure.py \
	    --out $(DOCS_RUN)/h2_$$name --overwrite --set progress=false "$$@" || exit 1; done
	# the perfectly plastic soil (c_r = c) on the default quadrilaterals and on triangles of the
	# same size, continuum only: the collapse load of the two cell shapes without softening
	for run in "perfect" "triangle_perfect --set cells=triangle"; do set -- $$run; name=$$1; \
	    shift; $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/h2_$$name \
	    --overwrite --set progress=false --set discrete=false --set residual_cohesion=69 "$$@" \
	    || exit 1; done
	for c in h2 h2_reflecting h2_fine0.16 h2_fine0.12 h2_fine0.04 h2_structured h2_punch \
	    h2_punch_fine0.04 h2_punch_v0.125 h2_punch_v0.125_fine0.04 h2_punch_fine0.12 h2_punch_structured \
	    h2_punch_ur0.1 h2_punch_ur0.4 h2_structured_fine0.04 h2_punch_structured_fine0.04 \
	    h2_perfect h2_triangle_perfect h2_W4.7952 h2_structured_W4.7952 \
	    h2_structured_W4.8048; do \
	    cp $(DOCS_RUN)/$$c/summary.json docs/summaries/$$c.json; done
	cp $(DOCS_RUN)/h2/load_settlement.png docs/figures/hybrid/h2_load_settlement.png
	cp $(DOCS_RUN)/h2_punch/load_settlement.png docs/figures/hybrid/h2_punch_load_settlement.png
	cp $(DOCS_RUN)/h2/final.png docs/figures/hybrid/h2_final.png
	cp $(DOCS_RUN)/h2/handover_plastic_strain.png docs/figures/hybrid/h2_handover_plastic_strain.png
	# the animation: a GIF, or where ffmpeg is installed an MP4 the docs' GIF is made from
	if [ -f $(DOCS_RUN)/h2/discrete/discrete.gif ]; then \
	    cp $(DOCS_RUN)/h2/discrete/discrete.gif docs/figures/hybrid/h2_discrete.gif; \
	else ffmpeg -nostdin -y -loglevel error -i $(DOCS_RUN)/h2/discrete/discrete.mp4 \
	    docs/figures/hybrid/h2_discrete.gif; fi

# H2's collapse load as the peak of the footing's settlement-controlled curve (continuum only):
# the default mesh, 0.1 % wider (under load control Newton stalls there), the structured and
# the refined meshes, and triangles (24 and 100 increments); a run that stops (exit 3) leaves
# its message in docs/summaries/h2_settlement_<name>.stopped.txt instead of a summary; the
# load-controlled runs that stall (the wider mesh, triangles) their messages in h2_load_*;
# the default quadrilaterals and the triangles (100 increments) followed to rest
# H2 continuum-only runs: $(1) the summaries' prefix, $(2) the options of every run, $(3) the
# runs ("name --set ..."); a run that stops (exit 3) leaves its message in
# docs/summaries/<prefix>_<name>.stopped.txt instead of a summary
define h2_continuum_runs
	for run in $(3); do \
	    set -- $$run; name=$(1)_$$1; shift; \
	    rm -f docs/summaries/$$name.json docs/summaries/$$name.stopped.txt; \
	    $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/$$name --overwrite \
	    --set progress=false --set discrete=false $(2) "$$@" \
	    2> $(DOCS_RUN)/$$name.stderr; rc=$$?; cat $(DOCS_RUN)/$$name.stderr >&2; \
	    if [ $$rc -eq 3 ]; then \
	    grep "stage incomplete" $(DOCS_RUN)/$$name.stderr > docs/summaries/$$name.stopped.txt; \
	    elif [ $$rc -eq 0 ]; then cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; \
	    else exit 1; fi; done
endef
H2_SETTLEMENT_RUNS := "default" "W4.8048 --set width=4.8048" "structured --set structured=true" \
	"fine0.04 --set fine=0.04" "structured_fine0.04 --set structured=true --set fine=0.04" \
	"triangle --set cells=triangle" \
	"triangle_steps100 --set cells=triangle --set continuum_steps=100"
H2_HOLD_RUNS := "default" "W4.8048 --set width=4.8048" "fine0.04 --set fine=0.04" \
	"structured_fine0.04 --set structured=true --set fine=0.04 --set continuum_steps=48" \
	"triangle --set cells=triangle" \
	"settlement_structured --set continuum_control=settlement --set structured=true" \
	"settlement_triangle_steps100 --set continuum_control=settlement --set cells=triangle \
	--set continuum_steps=100"

docs-h2-settlement: setup
	mkdir -p docs/summaries $(DOCS_RUN)
	$(call h2_continuum_runs,h2_settlement,--set continuum_control=settlement,\
	    $(H2_SETTLEMENT_RUNS))
	# followed to rest from the peak: the default quadrilaterals and the triangles
	for run in "default_rest" "triangle_steps100_rest --set cells=triangle \
	    --set continuum_steps=100"; do \
	    set -- $$run; name=h2_settlement_$$1; shift; \
	    $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/$$name --overwrite \
	    --set progress=false --set continuum_control=settlement "$$@" || exit 1; \
	    cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done
	# Newton's retry of cycling increments (continuum_hold_flipping, continuum only): the
	# default mesh, the meshes where the load ramp stalls or stops short, the refined one and
	# two settlement-controlled paths
	$(call h2_continuum_runs,h2_hold,--set continuum_hold_flipping=true,$(H2_HOLD_RUNS))
	# the same meshes under load control where it stalls, and the perfectly plastic soil on the
	# refined triangles: the message kept
	for run in "W4.8048 --set width=4.8048" "triangle --set cells=triangle" \
	    "triangle_fine0.04_perfect --set cells=triangle --set fine=0.04 \
	    --set residual_cohesion=69"; do \
	    set -- $$run; name=h2_load_$$1; shift; rm -f docs/summaries/$$name.stopped.txt; \
	    $(PY) -m hybrid run cases/footing_failure.py --out $(DOCS_RUN)/$$name --overwrite \
	    --set progress=false --set discrete=false "$$@" 2> $(DOCS_RUN)/$$name.stderr; rc=$$?; \
	    cat $(DOCS_RUN)/$$name.stderr >&2; if [ $$rc -eq 3 ]; then \
	    grep "stage incomplete" $(DOCS_RUN)/$$name.stderr > docs/summaries/$$name.stopped.txt; \
	    elif [ $$rc -ne 0 ]; then exit 1; fi; done

H3_LENGTHS := 19.96 19.97 19.98 19.99 20.01 20.02 20.03 20.04

docs-h3-d10: setup
	mkdir -p docs/summaries docs/figures/hybrid
	$(PY) -m hybrid run cases/retaining_wall_collapse.py --out $(DOCS_RUN)/h3 --set progress=false --overwrite
	$(PY) -m hybrid run cases/toppling.py --out $(DOCS_RUN)/d10 --set progress=false --overwrite
	# H3's mesh sensitivity (docs/hybrid.md): the structured mesh coarser and finer, gmsh's
	# unstructured quadrilaterals at the default size (at 0.25 m: below)
	for size in 1.0 0.25; do $(PY) -m hybrid run cases/retaining_wall_collapse.py \
	    --out $(DOCS_RUN)/h3_size$$size --overwrite --set progress=false --set size=$$size \
	    || exit 1; done
	$(PY) -m hybrid run cases/retaining_wall_collapse.py --out $(DOCS_RUN)/h3_unstructured \
	    --overwrite --set progress=false --set structured=false
	# the default and the unstructured mesh with the backfill up to 0.2 % shorter and longer
	# (nine runs on each): how far one run's run-out moves under a change far below any test's
	# precision, and the mean of each mesh's runs
	for L in $(H3_LENGTHS); do $(PY) -m hybrid run cases/retaining_wall_collapse.py \
	    --out $(DOCS_RUN)/h3_L$$L --overwrite --set progress=false --set length=$$L || exit 1; \
	    $(PY) -m hybrid run cases/retaining_wall_collapse.py --out $(DOCS_RUN)/h3_unstructured_L$$L \
	    --overwrite --set progress=false --set length=$$L --set structured=false || exit 1; \
	    cp $(DOCS_RUN)/h3_L$$L/summary.json docs/summaries/h3_L$$L.json; \
	    cp $(DOCS_RUN)/h3_unstructured_L$$L/summary.json docs/summaries/h3_unstructured_L$$L.json; \
	    done
	# the 0.25 m grid and gmsh's unstructured quadrilaterals at 0.25 m, five runs on each
	# (backfill 19.96 to 20.04 m in steps of 0.02 m): the mesh types on refinement
	for L in 19.96 19.98 20.02 20.04; do $(PY) -m hybrid run cases/retaining_wall_collapse.py \
	    --out $(DOCS_RUN)/h3_size0.25_L$$L --overwrite --set progress=false --set size=0.25 \
	    --set length=$$L || exit 1; \
	    cp $(DOCS_RUN)/h3_size0.25_L$$L/summary.json docs/summaries/h3_size0.25_L$$L.json; done
	for L in 19.96 19.98 20 20.02 20.04; do name=h3_unstructured_size0.25$$( [ $$L = 20 ] \
	    || echo _L$$L ); $(PY) -m hybrid run cases/retaining_wall_collapse.py \
	    --out $(DOCS_RUN)/$$name --overwrite --set progress=false --set size=0.25 \
	    --set structured=false --set length=$$L || exit 1; \
	    cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done
	# the grid refined again, to 0.125 m, five runs (the same lengths): three grids in all
	# (15 360 cells: about half an hour a run on one core here, 2.5 hours for the five)
	for L in 19.96 19.98 20 20.02 20.04; do name=h3_size0.125$$( [ $$L = 20 ] \
	    || echo _L$$L ); $(PY) -m hybrid run cases/retaining_wall_collapse.py \
	    --out $(DOCS_RUN)/$$name --overwrite --set progress=false --set size=0.125 \
	    --set length=$$L || exit 1; \
	    cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done
	for c in h3 d10 h3_size1.0 h3_size0.25 h3_unstructured; do \
	    cp $(DOCS_RUN)/$$c/summary.json docs/summaries/$$c.json; done
	cp $(DOCS_RUN)/h3/thrust_translation.png docs/figures/hybrid/h3_thrust_translation.png
	cp $(DOCS_RUN)/h3/handover_plastic_strain.png docs/figures/hybrid/h3_handover_plastic_strain.png
	cp $(DOCS_RUN)/h3/wedge.png docs/figures/hybrid/h3_wedge.png
	cp $(DOCS_RUN)/h3/final.png docs/figures/hybrid/h3_final.png
	cp $(DOCS_RUN)/d10/failures.png docs/figures/hybrid/d10_toppling_failures.png

# Carsington's construction: the thesis's set-up (a run with a FAILed check, exit 4, is kept: a
# comparison with the thesis or the observed slide is a result the docs report; any other
# failure stops; tests/test_docs_numbers.py asserts the bars every committed run must keep),
# the last lift in parts of 0.25 m, the continuum stage on finer meshes (3 and 2 m elements),
# the fill level of the collapse on 6, 4.5, 3 and 2 m elements (the fill above 194 m OD in
# parts of 0.5 m), the 3 m mesh's stop again with a least increment ten times smaller
docs-carsington-construction: setup
	mkdir -p docs/summaries docs/figures/carsington
	$(CARS) --out $(DOCS_RUN)/carsington || [ $$? -eq 4 ] || exit 1
	$(CARS) --out $(DOCS_RUN)/carsington_last_lift --set parts_above=198 --set part_height=0.25 \
	    --set safety=false --set discrete_time=0
	for size in 3 2; do $(CARS) --out $(DOCS_RUN)/carsington_size$$size --set safety=false \
	    --set discrete_time=0 --set size=$$size || exit 1; done
	for size in 6 4.5 3 2; do $(CARS) --out $(DOCS_RUN)/carsington_parts_size$$size \
	    --set safety=false --set discrete_time=0 --set size=$$size --set parts_above=194 \
	    --set part_height=0.5 || exit 1; done
	$(CARS) --out $(DOCS_RUN)/carsington_parts_size3_increment1e-4 --set safety=false \
	    --set discrete_time=0 --set size=3 --set parts_above=194 --set part_height=0.5 \
	    --set min_increment=1e-4
	for c in carsington carsington_last_lift carsington_size3 carsington_size2 \
	    carsington_parts_size6 carsington_parts_size4.5 carsington_parts_size3 \
	    carsington_parts_size2 carsington_parts_size3_increment1e-4; do \
	    cp $(DOCS_RUN)/$$c/summary.json docs/summaries/$$c.json; done
	for f in end_of_construction_yielded end_of_construction_sigma_yy \
	    end_of_construction_sigma_xx core_displacement_vs_fill_level discrete_final; do \
	    cp $(DOCS_RUN)/carsington/$$f.png docs/figures/carsington/$$f.png; done

# Carsington's fill level against the assumed extent of the yellow clay: 20, 25, 30 and 50 m
# long on the 3 and 2 m meshes, 1 and 2 m thick (the published range) on the 3 m mesh; the
# fill above 194 m OD (above 182 m OD for the 50 m layer, which fails lower) placed in 0.5 m
# parts, as in docs-carsington-construction, whose carsington_parts_size3 and _size2 are the
# default rows (36 m long, 1.5 m thick)
docs-carsington-sensitivity: setup
	mkdir -p docs/summaries
	for run in "3 Y20 194 yellow_clay_length=20" "3 Y25 194 yellow_clay_length=25" \
	    "3 Y30 194 yellow_clay_length=30" "3 Y50 182 yellow_clay_length=50" \
	    "3 T1.0 194 yellow_clay_thickness=1.0" "3 T2.0 194 yellow_clay_thickness=2.0" \
	    "2 Y20 194 yellow_clay_length=20" "2 Y25 194 yellow_clay_length=25" \
	    "2 Y30 194 yellow_clay_length=30" "2 Y50 182 yellow_clay_length=50"; do \
	    set -- $$run; name=carsington_parts_size$$1_$$2; \
	    $(CARS) --out $(DOCS_RUN)/$$name --set safety=false --set discrete_time=0 \
	    --set size=$$1 --set parts_above=$$3 --set part_height=0.5 --set $$4 || exit 1; \
	    cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done

# Carsington's slide: beyond the thesis, strain softening (u_r 0.5 m; 0.2 and 1 m; 0.5 m on 8,
# 5, 4, 3, 2.5, 2 and 1.5 m elements); softening in the discrete phase only (the dam built at
# Table 6.3's peak strengths); from the design height (the section with 30 m of yellow clay
# stands to the crest with Table 6.3 in whole lifts), its discrete phase as it is and with
# softening (on 6, 4, 3 and 2 m elements), and with 25 m of yellow clay and the fill in parts
# (the section stands to the crest on the 4, 3 and 2 m meshes); the discrete phase's
# sensitivity to mass damping (default none; the thesis ran 3 /s)
docs-carsington-slide: setup
	mkdir -p docs/summaries docs/figures/carsington
	for run in "softening 0.5 6" "softening_ur0.2 0.2 6" "softening_ur1 1.0 6" \
	    "softening_size8 0.5 8" "softening_size5 0.5 5" "softening_size4 0.5 4" \
	    "softening_size3 0.5 3" "softening_size2.5 0.5 2.5" "softening_size2 0.5 2" \
	    "softening_size1.5 0.5 1.5"; do set -- $$run; \
	    $(CARS) --out $(DOCS_RUN)/carsington_$$1 --set safety=false --set softening=true \
	    --set softening_displacement=$$2 --set size=$$3 || [ $$? -eq 4 ] || exit 1; done
	$(CARS) --out $(DOCS_RUN)/carsington_discrete_softening --set safety=false \
	    --set discrete_softening=true || [ $$? -eq 4 ] || exit 1
	for run in "design_height" "design_height_softening --set discrete_softening=true" \
	    "design_height_softening_size4 --set discrete_softening=true --set size=4" \
	    "design_height_softening_size3 --set discrete_softening=true --set size=3" \
	    "design_height_softening_size2 --set discrete_softening=true --set size=2"; do \
	    set -- $$run; name=$$1; shift; $(CARS) --out $(DOCS_RUN)/carsington_$$name \
	    --set safety=false --set yellow_clay_length=30 "$$@" || [ $$? -eq 4 ] || exit 1; done
	# the design-height runs with softening on the 6, 4 and 3 m meshes with the yellow clay 3 cm
	# shorter and longer: how far one run moves under a change far below what is known of it
	for Y in 29.97 30.03; do for size in 6 4 3; do \
	    tail=$$( [ $$size = 6 ] || echo _size$$size ); \
	    $(CARS) --out $(DOCS_RUN)/carsington_design_height_softening$${tail}_Y$$Y \
	    --set safety=false --set yellow_clay_length=$$Y --set discrete_softening=true \
	    --set size=$$size || [ $$? -eq 4 ] || exit 1; done; done
	# from the design height on a section that stands to the crest on the 4, 3 and 2 m meshes:
	# the yellow clay 25 m long, the fill above 194 m OD in 0.5 m parts
	# (docs-carsington-sensitivity's 25 m rows), the discrete phase without softening on the
	# 3 m mesh, and with softening on the 4, 3 and 2 m meshes, each also with the yellow clay
	# 3 cm shorter and longer
	for run in "design_height_parts 3 25" \
	    "design_height_parts_softening_size4 4 25 --set discrete_softening=true" \
	    "design_height_parts_softening_size3 3 25 --set discrete_softening=true" \
	    "design_height_parts_softening_size2 2 25 --set discrete_softening=true" \
	    "design_height_parts_softening_size4_Y24.97 4 24.97 --set discrete_softening=true" \
	    "design_height_parts_softening_size3_Y24.97 3 24.97 --set discrete_softening=true" \
	    "design_height_parts_softening_size2_Y24.97 2 24.97 --set discrete_softening=true" \
	    "design_height_parts_softening_size4_Y25.03 4 25.03 --set discrete_softening=true" \
	    "design_height_parts_softening_size3_Y25.03 3 25.03 --set discrete_softening=true" \
	    "design_height_parts_softening_size2_Y25.03 2 25.03 --set discrete_softening=true"; do \
	    set -- $$run; name=carsington_$$1; size=$$2; Y=$$3; shift 3; \
	    $(CARS) --out $(DOCS_RUN)/$$name --set safety=false --set size=$$size \
	    --set yellow_clay_length=$$Y --set parts_above=194 --set part_height=0.5 "$$@" \
	    || [ $$? -eq 4 ] || exit 1; cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; \
	    done
	# the same section (25 m) in whole lifts, softening in the discrete phase, 3 and 2 m meshes
	for size in 3 2; do name=carsington_design_height_Y25_softening_size$$size; \
	    $(CARS) --out $(DOCS_RUN)/$$name --set safety=false --set size=$$size \
	    --set yellow_clay_length=25 --set discrete_softening=true || [ $$? -eq 4 ] || exit 1; \
	    cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done
	# the softening analysis on the 4, 3, 2.5 and 2 m meshes with the yellow clay 3 and 6 cm
	# shorter and longer: one run's scatter, and the means of five runs on each mesh
	for size in 4 3 2.5 2; do for Y in 35.94 35.97 36.03 36.06; do \
	    name=carsington_softening_size$${size}_Y$$Y; \
	    $(CARS) --out $(DOCS_RUN)/$$name --set safety=false --set softening=true \
	    --set softening_displacement=0.5 --set size=$$size --set yellow_clay_length=$$Y \
	    || [ $$? -eq 4 ] || exit 1; cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; \
	    done; done
	for md in 0.5 3; do $(CARS) --out $(DOCS_RUN)/carsington_damping$$md --set safety=false \
	    --set mass_damping=$$md || [ $$? -eq 4 ] || exit 1; done
	for c in carsington_softening carsington_softening_ur0.2 carsington_softening_ur1 \
	    carsington_softening_size8 carsington_softening_size5 carsington_softening_size4 \
	    carsington_softening_size3 carsington_softening_size2.5 carsington_softening_size2 \
	    carsington_softening_size1.5 carsington_discrete_softening carsington_design_height \
	    carsington_design_height_softening carsington_design_height_softening_size4 \
	    carsington_design_height_softening_size3 carsington_design_height_softening_size2 \
	    carsington_damping0.5 carsington_damping3 \
	    carsington_design_height_softening_Y29.97 carsington_design_height_softening_Y30.03 \
	    carsington_design_height_softening_size4_Y29.97 \
	    carsington_design_height_softening_size4_Y30.03 \
	    carsington_design_height_softening_size3_Y29.97 \
	    carsington_design_height_softening_size3_Y30.03; do \
	    cp $(DOCS_RUN)/$$c/summary.json docs/summaries/$$c.json; done
	cp $(DOCS_RUN)/carsington_softening/discrete_final.png \
	    docs/figures/carsington/softening_discrete_final.png

# R1 on grains of L0 / 20, and its sensitivity to the grain size (L0 / 10 and L0 / 30)
docs-r1: setup
	mkdir -p docs/summaries docs/figures/hybrid
	for a in 0.5 1 2; do $(PY) -m hybrid run cases/granular_collapse.py --out $(DOCS_RUN)/r1_a$$a \
	  --set aspect=$$a --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; done
	for a in 0.5 1 2; do for n in 10 30; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_nx$$n --set aspect=$$a --set nx=$$n --set progress=false \
	  --overwrite || [ $$? -eq 4 ] || exit 1; done; done
	# the same runs with L0 0.1 % shorter and longer: how far a run-out moves under a change
	# of the set-up far below any experiment's precision
	for a in 0.5 1 2; do for L in 0.1998 0.2002; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_L$$L --set aspect=$$a --set length=$$L --set progress=false \
	  --overwrite || [ $$? -eq 4 ] || exit 1; done; done
	for r in a0.5 a1 a2 a0.5_nx10 a0.5_nx30 a1_nx10 a1_nx30 a2_nx10 a2_nx30 a0.5_L0.1998 \
	  a0.5_L0.2002 a1_L0.1998 a1_L0.2002 a2_L0.1998 a2_L0.2002; do \
	  cp $(DOCS_RUN)/r1_$$r/summary.json docs/summaries/r1_$$r.json; done
	$(PY) -c "import json, runpy; f = runpy.run_path('cases/granular_collapse.py')['plot_deposits']; \
	  f('docs/figures/hybrid/r1_deposits.png', [json.load(open(f'docs/summaries/r1_a{a}.json')) \
	  for a in ('0.5', '1', '2')])"

# R1's assumed grain parameters, each changed alone at a = 1 and 2: the contact damping ratio
# (0.1 and 0.6 beside the case's 0.3), the grains' stiffness (E ten times the case's 840 kPa)
# and the contact angle (the calibrated 11.1 deg less 2, and 1 and 2 more: its uncertainty); the
# experiment's unknown floor, rough (a sawtooth standing in for grains fixed to it) at a = 0.5,
# 1 and 2, and on it grains of L0 / 10 and L0 / 30 at a = 0.5 and 1; a structured mesh of squares
docs-r1-assumptions: setup
	mkdir -p docs/summaries
	for a in 2 1; do for z in 0.1 0.6; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_zeta$$z --set aspect=$$a --set contact_damping=$$z \
	  --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; done; \
	  $(PY) -m hybrid run cases/granular_collapse.py --out $(DOCS_RUN)/r1_a$${a}_E8400 \
	  --set aspect=$$a --set E=8400 --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; \
	  for c in 9.1 12.1 13.1; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_phic$$c --set aspect=$$a --set contact_phi=$$c \
	  --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; done; done
	for a in 1 2; do for r in zeta0.1 zeta0.6 E8400 phic9.1 phic12.1 phic13.1; do \
	  cp $(DOCS_RUN)/r1_a$${a}_$$r/summary.json docs/summaries/r1_a$${a}_$$r.json; done; done
	# the floor: a sawtooth standing in for grains fixed to it, instead of the smooth plane
	for a in 0.5 1 2; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_rough --set aspect=$$a --set floor=rough \
	  --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; \
	  cp $(DOCS_RUN)/r1_a$${a}_rough/summary.json docs/summaries/r1_a$${a}_rough.json; done
	# a structured mesh of squares instead of the triangles, at a = 0.5, 1 and 2
	for a in 0.5 1 2; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_squares --set aspect=$$a --set cells=quadrilateral \
	  --set structured=true --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; \
	  cp $(DOCS_RUN)/r1_a$${a}_squares/summary.json docs/summaries/r1_a$${a}_squares.json; done
	# and its grain size: L0 / 10 and L0 / 30 at a = 0.5 and 1
	for a in 0.5 1; do for n in 10 30; do $(PY) -m hybrid run cases/granular_collapse.py \
	  --out $(DOCS_RUN)/r1_a$${a}_nx$${n}_rough --set aspect=$$a --set nx=$$n --set floor=rough \
	  --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; \
	  cp $(DOCS_RUN)/r1_a$${a}_nx$${n}_rough/summary.json docs/summaries/r1_a$${a}_nx$${n}_rough.json; \
	  done; done

# R1 on finer grains, where the flat floor's run-out stops growing: L0 / 40, 50 and 60 at
# a = 0.5, L0 / 40 and 60 at a = 1, L0 / 40 at a = 2; at L0 / 40 three packings (L0 0.1 %
# shorter and longer) at a = 0.5 and 1, and at L0 / 60 at a = 1; the rough floor at L0 / 40
# and 60 (a = 0.5 and 1)
R1_FINE_RUNS := "a0.5_nx40 --set aspect=0.5 --set nx=40" "a0.5_nx50 --set aspect=0.5 --set nx=50" \
	"a0.5_nx60 --set aspect=0.5 --set nx=60" "a1_nx40 --set aspect=1 --set nx=40" \
	"a1_nx60 --set aspect=1 --set nx=60" "a2_nx40 --set aspect=2 --set nx=40" \
	"a0.5_nx40_L0.1998 --set aspect=0.5 --set nx=40 --set length=0.1998" \
	"a0.5_nx40_L0.2002 --set aspect=0.5 --set nx=40 --set length=0.2002" \
	"a1_nx40_L0.1998 --set aspect=1 --set nx=40 --set length=0.1998" \
	"a1_nx40_L0.2002 --set aspect=1 --set nx=40 --set length=0.2002" \
	"a0.5_nx40_rough --set aspect=0.5 --set nx=40 --set floor=rough" \
	"a1_nx40_rough --set aspect=1 --set nx=40 --set floor=rough" \
	"a0.5_nx60_rough --set aspect=0.5 --set nx=60 --set floor=rough" \
	"a1_nx60_rough --set aspect=1 --set nx=60 --set floor=rough" \
	"a1_nx60_L0.1998 --set aspect=1 --set nx=60 --set length=0.1998" \
	"a1_nx60_L0.2002 --set aspect=1 --set nx=60 --set length=0.2002"

docs-r1-grain-size: setup
	mkdir -p docs/summaries
	for run in $(R1_FINE_RUNS); do set -- $$run; name=r1_$$1; shift; \
	  $(PY) -m hybrid run cases/granular_collapse.py --out $(DOCS_RUN)/$$name "$$@" \
	  --set progress=false --overwrite || [ $$? -eq 4 ] || exit 1; \
	  cp $(DOCS_RUN)/$$name/summary.json docs/summaries/$$name.json; done

bench: setup
	$(PY) -m hybrid bench --json results/bench.json

clean:
	rm -rf results .cache .pytest_cache
