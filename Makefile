# sunmc - Monte Carlo tolerance, calibration and design-trade tool for sun sensors.
#   make            build build/sunmc
#   make run        install missing packages, build, run the shipped configs, print Table 1
#   make test       install missing packages, build, run the cmocka suite (plain and ASan+UBSan)
#   make test-fast  the plain suites, golden comparison included (what `make mutate` runs)
#   make mutate     apply each mutant of tests/mutants.txt to a copy of the tree, run test-fast
#   make plots RUN=DIR   draw every figure a run directory holds
#   make figures    regenerate the papers' figures into build/figures/
#   make claims     check the papers' claims, rewrite docs/claims.md
#   make docs-check re-run the docs' commands, compare the numbers the pages quote
#   make docs-check-slow  the same for the marks whose commands take minutes
#   make install PREFIX=/usr/local DESTDIR=
#   make fuzz [FUZZ_SECONDS=60]  run each libFuzzer harness of tests/fuzz/ (clang; not in make test)
#                   and the importers' fuzz loop (make fuzz-import alone: no clang)
# User CFLAGS/LDFLAGS are added to ours.

# `make` alone builds build/sunmc (rules below, such as the dependency files',
# would otherwise become the default goal).
.DEFAULT_GOAL := all

PREFIX  ?= /usr/local
BUILD   ?= build
VERSION := 0.1.0

# MPI=1 builds with MPI (mpicc; Debian's MPICH, see README "Running on a
# cluster"): `mpirun -np R build/sunmc run ...` splits the units across R
# ranks.  The choice is remembered in $(BUILD)/mpi.flag, so a later plain
# `make` or `make test` keeps it (MPI=0 switches back); every object is
# rebuilt when it changes.
# Reading the file while make parses writes nothing; the rule below rewrites
# it (only when the choice changed, so nothing rebuilds otherwise).
MPI ?= $(or $(shell cat $(BUILD)/mpi.flag 2>/dev/null),0)
ifeq ($(MPI),1)
CC := mpicc
MPI_CFLAGS := -DSUNMC_MPI
endif

# HDF5 (run --format hdf5, src/util/h5out.c): Debian's libhdf5-dev names its
# pkg-config file hdf5 (Debian 13) or hdf5-serial (Debian 12).
HDF5_PC    := $(firstword $(foreach p,hdf5 hdf5-serial,$(shell pkg-config --exists $(p) 2>/dev/null && echo $(p))))
HDF5_CFLAGS := $(if $(HDF5_PC),$(shell pkg-config --cflags $(HDF5_PC)),-I/usr/include/hdf5/serial)
HDF5_LIBS  := $(if $(HDF5_PC),$(shell pkg-config --libs $(HDF5_PC)),-L/usr/lib/$(shell uname -m)-linux-gnu/hdf5/serial -lhdf5)
# The library is not linked but loaded by `run --format hdf5` (dlopen,
# h5out.c): linked, it and its thirty-odd dependencies cost every sunmc
# process about 12 ms of CPU at start-up.  h5out.c is told its soname (read
# off the library the link would take), or the library's path.
HDF5_LIBDIRS := $(patsubst -L%,%,$(filter -L%,$(HDF5_LIBS))) /usr/lib/$(shell uname -m)-linux-gnu
HDF5_SO    := $(firstword $(wildcard $(addsuffix /lib$(patsubst -l%,%,$(firstword $(filter -lhdf5%,$(HDF5_LIBS)))).so,$(HDF5_LIBDIRS))))
HDF5_SONAME := $(if $(HDF5_SO),$(shell objdump -p $(HDF5_SO) 2>/dev/null | awk '/SONAME/ { print $$2 }'))
HDF5_LIB   := $(or $(HDF5_SONAME),$(HDF5_SO),libhdf5_serial.so)
PKG_CFLAGS := $(shell pkg-config --cflags gsl 2>/dev/null) $(HDF5_CFLAGS)
PKG_LIBS   := $(shell pkg-config --libs gsl 2>/dev/null) -ldl
CMOCKA_LIBS := $(shell pkg-config --libs cmocka 2>/dev/null || echo -lcmocka)

OPT ?= -O2
# Instruction-set baseline: x86-64-v2 (SSE4.2), which every x86-64 CPU of
# the last decade has; the kernels are also built for x86-64-v3 (AVX2) and
# chosen at run time (include/util/vmath.h).  ARCH= builds for any target.
ARCH ?= $(if $(filter x86_64,$(shell uname -m)),-march=x86-64-v2)
SUNMC_CFLAGS := -std=c11 -D_DEFAULT_SOURCE -DSUNMC_VERSION='"$(VERSION)"' -Wall -Wextra \
                -Wshadow -Wno-unused-parameter -g $(OPT) $(ARCH) -fopenmp $(PKG_CFLAGS) $(MPI_CFLAGS)
ALL_CFLAGS := $(SUNMC_CFLAGS) $(CFLAGS)
ALL_LDLIBS := $(PKG_LIBS) -lm -fopenmp $(LDFLAGS)

# Kernel files: the loops over a unit's readings and fit points, vectorised
# with glibc's vector math (include/util/vmath.h).  Only these get the flags
# it needs: -fno-math-errno (libm calls may skip errno, so GCC may call the
# vector versions), -fno-trapping-math (no floating-point traps, so floor
# and trunc vectorise and selects may compute both sides) and no sin/cos
# builtins (GCC would fuse a sin and a cos of one angle into a scalar
# sincos call).  None changes a result: IEEE rounding, NaN compares and
# isfinite work here as everywhere else.
KERNEL_SRC := src/util/rng.c src/util/fit.c src/ess/ess_model.c src/ess/ess_model_ext.c src/ess/ess_calib.c \
              src/ess/ess_sensor.c src/ess/ess_readings.c src/ess/ess_score.c src/dss/dss_readings.c \
              src/dss/dss_model_batch.c src/dss/dss_score.c src/dss/dss_onboard.c
KERNEL_CFLAGS := -DSUNMC_VMATH -fno-math-errno -fno-trapping-math -fno-builtin-sin -fno-builtin-cos
# KERNEL_ISA=baseline builds the kernels for the baseline only (no AVX2
# clone): every node of a mixed cluster then runs the same path, and its
# shards merge (manifest.ini records kernel_isa and build).
KERNEL_ISA ?=
ifeq ($(KERNEL_ISA),baseline)
ALL_CFLAGS += -DVM_FORCE_BASELINE
endif
# The build's identity in manifest.ini: the flags that move a result's bits.
$(BUILD)/obj/util/vmath.o $(BUILD)/asan/obj/util/vmath.o: \
    ALL_CFLAGS += -DSUNMC_BUILD_FLAGS='"$(strip $(OPT) $(ARCH) $(if $(filter baseline,$(KERNEL_ISA)),kernels baseline))"'

# Layers, one way: cli -> families -> core -> util.  Each layer compiles
# against its own headers and those below it only, so an include that
# points upward does not build.  The families are every folder of src/ that
# is not cli, core or util: adding a family is a folder (src/NAME/ and
# include/NAME/) and its line in src/core/registry.c, no line here.
FAMILIES := $(sort $(filter-out cli core util,$(notdir $(patsubst %/,%,$(wildcard src/*/)))))
LAYER_INC_util := -Iinclude/util
LAYER_INC_core := $(LAYER_INC_util) -Iinclude/core
$(foreach f,$(FAMILIES),$(eval LAYER_INC_$(f) := $$(LAYER_INC_core) -Iinclude/$(f)))
LAYER_INC_cli  := $(LAYER_INC_core) -Iinclude/cli
TEST_INC       := $(LAYER_INC_core) -Iinclude/cli $(FAMILIES:%=-Iinclude/%) -Itests
layer_inc = $(LAYER_INC_$(word 2,$(subst /, ,$(1))))

LAYERS   := util core $(FAMILIES)
MAIN_SRC := $(wildcard src/cli/*.c)
LIB_SRC  := $(foreach l,$(LAYERS),$(wildcard src/$(l)/*.c))
# The suites: tests/unit/<layer or family>/, tests/cli/ (commands end to
# end), tests/oracle/ (physics against independent derivations and the
# papers), found wherever they sit; a suite's binary is build/tests/<name>,
# so two suites may not share a name.
TEST_SRC := $(wildcard tests/test_*.c tests/*/test_*.c tests/*/*/test_*.c)
TEST_NAMES := $(notdir $(TEST_SRC:.c=))
ifneq ($(words $(TEST_NAMES)),$(words $(sort $(TEST_NAMES))))
$(error two test suites share a name: $(sort $(foreach n,$(TEST_NAMES),$(if $(filter-out 1,$(words $(filter $(n),$(TEST_NAMES)))),$(n)))))
endif
vpath test_%.c $(sort $(dir $(TEST_SRC)))
# A suite that moved leaves its old path in the compiler's .d file of an
# earlier build: that path is no longer a prerequisite to look for.
tests/test_%.c: ;

# Test-only code linked into every test (the toy family), and the commands
# without main() so that tests can run them in process.
TEST_HELP_SRC := $(filter-out tests/test_%,$(wildcard tests/*.c))
CLI_LIB_SRC := $(filter-out src/cli/main.c,$(MAIN_SRC))

LIB_OBJ  := $(LIB_SRC:src/%.c=$(BUILD)/obj/%.o)
TEST_OBJ := $(TEST_NAMES:%=$(BUILD)/tobj/%.o)
TEST_HELP_OBJ := $(TEST_HELP_SRC:tests/%.c=$(BUILD)/tobj/%.o)
TEST_BIN := $(TEST_NAMES:%=$(BUILD)/tests/%)
# The suites `make test-fast` and `make mutate` run: all but the mutation
# script's own test.  The golden comparison is among them (issue 29): a number
# only tests/golden/ records (a budget.tsv column, a params.ini digit) is still
# guarded against a mutant; it takes ~10 s and runs last (mutate.sh orders the
# suites by their time).
FAST_TEST_BIN := $(filter-out $(BUILD)/tests/test_mutate,$(TEST_BIN))

ASAN     := $(BUILD)/asan
ASAN_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
ASAN_OBJ := $(LIB_SRC:src/%.c=$(ASAN)/obj/%.o)
ASAN_TEST_OBJ := $(TEST_NAMES:%=$(ASAN)/tobj/%.o)
ASAN_TEST_HELP_OBJ := $(TEST_HELP_SRC:tests/%.c=$(ASAN)/tobj/%.o)
ASAN_TEST_BIN := $(TEST_NAMES:%=$(ASAN)/tests/%)

# Each object depends on the headers it includes (compiler-written .d files),
# so a header change recompiles only its includers; an object without its .d
# (a build from before this rule) is recompiled once.
DEPFLAGS = -MMD -MP
ALL_DEP := $(LIB_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(TEST_HELP_OBJ:.o=.d) \
           $(MAIN_SRC:src/%.c=$(BUILD)/obj/%.d) $(ASAN_OBJ:.o=.d) $(ASAN_TEST_OBJ:.o=.d) \
           $(ASAN_TEST_HELP_OBJ:.o=.d) $(MAIN_SRC:src/%.c=$(ASAN)/obj/%.d)
$(ALL_DEP): ;
.PRECIOUS: $(ALL_DEP)
-include $(wildcard $(ALL_DEP))

# Test objects are kept: a change in the library only relinks the suites.
.SECONDARY: $(TEST_OBJ) $(ASAN_TEST_OBJ) $(TEST_HELP_OBJ) $(ASAN_TEST_HELP_OBJ)

.PHONY: FORCE all programs run test test-plain test-fast test-asan test-mpi deps clean install man plots figures claims docs-check docs-check-slow bench \
        reference golden mutate mutate-build mutate-tests fuzz fuzz-build fuzz-deps fuzz-import

# `make` alone compiles on every core: without a -j of the caller's it
# calls itself again with one (the two programs share no step to wait on,
# and a clean build on one core takes about a minute).
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
all:
	@case " $$MAKEFLAGS " in \
	  *" -j"*|*jobserver*) $(MAKE) --no-print-directory programs ;; \
	  *) $(MAKE) --no-print-directory -j$(JOBS) programs ;; \
	esac

programs: $(BUILD)/sunmc $(BUILD)/sunmc-baseline

# Install system packages only when something is missing.
deps:
	@if ! pkg-config --exists gsl cmocka 2>/dev/null || \
	    [ ! -f /usr/include/Random123/philox.h ] || \
	    { [ ! -f /usr/include/hdf5/serial/hdf5.h ] && [ ! -f /usr/include/hdf5.h ]; } || \
	    ! /usr/bin/python3 -c 'import h5py' >/dev/null 2>&1 || ! command -v gnuplot >/dev/null 2>&1 || \
	    ! command -v cc >/dev/null 2>&1 || ! /usr/bin/python3 -c 'import scipy.io' >/dev/null 2>&1; then \
	  echo "sunmc: installing missing system packages (scripts/install-deps.sh)"; \
	  MPI=$(MPI) bash scripts/install-deps.sh; \
	elif [ "$(MPI)" = 1 ] && ! command -v mpicc >/dev/null 2>&1; then \
	  echo "sunmc: installing MPI (scripts/install-deps.sh, MPI=1)"; \
	  MPI=1 bash scripts/install-deps.sh; \
	fi

# An MPI build installs MPI first when it is missing.
ifeq ($(MPI),1)
all: deps
endif

# The MPI tests (2 and 3 ranks, scripts/mpi-batch.sh) on an MPI build of
# its own (build/mpi/), for CI: the plain build stays as it is.  `make
# test` on an MPI build (make MPI=1) runs them too.
test-mpi:
	$(MAKE) --no-print-directory BUILD=$(BUILD)/mpi MPI=1 deps $(BUILD)/mpi/sunmc \
	    $(BUILD)/mpi/tests/test_mpi $(BUILD)/mpi/tests/test_cluster
	@SUNMC=$(BUILD)/mpi/sunmc bash tests/run-suite.sh $(BUILD)/mpi/tests/test_mpi \
	    $(BUILD)/mpi/tests/test_cluster > $(BUILD)/mpi/test-mpi.log; st=$$?; \
	    cat $(BUILD)/mpi/test-mpi.log; exit $$st

# Without GSL the first compile would fail on a raw "gsl/gsl_matrix.h: No
# such file": say which command installs the packages instead.
$(BUILD)/packages.ok:
	@if ! pkg-config --exists gsl 2>/dev/null && [ ! -f /usr/include/gsl/gsl_matrix.h ]; then \
	  echo "sunmc: GSL is not installed (gsl/gsl_matrix.h is missing): run 'make deps'" \
	       "(scripts/install-deps.sh installs GSL, cmocka, Random123 and gnuplot), then make" >&2; \
	  exit 1; fi
	@mkdir -p $(BUILD) && touch $@

$(BUILD)/mpi.flag: FORCE
	@mkdir -p $(BUILD); [ "$$(cat $@ 2>/dev/null)" = "$(MPI)" ] || echo $(MPI) > $@
FORCE:

# One template per build kind: $(1) the output folder, $(2) the compiler,
# $(3) the flags, $(4) extra prerequisites of each object.  The plain build
# ($(BUILD)) and the ASan+UBSan build ($(ASAN)) are two calls of it; the
# fuzz build below reuses its object and library rules.
define LIB_RULES
$(1)/obj/%.o: src/%.c $(1)/obj/%.d $(BUILD)/mpi.flag $(4)
	@mkdir -p $$(dir $$@)
	$(2) $(3) $$(DEPFLAGS) $$(call layer_inc,$$<) -c $$< -o $$@

$(1)/libsunmc.a: $$(LIB_SRC:src/%.c=$(1)/obj/%.o)
	rm -f $$@ && ar rcs $$@ $$^

# The commands without main(), so that tests can run them in process.
$(1)/libsunmc_cli.a: $$(CLI_LIB_SRC:src/%.c=$(1)/obj/%.o)
	rm -f $$@ && ar rcs $$@ $$^
endef

define BUILD_RULES
$(call LIB_RULES,$(1),$$(CC),$(2),$(3))

$(1)/sunmc: $$(MAIN_SRC:src/%.c=$(1)/obj/%.o) $(1)/libsunmc.a
	$$(CC) $(2) -o $$@ $$^ $$(ALL_LDLIBS)

$(1)/tobj/test_%.o: test_%.c $(1)/tobj/test_%.d $(BUILD)/mpi.flag
	@mkdir -p $$(dir $$@)
	$$(CC) $(2) $$(DEPFLAGS) $$(TEST_INC) -c $$< -o $$@

$(1)/tobj/%.o: tests/%.c $(1)/tobj/%.d $(BUILD)/mpi.flag
	@mkdir -p $$(dir $$@)
	$$(CC) $(2) $$(DEPFLAGS) $$(TEST_INC) -c $$< -o $$@

$(1)/tests/%: $(1)/tobj/%.o $$(TEST_HELP_SRC:tests/%.c=$(1)/tobj/%.o) $(1)/libsunmc_cli.a $(1)/libsunmc.a | $(1)/tests
	$$(CC) $(2) -o $$@ $$< $$(TEST_HELP_SRC:tests/%.c=$(1)/tobj/%.o) $(1)/libsunmc_cli.a \
	    $(1)/libsunmc.a $$(CMOCKA_LIBS) $$(ALL_LDLIBS)
endef

$(eval $(call BUILD_RULES,$(BUILD),$$(ALL_CFLAGS),| $$(BUILD)/packages.ok))
$(eval $(call BUILD_RULES,$(ASAN),$$(ALL_CFLAGS) $$(ASAN_FLAGS)))

$(KERNEL_SRC:src/%.c=$(BUILD)/obj/%.o) $(KERNEL_SRC:src/%.c=$(ASAN)/obj/%.o): \
    ALL_CFLAGS += $(KERNEL_CFLAGS)
$(BUILD)/obj/util/h5out.o $(ASAN)/obj/util/h5out.o: ALL_CFLAGS += -DSUNMC_HDF5_LIB='"$(HDF5_LIB)"'


# sunmc-baseline: the same program with the kernels (and vmath.o's build
# id) built for the baseline only.  `sunmc run --isa baseline` and
# SUNMC_ISA=baseline run it on any CPU, so the shards of a mixed cluster
# merge (issue 22, rule 3).  Only these objects differ from the plain build.
BASE_OBJ := $(KERNEL_SRC:src/%.c=$(BUILD)/base/%.o) $(BUILD)/base/util/vmath.o
$(BUILD)/base/%.o: src/%.c $(BUILD)/obj/%.o
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(KERNEL_CFLAGS) -DVM_FORCE_BASELINE $(call layer_inc,$<) -c $< -o $@
$(BUILD)/base/util/vmath.o: src/util/vmath.c $(BUILD)/obj/util/vmath.o
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -DVM_FORCE_BASELINE \
	    -DSUNMC_BUILD_FLAGS='"$(strip $(OPT) $(ARCH) kernels baseline)"' \
	    $(call layer_inc,$<) -c $< -o $@
$(BUILD)/sunmc-baseline: $(MAIN_SRC:src/%.c=$(BUILD)/obj/%.o) $(BASE_OBJ) \
    $(filter-out $(KERNEL_SRC:src/%.c=$(BUILD)/obj/%.o) $(BUILD)/obj/util/vmath.o,$(LIB_SRC:src/%.c=$(BUILD)/obj/%.o))
	$(CC) $(ALL_CFLAGS) -o $@ $^ $(ALL_LDLIBS)

$(BUILD)/tests $(ASAN)/tests:
	mkdir -p $@

run: deps
	$(MAKE) --no-print-directory all
	$(BUILD)/sunmc run configs/ess_type_a.ini --out runs/ess_type_a
	$(BUILD)/sunmc run configs/ess_type_b.ini --out runs/ess_type_b
	$(BUILD)/sunmc run configs/dss.ini --out runs/dss
	$(BUILD)/sunmc run configs/psd.ini --out runs/psd

test: deps
	$(MAKE) --no-print-directory test-plain test-asan
	@bash tests/summarize.sh $(BUILD)/test-plain.log $(ASAN)/test-asan.log $(SUMMARY_EXTRA)

test-plain: $(BUILD)/sunmc $(BUILD)/sunmc-baseline $(TEST_BIN)
	@SUNMC=$(BUILD)/sunmc bash tests/run-suite.sh $(TEST_BIN) | tee $(BUILD)/test-plain.log

test-fast: $(BUILD)/sunmc $(BUILD)/sunmc-baseline $(FAST_TEST_BIN)
	@SUNMC=$(BUILD)/sunmc bash tests/run-suite.sh $(FAST_TEST_BIN)

test-asan: $(ASAN)/sunmc $(ASAN_TEST_BIN)
	@mkdir -p $(ASAN)
	@ASAN_OPTIONS=detect_leaks=1 SUNMC=$(ASAN)/sunmc bash tests/run-suite.sh $(ASAN_TEST_BIN) | tee $(ASAN)/test-asan.log

# Mutation testing (scripts/dev/mutate.sh, tests/mutants.txt): each mutant is
# applied to a copy of the tree, built incrementally there (mutate-build) and
# the suites listed by mutate-tests are run.  Not part of `make test`.
#   make mutate [MUTANTS=FILE] [ONLY=REGEX]
mutate:
	bash scripts/dev/mutate.sh $(if $(MUTANTS),--list $(MUTANTS)) $(if $(ONLY),--only '$(ONLY)')

mutate-build: $(BUILD)/sunmc $(FAST_TEST_BIN)

mutate-tests:
	@echo $(FAST_TEST_BIN)

# The reference config is generated from the key table; a test checks it is current.
reference: $(BUILD)/sunmc
	$(BUILD)/sunmc config --reference > configs/reference.ini

# Golden outputs (tests/golden/): re-record them only for a change that is
# meant to move a number, and say why in the commit.
golden: $(BUILD)/sunmc
	bash tests/golden.sh $(BUILD)/sunmc tests/golden

# Figures: `make plots RUN=DIR` draws what a run directory holds, next to it;
# `make figures` rebuilds the papers' figures into $(BUILD)/figures/.
plots: $(BUILD)/sunmc
	@test -n "$(RUN)" || { echo "usage: make plots RUN=DIR [svg=1]" >&2; exit 2; }
	bash scripts/plots.sh $(RUN) $(if $(filter 1,$(svg)),svg)

figures: $(BUILD)/sunmc
	SUNMC=$(BUILD)/sunmc bash scripts/figures.sh

# `make docs-check` re-runs the commands of the docs whose numbers the pages
# quote (marked `<!-- check: ... -->`, scripts/docs-check.py) and fails when
# a quoted number differs from the printed one beyond the page's tolerance.
# `make docs-check-slow` runs the marks too slow for that
# (`<!-- check-slow: ... -->`, minutes each; not in `make test` or CI's time);
# DOCS_CHECK_SLOW=1 make docs-check runs both.
docs-check: $(BUILD)/sunmc
	SUNMC=$(BUILD)/sunmc /usr/bin/python3 scripts/docs-check.py

docs-check-slow: $(BUILD)/sunmc
	SUNMC=$(BUILD)/sunmc /usr/bin/python3 scripts/docs-check.py --slow

# `make claims` checks the papers' claims row by row and rewrites docs/claims.md.
claims: $(BUILD)/sunmc
	SUNMC=$(BUILD)/sunmc bash scripts/claims.sh

# Fuzzing (tests/fuzz/: libFuzzer harnesses for the INI config, --set lists,
# the CSV reader, params.ini + compensate and the command line's argument
# vectors, each with a seed corpus).  The
# library is rebuilt with clang and -fsanitize=fuzzer-no-link,address,undefined
# into $(FUZZ)/; each harness runs FUZZ_SECONDS seconds from its seeds plus
# what earlier runs found ($(FUZZ)/corpus/NAME); crashes are written to
# $(FUZZ)/crash-NAME-*.  clang is installed on demand (FUZZ=1
# scripts/install-deps.sh), never for `make test`.  Then the importers of the
# public PSD data (scripts/psd-import.py, psd-score.py) are fuzzed for
# FUZZ_SECONDS by a Python loop (scripts/dev/fuzz-import.py; `make
# fuzz-import` alone): exit 0 or 2, no traceback, nothing written on a
# refusal, no temporary file left; failing cases in $(FUZZ)/import/crash-*.
FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
FUZZ := $(BUILD)/fuzz
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
FUZZ_CFLAGS := -std=c11 -D_DEFAULT_SOURCE -DSUNMC_VERSION='"$(VERSION)"' -g -O1 -fopenmp \
               $(PKG_CFLAGS) $(FUZZ_SAN)
FUZZ_OBJ := $(LIB_SRC:src/%.c=$(FUZZ)/obj/%.o)
FUZZ_HARNESS := $(wildcard tests/fuzz/fuzz_*.c)
FUZZ_BIN := $(FUZZ_HARNESS:tests/fuzz/%.c=$(FUZZ)/%)

fuzz-deps:
	@command -v $(FUZZ_CC) >/dev/null 2>&1 || { echo "sunmc: installing clang for make fuzz"; \
	  FUZZ=1 bash scripts/install-deps.sh; }

# The same object and library rules as the other builds (a header change
# recompiles its includers through the .d files); libsunmc_cli.a holds the
# commands for the command-line harness (fuzz_argv).
$(eval $(call LIB_RULES,$(FUZZ),$$(FUZZ_CC),$$(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link))
FUZZ_DEP := $(FUZZ_OBJ:.o=.d) $(CLI_LIB_SRC:src/%.c=$(FUZZ)/obj/%.d)
$(FUZZ_DEP): ;
.PRECIOUS: $(FUZZ_DEP)
-include $(wildcard $(FUZZ_DEP))

$(FUZZ)/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_util.h $(FUZZ)/libsunmc_cli.a $(FUZZ)/libsunmc.a
	$(FUZZ_CC) $(FUZZ_CFLAGS) -fsanitize=fuzzer $(TEST_INC) -o $@ $< $(FUZZ)/libsunmc_cli.a \
	    $(FUZZ)/libsunmc.a $(PKG_LIBS) -lm

fuzz-build: fuzz-deps
	$(MAKE) --no-print-directory $(FUZZ_BIN)

fuzz: fuzz-build
	@for h in $(FUZZ_BIN); do \
	  n=$${h##*/fuzz_}; mkdir -p $(FUZZ)/corpus/$$n; \
	  echo "== fuzz $$n: $(FUZZ_SECONDS) s"; \
	  ASAN_OPTIONS=detect_leaks=1 $$h -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
	      -timeout=10 -rss_limit_mb=2048 -artifact_prefix=$(FUZZ)/crash-$$n- \
	      $(FUZZ)/corpus/$$n tests/fuzz/corpus/$$n > $(FUZZ)/$$n.log 2>&1; st=$$?; \
	  grep -E '^#[0-9]+ +DONE|^stat::(number_of_executed_units|new_units_added)|ERROR|SUMMARY' \
	      $(FUZZ)/$$n.log; \
	  test $$st -eq 0 || { echo "fuzz $$n: FAILED (see $(FUZZ)/$$n.log)"; exit 1; }; \
	done; echo "fuzz: every harness ran clean"
	@$(MAKE) --no-print-directory fuzz-import

fuzz-import: deps
	@echo "== fuzz import: $(FUZZ_SECONDS) s"
	@/usr/bin/python3 scripts/dev/fuzz-import.py --seconds $(FUZZ_SECONDS) --work $(FUZZ)/import

# The transcendental floor (scripts/dev/bench-floor.c): the vector math calls of one
# ESS type A unit before issue 27, and nothing else, in the kernels' flags.
$(BUILD)/bench-floor: scripts/dev/bench-floor.c include/util/vmath.h
	$(CC) $(ALL_CFLAGS) $(KERNEL_CFLAGS) $(LAYER_INC_util) -o $@ $< -lm

bench: $(BUILD)/sunmc $(BUILD)/bench-floor
	bash scripts/dev/bench.sh $(BUILD)/sunmc

install: $(BUILD)/sunmc $(BUILD)/sunmc-baseline
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/sunmc/configs $(DESTDIR)$(PREFIX)/share/sunmc/scripts
	install -m 755 $(BUILD)/sunmc $(DESTDIR)$(PREFIX)/bin/sunmc
	install -m 755 $(BUILD)/sunmc-baseline $(DESTDIR)$(PREFIX)/bin/sunmc-baseline
	install -m 644 configs/*.ini $(DESTDIR)$(PREFIX)/share/sunmc/configs/
	install -m 644 $(wildcard scripts/*.gp) $(DESTDIR)$(PREFIX)/share/sunmc/scripts/
	install -m 755 scripts/plots.sh scripts/slurm-array.sh scripts/mpi-batch.sh \
	    $(DESTDIR)$(PREFIX)/share/sunmc/scripts/
	install -d $(DESTDIR)$(PREFIX)/share/man/man1 $(DESTDIR)$(PREFIX)/share/bash-completion/completions
	install -m 644 man/sunmc.1 $(DESTDIR)$(PREFIX)/share/man/man1/sunmc.1
	install -m 644 scripts/sunmc-completion.bash $(DESTDIR)$(PREFIX)/share/bash-completion/completions/sunmc

# The man page is made from the binary's --help texts (tests/cli/test_help_man.c checks it).
man: $(BUILD)/sunmc
	bash scripts/dev/gen-man.sh $(BUILD)/sunmc > man/sunmc.1

clean:
	rm -rf $(BUILD)
