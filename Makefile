# rebond — build, test, run. `make help` lists the targets.
SHELL := /bin/bash
FC      ?= gfortran
CC      ?= gcc
ifeq ($(origin FC),default)
FC := gfortran
endif
BUILD   := build
HDF5_INC := /usr/include/hdf5/serial
HDF5_LIB := -lhdf5_serial_fortran -lhdf5_serial
FFLAGS  ?= -O2 -g
FFLAGS  += -std=f2008 -fimplicit-none -Wall -Wno-unused-dummy-argument -ffree-line-length-132 \
           -fall-intrinsics -I$(HDF5_INC) -J$(BUILD) -I$(BUILD)
CFLAGS  ?= -O2 -g
CFLAGS  += -Wall -Wextra -I/usr/include/suitesparse
LDLIBS  := $(HDF5_LIB) -lcholmod -lsuitesparseconfig -llapack -lblas
PY      := /usr/bin/python3

LIB_F90 := $(filter-out src/rebond.f90,$(wildcard src/*.f90))
LIB_C   := $(wildcard src/*.c)
LIB_OBJ := $(patsubst src/%.f90,$(BUILD)/%.o,$(LIB_F90)) $(patsubst src/%.c,$(BUILD)/%.o,$(LIB_C))
TEST_F90 := $(wildcard tests/unit/test_*.f90)
TEST_BIN := $(patsubst tests/unit/%.f90,$(BUILD)/tests/%,$(TEST_F90))
DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: all deps run test bench clean help
all: bin/rebond

help:
	@echo "make deps    install the Debian packages rebond needs (apt-get, as root)"
	@echo "make         build bin/rebond"
	@echo "make run     install what is missing, build, run the default scene"
	@echo "make test    build and run every test; ends with 'N passed, M failed'"
	@echo "make bench   QUAD4 plate benchmark (writes docs/performance.md)"

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

$(BUILD)/%.o: src/%.f90 | $(DEPS_STAMP)
	$(FC) $(FFLAGS) -c $< -o $@

$(BUILD)/%.o: src/%.c | $(DEPS_STAMP)
	$(CC) $(CFLAGS) -c $< -o $@

$(BUILD)/librebond.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

bin/rebond: $(BUILD)/rebond.o $(BUILD)/librebond.a
	@mkdir -p bin
	$(FC) $(FFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/testing.o: tests/testing.f90 $(BUILD)/kinds.o
	$(FC) $(FFLAGS) -c $< -o $@

$(BUILD)/tests/%: tests/unit/%.f90 $(BUILD)/testing.o $(BUILD)/librebond.a
	@mkdir -p $(BUILD)/tests
	$(FC) $(FFLAGS) -o $@ $< $(BUILD)/testing.o $(BUILD)/librebond.a $(LDLIBS)

test: bin/rebond $(TEST_BIN)
	@bash tests/run_tests.sh

run: bin/rebond
	@bin/rebond inputs/beam_drop_vertical.dat
	@echo "results are in results/beam_drop_vertical/ (history.csv, probes.csv, events.csv, fields.h5, fields.xmf)"

bench: bin/rebond
	@bash tools/bench.sh

clean:
	rm -rf $(BUILD) bin/rebond

# The paper's validation scenes (beams dropped on the ground): results/validation/,
# docs/figures/*.png, docs/validation.md. Missing scenes are skipped and reported.
.PHONY: validation
validation: bin/rebond
	@bash tools/make_validation.sh
