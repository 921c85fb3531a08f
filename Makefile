# ParallaxES: the two commands of the quick start, and their parts.
#   make run    install missing Debian packages, build, render out/default.png
#   make test   the same set-up, then the whole suite through ctest
#   make sanitize  unit and GPU tests under AddressSanitizer and UBSan (clang,
#               own build folder), then the libFuzzer targets for a bounded time
#   make web    the viewer page (Emscripten, build-web/web/; docs/web.md)
#   make web-test  the page in headless chromium (tests/web/run.sh)
MAKEFLAGS += --no-print-directory
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

# Debian 12 packages the build and the tests need.
DEBIAN_PACKAGES := cmake make g++ libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
	libglm-dev libstb-dev libjpeg62-turbo-dev nlohmann-json3-dev libcli11-dev googletest libgtest-dev glslang-tools glslang-dev \
	libastcenc-dev libzstd-dev

.PHONY: all deps configure build run test sanitize sanitize-deps clean web web-test

all: build

deps:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do \
		dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed$$' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
		if [ "$$(id -u)" != 0 ]; then \
			echo "Missing Debian packages. Run as root:"; \
			echo "  apt-get install -y --no-install-recommends" $$missing; \
			exit 1; \
		fi; \
		echo "Installing:" $$missing; \
		DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing || \
		{ apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing; }; \
	fi

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || cmake -S . -B $(BUILD_DIR)

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	@$(BUILD_DIR)/parallax render default -o out/default.png --size 512x512 --es 3

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# --- make sanitize ---------------------------------------------------------------
SANITIZE_DIR ?= build-sanitize
FUZZ_SECONDS ?= 60
SANITIZE_PACKAGES := clang-14 libclang-rt-14-dev libfuzzer-14-dev llvm-14
SANITIZE_TARGETS := px_unit_tests px_report_tests px_cost_tests px_gpu_tests parallax_cli px_fuzz_scene px_fuzz_image px_fuzz_ktx1 px_fuzz_ktx2 px_fuzz_pvr
# Mesa's own allocations look like leaks to LeakSanitizer: leaks are checked
# where no GL runs (the unit tests, the fuzz targets), not in the GPU tests.
ASAN_BASE := abort_on_error=0:detect_stack_use_after_return=1:strict_string_checks=1:check_initialization_order=1
UBSAN_OPTS := print_stacktrace=1:halt_on_error=1

sanitize-deps:
	@$(MAKE) deps DEBIAN_PACKAGES="$(DEBIAN_PACKAGES) $(SANITIZE_PACKAGES)"

sanitize: sanitize-deps
	@cmake -S . -B $(SANITIZE_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
		-DPX_SANITIZE=ON -DPX_FUZZ=ON -DPX_FUZZ_SECONDS=$(FUZZ_SECONDS) >/dev/null
	@cmake --build $(SANITIZE_DIR) -j $(JOBS) --target $(SANITIZE_TARGETS)
	@cd $(SANITIZE_DIR) && ASAN_OPTIONS=$(ASAN_BASE):detect_leaks=1 UBSAN_OPTIONS=$(UBSAN_OPTS) \
		ctest --output-on-failure -j $(JOBS) -R '^(unit|unit_reports|unit_costs)$$'
	@cd $(SANITIZE_DIR) && ASAN_OPTIONS=$(ASAN_BASE):detect_leaks=0 UBSAN_OPTIONS=$(UBSAN_OPTS) \
		ctest --output-on-failure -j $(JOBS) -R '^(gpu_es2|gpu_es3|cli_errors)$$'
	@cd $(SANITIZE_DIR) && ASAN_OPTIONS=$(ASAN_BASE):detect_leaks=1 UBSAN_OPTIONS=$(UBSAN_OPTS) \
		ctest --output-on-failure -j $(JOBS) -L fuzz

clean:
	rm -rf $(BUILD_DIR) $(SANITIZE_DIR) $(WEB_DIR) out

# --- make web: the library and the viewer page for browsers (docs/web.md) -------
# Debian's emscripten 3.1.6 finds its node modules (acorn) only through
# NODE_PATH. Serve build-web/web/ from a local web server to open it.
WEB_DIR ?= build-web
web:
	@$(MAKE) deps DEBIAN_PACKAGES="emscripten libglm-dev nlohmann-json3-dev libstb-dev"
	@NODE_PATH=/usr/share/nodejs emcmake cmake -S . -B $(WEB_DIR) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@NODE_PATH=/usr/share/nodejs cmake --build $(WEB_DIR) -j $(JOBS)
	@echo "the page: $(WEB_DIR)/web/index.html (serve it: python3 -m http.server -b 127.0.0.1 -d $(WEB_DIR)/web 8000)"

web-test: build
	@bash tests/web/run.sh
