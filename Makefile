# The two commands (README): `make run` and `make test`. Both install missing Debian packages first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
ifdef CI
CMAKE_FLAGS += -DIBVALVE_WERROR=ON
endif
RUN_CASE ?= examples/aortic_valve/default.toml
# The run folder follows the case: examples/lumped/default.toml runs in runs/lumped_default, so one
# case's run never replaces another's (give RUN_DIR to choose).
RUN_DIR ?= runs/$(notdir $(patsubst %/,%,$(dir $(RUN_CASE))))_$(basename $(notdir $(RUN_CASE)))
RUN_RANKS ?= 2

# No "Entering directory" lines from make itself or from the make that cmake --build starts.
MAKEFLAGS += --no-print-directory

export OMPI_ALLOW_RUN_AS_ROOT = 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM = 1

.PHONY: run test nightly bench build quiet-build deps configure format clean regression-reference

run: quiet-build
	mpiexec --oversubscribe -n $(RUN_RANKS) $(BUILD_DIR)/app/ibvalve run $(RUN_CASE) -o $(RUN_DIR) --overwrite
	@echo "Run folder: $(RUN_DIR)  (report: $(RUN_DIR)/report/report.html)"

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -LE nightly

nightly: build
	cd $(BUILD_DIR) && ctest --output-on-failure -L nightly

# Rewrite the regression suite's stored results from this build (tests/regression/README.md says when).
regression-reference: build
	scripts/refresh-regression-reference $(BUILD_DIR)

bench: build
	cmake --build $(BUILD_DIR) --target all -j $(JOBS)
	@echo "Benchmarks are in $(BUILD_DIR)/bench/ (see bench/README.md)"

deps:
	@scripts/install-deps

configure: deps
	@mkdir -p $(BUILD_DIR)
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD_DIR)/configure.log 2>&1 || { cat $(BUILD_DIR)/configure.log; exit 1; }

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# `make run` builds in one line: the compiler's output goes to build/build.log, shown whole when the
# build fails.
quiet-build: configure
	@echo "Building ibvalve (the build's output: $(BUILD_DIR)/build.log)"
	@cmake --build $(BUILD_DIR) -j $(JOBS) > $(BUILD_DIR)/build.log 2>&1 || { cat $(BUILD_DIR)/build.log; \
	  echo "The build failed: its output is above and in $(BUILD_DIR)/build.log"; exit 1; }

format:
	find . -path ./$(BUILD_DIR) -prune -o \( -name '*.cpp' -o -name '*.hpp' \) -print | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
