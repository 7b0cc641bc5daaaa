# rebond — build, test, run. `make help` lists the targets.
SHELL := /bin/bash
FC      ?= gfortran
CC      ?= gcc
ifeq ($(origin FC),default)
FC := gfortran
endif
BUILD   := build
BIN     := bin/rebond
HDF5_INC := /usr/include/hdf5/serial
HDF5_LIB := -lhdf5_serial_fortran -lhdf5_serial
FFLAGS  ?= -O2 -g
FFLAGS  += -std=f2008 -fimplicit-none -Wall -Wno-unused-dummy-argument -ffree-line-length-132 -ffpe-summary=none \
           -fall-intrinsics -I$(HDF5_INC) -J$(BUILD) -I$(BUILD)
CFLAGS  ?= -O2 -g
CFLAGS  += -Wall -Wextra -I/usr/include/suitesparse
# MPI (Open MPI, Debian's libopenmpi-dev) for `rebond sweep`: the mpifort wrapper's flags, with
# gfortran. Recursive (=) so that they are read when a recipe runs, after `make deps` installed it.
MPI_FFLAGS = $(shell mpifort --showme:compile 2>/dev/null)
MPI_LIBS   = $(shell mpifort --showme:link 2>/dev/null)
override FFLAGS += $(MPI_FFLAGS)
# MUMPS (Debian's libmumps-ptscotch-dev: built on Open MPI with Scotch and PT-Scotch orderings):
# its Fortran include dmumps_struc.h.
MUMPS_INC := /usr/include
MUMPS_LIB := -ldmumps_ptscotch -lmumps_common_ptscotch -lpord_ptscotch
override FFLAGS += -I$(MUMPS_INC)
LDLIBS  = $(HDF5_LIB) $(MUMPS_LIB) -lumfpack -lcholmod -lamd -lsuitesparseconfig -larpack -llapack -lblas $(MPI_LIBS)
PY      := /usr/bin/python3

# Sources live in src/<concern>/ (README: the module tour); objects and .mod files go flat
# into $(BUILD)/, the source found by vpath.
SRC_DIRS := $(sort $(dir $(wildcard src/*/*.f90 src/*/*.c)))
LIB_F90 := $(wildcard src/*/*.f90)
LIB_C   := $(wildcard src/*/*.c)
LIB_OBJ := $(addprefix $(BUILD)/,$(notdir $(LIB_F90:.f90=.o) $(LIB_C:.c=.o)))
vpath %.f90 src $(SRC_DIRS)
vpath %.c $(SRC_DIRS)
TEST_F90 := $(wildcard tests/unit/test_*.f90)
TEST_BIN := $(patsubst tests/unit/%.f90,$(BUILD)/tests/%,$(TEST_F90))
DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: all deps run test bench clean help
all: $(BIN)

help:
	@echo "make deps    install the Debian packages rebond needs (apt-get, as root)"
	@echo "make         build bin/rebond"
	@echo "make run     install what is missing, build, run the default scene"
	@echo "make test    build and run every test; ends with 'N passed, M failed'"
	@echo "make test T=NAME   only the suites whose name contains NAME (e.g. T=contact, T=scene_bar)"
	@echo "make bench   QUAD4 plate benchmark (writes docs/performance.md), and the others (docs/performance-*.md)"
	@echo "make studies run every studies/*.sweep under mpirun (results/studies/, docs/sweep.md)"
	@echo "make check-debug  unit tests and every scene with -fcheck=all and FPE traps (build-debug/)"
	@echo "make valgrind     memcheck of four short scenes and a sweep with bin/rebond (docs/reliability.md)"
	@echo "make reliability  hostile input, full disk, fuzz and kill/restart counts (docs/reliability.md)"
	@echo "make validation   the paper's beam drops and the contact table (docs/validation.md, docs/contact-table.md)"
	@echo "make contact-table  the impact modes on three exact benchmarks (docs/contact-table.md, docs/contact-trade.md)"
	@echo "make large   the energy correction in large displacements, by step (docs/large-displacements.md)"
	@echo "make iterations  ITERATION ELASTIC, TANGENT, AUTO and the energy test (docs/nonlinear-performance.md)"
	@echo "make zone    SCHEME ZONE: eq (9) on the nonlinear elements' equations (docs/nonlinear-performance.md)"
	@echo "make peers   rebond and CalculiX on the same bar impacts (docs/peers.md)"
	@echo "make restitution  RESTITUTION e against the bodies' coefficient (docs/contact.md)"
	@echo "make paraview-check  fields.xmf in ParaView's two XDMF readers, pictures in docs/figures/ (installs paraview)"

# Dependencies: installed once by `make deps`, checked by every build.
deps:
	@bash tools/install_deps.sh

$(DEPS_STAMP):
	@mkdir -p $(BUILD)
	@bash tools/install_deps.sh --check || bash tools/install_deps.sh
	@touch $@

$(BUILD)/deps.mk: $(LIB_F90) src/rebond.f90 tests/testing.f90 $(TEST_F90) tools/fdeps.py | $(DEPS_STAMP)
	@mkdir -p $(BUILD)/tests
	@python3 tools/fdeps.py $(BUILD) $(LIB_F90) src/rebond.f90 tests/testing.f90 > $@

-include $(BUILD)/deps.mk

$(BUILD)/%.o: %.f90 | $(DEPS_STAMP)
	$(FC) $(FFLAGS) -c $< -o $@

$(BUILD)/%.o: %.c | $(DEPS_STAMP)
	$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/librebond.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BIN): $(BUILD)/rebond.o $(BUILD)/librebond.a
	@mkdir -p $(dir $@)
	$(FC) $(FFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/testing.o: tests/testing.f90 $(BUILD)/kinds.o
	$(FC) $(FFLAGS) -c $< -o $@

$(BUILD)/tests/%: tests/unit/%.f90 $(BUILD)/testing.o $(BUILD)/librebond.a
	@mkdir -p $(BUILD)/tests
	$(FC) $(FFLAGS) -o $@ $< $(BUILD)/testing.o $(BUILD)/librebond.a $(LDLIBS)

# make test T=NAME runs the suites whose name contains NAME (test_contact, scene_bar_impact, …).
test: bin/rebond $(TEST_BIN)
	@bash tests/run_tests.sh $(T)

run: bin/rebond
	@bin/rebond inputs/beam_drop_vertical.dat
	@echo "results are in results/beam_drop_vertical/ (history.csv, probes.csv, events.csv, contacts.csv, fields.h5, fields.xmf)"
	@echo "look at them: /usr/bin/python3 tools/plot_energy.py results/beam_drop_vertical --scene inputs/beam_drop_vertical.dat -o energy.png"
	@echo "              (energy, balance, rebound heights); fields.xmf opens in ParaView (displacement, stress, reaction)"

bench: bin/rebond
	@bash tools/bench.sh
	@BENCH_DIM=3 BENCH_SIZES="1e4 1e5" bash tools/bench.sh
	@/usr/bin/python3 tools/bench_load.py --write
	@bash tools/bench_nonlinear.sh
	@BENCH_CONTACT_OUT=docs/performance-contact.md bash tools/bench_contact.sh
	@/usr/bin/python3 tools/bench_taylor.py
	@/usr/bin/python3 tools/bench_taylor.py bin/rebond docs/taylor-axisymmetric.md --scene inputs/taylor_bar.dat
	@/usr/bin/python3 tools/bench_friction.py
	@/usr/bin/python3 tools/bench_zone3d.py bin/rebond docs/performance-zone3d.md
	@/usr/bin/python3 tools/bench_mumps.py bin/rebond docs/performance-mumps.md

clean:
	rm -rf $(BUILD) bin/rebond

# The paper's validation scenes (beams dropped on the ground): results/validation/,
# docs/figures/*.png, docs/validation.md. Missing scenes are skipped and reported.
.PHONY: validation
validation: bin/rebond
	@bash tools/make_validation.sh
	@/usr/bin/python3 tools/contact_table.py
	@/usr/bin/python3 tools/contact_table.py --trade

# fields.xmf in ParaView's default reader (Xdmf3ReaderS) and the legacy XDMF Reader, under
# xvfb-run: every array of fields.h5 in both, a picture of each case (docs/figures/paraview_*.png).
# Installs Debian's paraview and xvfb when pvpython is missing (as root).
.PHONY: paraview-check
paraview-check: bin/rebond
	@/usr/bin/python3 tools/paraview_check.py

# RESTITUTION e on deformable bodies: the body-level coefficient and the energy dissipated, two
# blocks and a ring (docs/contact.md, "What RESTITUTION means on a deformable body"; ~1 min).
.PHONY: restitution
restitution: bin/rebond
	@/usr/bin/python3 tools/restitution_table.py --write

# Large displacements (docs/large-displacements.md): the energy correction against plain Newmark
# on the stiff bar pendulum, by step, with the figure docs/figures/large_energy_vs_h.png.
.PHONY: large
large: bin/rebond
	@/usr/bin/python3 tools/large_study.py

# The iteration of eq (9) (docs/nonlinear-performance.md): ELASTIC, TANGENT and AUTO with and
# without the energy test, on the nonlinear scenes.
.PHONY: iterations
iterations: bin/rebond
	@/usr/bin/python3 tools/iteration_study.py

# The nonlinear zone of eq (9)'s iteration (SCHEME ZONE) against the whole system and the linear
# step, at three mesh sizes and growing plastic patches (docs/nonlinear-performance.md; ~20 min).
.PHONY: zone
zone: bin/rebond
	@/usr/bin/python3 tools/zone_study.py

# rebond and CalculiX side by side (docs/peers.md): SDNV100's bar on a wall, elastic and
# elastic-plastic, over meshes and steps, and the copper Taylor bar (axisymmetric and plane strain);
# installs Debian's calculix-ccx when it is missing.
.PHONY: peers
peers: bin/rebond
	@command -v ccx >/dev/null 2>&1 || apt-get install -y calculix-ccx >/dev/null || \
	  { echo "peers: CalculiX is needed (apt-get install calculix-ccx, as root)"; exit 1; }
	@/usr/bin/python3 tools/peers.py
	@/usr/bin/python3 tools/peers_taylor.py
	@/usr/bin/python3 tools/peers_friction.py

# The contact comparison (docs/contact-table.md): three impact benchmarks with exact solutions,
# every impact mode at every mesh size.
.PHONY: contact-table
contact-table: bin/rebond
	@/usr/bin/python3 tools/contact_table.py
	@/usr/bin/python3 tools/contact_table.py --trade

# Reliability (docs/reliability.md). check-debug builds a separate tree (build-debug/,
# bin/rebond-debug) with run-time checks and FPE traps, then runs every unit suite and every
# scene on it; valgrind runs memcheck on short runs of the normal -O2 -g binary.
DEBUG_BUILD  := build-debug
DEBUG_BIN    := bin/rebond-debug
DEBUG_FFLAGS := -g -O0 -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace
DEBUG_CFLAGS := -g -O0
VALGRIND_SCENES := inputs/cantilever_release.dat inputs/mass_bounce.dat tests/scenes/lplate/lplate.dat \
  tests/scenes/gmsh_scene/tags.dat $(wildcard studies/mass_bounce.sweep)
.PHONY: check-debug valgrind
check-debug:
	@DEBUG_BUILD='$(DEBUG_BUILD)' DEBUG_BIN='$(DEBUG_BIN)' DEBUG_FFLAGS='$(DEBUG_FFLAGS)' \
	  DEBUG_CFLAGS='$(DEBUG_CFLAGS)' MAKE='$(MAKE)' bash tools/check_debug.sh

valgrind: bin/rebond
	@bash tools/check_debug.sh --valgrind $(VALGRIND_SCENES)

# The measured reliability table of docs/reliability.md: the hostile-input, full-disk and restart
# checks, 2000 fuzzed scenes and 20 SIGKILL/restart trials (~10 min). Ends with `N passed, M failed`.
.PHONY: reliability
reliability: bin/rebond
	@/usr/bin/python3 tools/reliability_report.py

# Parameter studies: every studies/*.sweep run by `rebond sweep` under mpirun (one dispatching
# rank + one worker per core; the OMPI_* variables let Open MPI run as root, as in CI), tables
# in results/studies/<name>/ (sweep.csv, sweep.h5, sweep.md, pareto.png). docs/sweep.md.
STUDY_NP ?= $(shell echo $$(( $$(nproc) + 1 )))
.PHONY: studies
studies: bin/rebond
	@for f in studies/*.sweep; do [ -f "$$f" ] || continue; n=$$(basename "$$f" .sweep); \
	  echo "== $$f"; \
	  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np $(STUDY_NP) \
	    bin/rebond sweep "$$f" -o "results/studies/$$n" || echo "$$f: some cases failed (see sweep.csv)"; \
	  $(PY) tools/sweep_table.py "results/studies/$$n/sweep.csv" --png "results/studies/$$n/pareto.png" \
	    > "results/studies/$$n/sweep.md" && echo "   results/studies/$$n/sweep.md, pareto.png"; \
	done
	$(PY) tools/accuracy_speed.py --results results/studies --template studies/accuracy-speed.md.in \
	  --doc docs/accuracy-speed.md --figures docs/figures --np $(STUDY_NP)
	$(PY) tools/adaptive_study.py --out results/studies/adaptive --doc docs/adaptive-step.md --figures docs/figures
	$(PY) tools/sphere_spin.py --out results/studies/sphere_spin --doc docs/friction-sphere.md --figures docs/figures

# Stability at the extremes (issue 5, docs/extremes.md): every case of tests/extremes/matrix.py
# (steps 1e-8 s ... 10 periods, E over 12 decades, mass ratios 1e-6 ... 1e6, tiny gaps, grazing,
# 100 simultaneous impacts, 1e6 steps, perfect plasticity); runs in results/extremes/<case>/,
# table of outcomes in results/extremes/matrix.md and docs/extremes.md. `make test` runs the fast subset
# (tests/scenes/extremes/check.py). Exits 1 when a case fails.
.PHONY: extremes
extremes: bin/rebond
	@$(PY) tests/extremes/matrix.py --out results/extremes --markdown results/extremes/matrix.md --jobs 2 --strict \
	  --doc docs/extremes.md

# Fuzzing of the scene and mesh readers (issue 6): 10 000 mutants of the shipped scenes and meshes
# (tests/fuzz/fuzz.py, 2 jobs; ~8 min). Prints `PASS fuzz: N mutants, no crash` per batch of 1000,
# `FAIL fuzz <mutant>: <reason>` per crash (saved in tests/fuzz/crashes/), then the runtime; exits
# 1 on a crash. `make test` runs 400 of them (tests/scenes/fuzz/check.py). FUZZ_SEED=s for others.
.PHONY: fuzz
FUZZ_SEED ?= 1
fuzz: bin/rebond
	@$(PY) tests/fuzz/fuzz.py --mutants 10000 --seed $(FUZZ_SEED) --jobs 2 --batch 1000
