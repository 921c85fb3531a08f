# ParallaxES: the two commands of the quick start, and their parts.
#   make run    install missing Debian packages, build, render out/default.png
#   make test   the same set-up, then the whole suite through ctest
MAKEFLAGS += --no-print-directory
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

# Debian 12 packages the build and the tests need.
DEBIAN_PACKAGES := cmake make g++ libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
	libglm-dev libstb-dev nlohmann-json3-dev libcli11-dev googletest libgtest-dev glslang-tools

.PHONY: all deps configure build run test clean

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

clean:
	rm -rf $(BUILD_DIR) out
