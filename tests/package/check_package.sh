#!/usr/bin/env bash
# The package, tested as an integrator uses it: `cmake --install` the build
# into a fresh prefix, build examples/host_app against it with find_package,
# run it on ES 3.0 and ES 2.0 (it makes its own EGL context and framebuffer
# and checks its own GL state survived), build it again through pkg-config,
# and check what the binary pulled in: the renderer, and not the reference
# tracer, the benchmark, the JSON parser or the command-line code.
set -euo pipefail
build_dir=$1 source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; exit 1; }
for f in lib/libparallax_core.a lib/libparallax_gl.a lib/libparallax_render.a lib/cmake/ParallaxES/ParallaxESConfig.cmake \
         lib/pkgconfig/parallaxes.pc include/parallaxes/render/renderer.h include/parallaxes/core/result.h; do
    [ -f "$prefix/$f" ] || { echo "FAIL: the install has no $f"; exit 1; }
done
# Nothing in the installed headers may point back into the source or build tree.
if grep -rlE "$source_dir|$build_dir" "$prefix/include" "$prefix/lib/cmake" "$prefix/lib/pkgconfig"; then
    echo "FAIL: installed files name the build or source tree"; exit 1
fi

# find_package(ParallaxES), as examples/host_app/CMakeLists.txt does.
cmake -S "$source_dir/examples/host_app" -B "$work/host" -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" 2>&1 ||
    { cat "$work/configure.log"; exit 1; }
cmake --build "$work/host" -j 2 >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
app="$work/host/host_app"
"$app" --es 3
"$app" --es 2

# What a host app pulls in: the renderer, none of the rest.
symbols=$(nm -C "$app")
grep -q "px::Renderer::draw" <<<"$symbols" || { echo "FAIL: no px::Renderer::draw in host_app (nm read nothing?)"; exit 1; }
if leaked=$(grep -E "px::reference::|px::profiling::|px::tools::|nlohmann::|CLI::" <<<"$symbols" | head -5); then
    echo "FAIL: host_app pulls in code a host does not need:"; echo "$leaked"; exit 1
fi
strip -o "$work/host_app.stripped" "$app"
echo "ok: host_app built with find_package, $(stat -c %s "$work/host_app.stripped") bytes stripped"

# pkg-config, the same program.
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
flags=$(pkg-config --cflags --libs parallaxes) || { echo "FAIL: pkg-config cannot read parallaxes.pc"; exit 1; }
# shellcheck disable=SC2086
c++ -std=c++17 -O1 "$source_dir/examples/host_app/main.cpp" -o "$work/host_app_pc" $flags -lEGL -Wl,--gc-sections
"$work/host_app_pc" --es 3
echo "ok: host_app built with pkg-config ($flags)"
