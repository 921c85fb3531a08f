#!/usr/bin/env bash
# The footprint a mobile app sees, built as the README's "Using it in your
# app" section says for a size-conscious build: the library configured
# MinSizeRel (-Os), installed, and examples/host_app linked against it with
# --gc-sections, then stripped. Fails past PX_FOOTPRINT_LIMIT bytes (default
# 400000) or when the app links the JSON parser, the effect planner, or any
# file reader or codec. Not part of `make test` (it builds the library a
# second time, about three minutes on two cores): .ci/run calls it.
# PX_FOOTPRINT_ARCH=arm64 or armhf builds it for that CPU instead
# (cmake/toolchains/, the sysroot of tools/cross/make_sysroot.sh) and runs
# the app under qemu-user; there the size is reported, and checked only
# against a PX_FOOTPRINT_LIMIT given.
#   tests/package/footprint.sh [SOURCE_DIR]
set -euo pipefail
source_dir=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
# The budget is 400,000 bytes. On 2026-12-06 the app measured 393,360
# before, 426,192 after the one GL state table, the variant field table and
# the named-technique planner (issue 46) entered the host's path; on
# 2026-12-07, 389,360 with link-time optimisation across the library (the
# package's MinSizeRel objects carry LTO code, PX_LTO; the host app links
# with -flto in MinSizeRel). README "Size" says what grew and what shrank it.
limit=${PX_FOOTPRINT_LIMIT:-400000}
if [ -n "${PX_FOOTPRINT_ARCH:-}" ]; then limit=${PX_FOOTPRINT_LIMIT:-999999999}; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cross=() run=() tools=""
case "${PX_FOOTPRINT_ARCH:-}" in
    "") ;;
    arm64|armhf)
        arch=$PX_FOOTPRINT_ARCH
        triplet=$([ "$arch" = arm64 ] && echo aarch64-linux-gnu || echo arm-linux-gnueabihf)
        sysroot=${PX_SYSROOT:-$HOME/.cache/parallaxes/sysroot/$arch}
        cross=(-DCMAKE_TOOLCHAIN_FILE="$source_dir/cmake/toolchains/$arch.cmake")
        run=("$([ "$arch" = arm64 ] && echo qemu-aarch64 || echo qemu-arm)" -L "$sysroot")
        [ "$arch" = armhf ] && run+=(-cpu cortex-r5f)  # linear filtering is right without NEON (README)
        tools="$triplet-" ;;
    *) echo "PX_FOOTPRINT_ARCH: '$PX_FOOTPRINT_ARCH' is not arm64 or armhf" >&2; exit 2 ;;
esac

cmake -S "$source_dir" -B "$work/build" "${cross[@]}" -DCMAKE_BUILD_TYPE=MinSizeRel -DPX_BUILD_TESTS=OFF >"$work/configure.log" ||
    { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j "$(nproc)" --target parallax_core parallax_gl parallax_render parallax_platform \
    >"$work/build.log" 2>&1 || { tail -30 "$work/build.log"; exit 1; }
# Only the library is built: install its component without the tools.
cmake --install "$work/build" --prefix "$work/prefix" >"$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }
# ParallaxES_DIR: a cross toolchain looks for packages in its sysroot alone.
cmake -S "$source_dir/examples/host_app" -B "$work/host" "${cross[@]}" -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DParallaxES_DIR="$(dirname "$(find "$work/prefix" -name ParallaxESConfig.cmake | head -1)")" \
    -DCMAKE_BUILD_TYPE=MinSizeRel >"$work/host.log" 2>&1 || { cat "$work/host.log"; exit 1; }
cmake --build "$work/host" >>"$work/host.log" 2>&1 || { cat "$work/host.log"; exit 1; }
app="$work/host/host_app"
"${run[@]}" "$app" --es 3 --frames 2

symbols=$(${tools}nm -C "$app")
# (With link-time optimisation Renderer::draw itself may be inlined into the
# app: any of the renderer's members shows that nm read the symbols.)
grep -q "px::Renderer::" <<<"$symbols" || { echo "FAIL: no px::Renderer member in host_app (nm read nothing?)"; exit 1; }
# px::CostTable's own members and its parser (not std::function<optional<
# CostTable>(...)>'s, which RendererOptions' calibration lookup holds, empty,
# and which link-time optimisation leaves named in the app).
leaks='nlohmann|px::ScenePlanner|px::CostTable::|px::(parse|builtin)_cost_table|px::cost_table_json|px::measure_relief'
leaks+='|px::effect_planner|px::decode_(etc|astc|bc|pvrtc|rgba8)'
leaks+='|px::read_(ktx1|ktx2|pvr3|texture)|px::load_image|stbi_|jpeg_|ZSTD_|astcenc_'
leaked=$(grep -E "${PX_LEAK_PATTERN:-$leaks}" <<<"$symbols" || true)
if [ -n "$leaked" ]; then
    echo "FAIL: host_app links code it does not use ($(wc -l <<<"$leaked") symbols), first:"
    sed -n 1,5p <<<"$leaked"; exit 1
fi
${tools}strip -o "$work/host_app.stripped" "$app"
bytes=$(stat -c %s "$work/host_app.stripped")
if [ "$bytes" -gt "$limit" ]; then
    echo "FAIL: host_app is $bytes bytes stripped (MinSizeRel), past the limit of $limit"; exit 1
fi
echo "ok: host_app${PX_FOOTPRINT_ARCH:+ for $PX_FOOTPRINT_ARCH} $bytes bytes stripped (library MinSizeRel with LTO, --gc-sections), limit $limit; no parser, planner or codec symbols"
