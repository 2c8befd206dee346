# The two commands (README): `make run` and `make test`. Both install missing Debian packages first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
ifdef CI
CMAKE_FLAGS += -DIBVALVE_WERROR=ON
endif
RUN_CASE ?= examples/aortic_valve/default.toml
RUN_DIR ?= runs/default
RUN_RANKS ?= 2

export OMPI_ALLOW_RUN_AS_ROOT = 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM = 1

.PHONY: run test nightly bench build deps configure format clean regression-reference

run: build
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
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD_DIR).configure.log 2>&1 || { cat $(BUILD_DIR).configure.log; exit 1; }

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

format:
	find . -path ./$(BUILD_DIR) -prune -o \( -name '*.cpp' -o -name '*.hpp' \) -print | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log
