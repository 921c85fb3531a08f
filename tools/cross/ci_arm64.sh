#!/usr/bin/env bash
# The arm64 step of .ci/run, within about 10 minutes on two cores: the arm64
# sysroot (tools/cross/make_sysroot.sh, which installs the cross compiler and
# qemu-user), `parallax` cross-built (Release, the CLI and the library only:
# the test executables take as long again), and the cross set's tests
# labelled "ci" under qemu-aarch64: the default-samples render that crashed
# llvmpipe on arm64 (render_multisampled), the goldens through the CLI with
# the CPU's tolerances (compare_cli) and the planner's choices drawn and
# checked (plan_verify). The whole cross set: `ctest --preset arm64` after
# `cmake --build --preset arm64` (README, "ARM builds").
#   tools/cross/ci_arm64.sh [BUILD_DIR]   (default build-arm64-ci)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build-arm64-ci}
start=$(date +%s)
bash "$root/tools/cross/make_sysroot.sh" arm64 >/dev/null
echo "ci_arm64: sysroot ready ($(( $(date +%s) - start )) s)"
mkdir -p "$build"
cmake -S "$root" -B "$build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/arm64.cmake" -DCMAKE_BUILD_TYPE=Release \
    >"$build/ci-configure.log" 2>&1 || { cat "$build/ci-configure.log"; exit 1; }
cmake --build "$build" --target parallax_cli -j "$(nproc)" >"$build/ci-build.log" 2>&1 ||
    { tail -40 "$build/ci-build.log"; exit 1; }
echo "ci_arm64: parallax built for arm64 ($(( $(date +%s) - start )) s)"
ctest --test-dir "$build" -L '^ci$' --output-on-failure
echo "ci_arm64: done ($(( $(date +%s) - start )) s)"
