#!/usr/bin/env bash
# The package, tested as an integrator uses it: `cmake --install` the build
# into a fresh prefix, build examples/host_app against it with find_package,
# run it on ES 3.0 and ES 2.0 (it makes its own EGL context and framebuffer
# and checks its own GL state survived), build it again through pkg-config,
# and check what the binary pulled in: the renderer, and not the reference
# tracer, the benchmark, the JSON parser or the command-line code. Every
# installed header must compile alone under strict warnings, and the README's
# integration snippet must compile against the install.
set -euo pipefail
build_dir=$1 source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; exit 1; }
for f in lib/libparallax_core.a lib/libparallax_gl.a lib/libparallax_render.a lib/cmake/ParallaxES/ParallaxESConfig.cmake \
         lib/pkgconfig/parallaxes.pc include/parallaxes/render/renderer.h include/parallaxes/core/result.h \
         include/parallaxes/version.h; do
    [ -f "$prefix/$f" ] || { echo "FAIL: the install has no $f"; exit 1; }
done
# Nothing in the installed headers may point back into the source or build tree.
if grep -rlE "$source_dir|$build_dir" "$prefix/include" "$prefix/lib/cmake" "$prefix/lib/pkgconfig"; then
    echo "FAIL: installed files name the build or source tree"; exit 1
fi

# One prefix: every header under include/parallaxes/, nothing else in include/.
others=$(find "$prefix/include" -mindepth 1 -maxdepth 1 ! -name parallaxes)
[ -z "$others" ] || { echo "FAIL: headers outside include/parallaxes/: $others"; exit 1; }
# No debug info in the installed static libraries (PX_INSTALL_DEBUG_INFO=OFF).
for lib in "$prefix"/lib/libparallax_*.a; do
    if readelf -S --wide "$lib" 2>/dev/null | grep -q '\.debug_info'; then
        echo "FAIL: $lib carries debug information"; exit 1
    fi
done
echo "ok: static libraries without debug info, $(du -cb "$prefix"/lib/libparallax_*.a | tail -1 | cut -f1) bytes"

# Each public header alone, as a host's strict build compiles it.
strict=(-std=c++17 -fsyntax-only -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Werror)
header_failures=0
while read -r header; do
    printf '#include "%s"\n' "$header" >"$work/header.cpp"
    if ! c++ "${strict[@]}" -I"$prefix/include" "$work/header.cpp" >"$work/header.log" 2>&1; then
        echo "FAIL: $header does not compile cleanly under ${strict[*]}:"; head -5 "$work/header.log"
        header_failures=$((header_failures + 1))
    fi
done < <(cd "$prefix/include" && find parallaxes -name '*.h' | sort)
[ "$header_failures" -eq 0 ] || exit 1
echo "ok: every installed header compiles alone under ${strict[*]}"

# The README's snippets, extracted (each cpp block after a
# "<!-- snippet: NAME" marker) and compiled against the install as printed.
snippets=0
for name in $(sed -n 's/^<!-- snippet: \([a-z-]*\).*/\1/p' "$source_dir/README.md"); do
    awk -v name="$name" '$0 ~ "<!-- snippet: " name {on = 1; next} on && /^```cpp/ {code = 1; next} code && /^```/ {exit} code' \
        "$source_dir/README.md" >"$work/snippet-$name.cpp"
    [ -s "$work/snippet-$name.cpp" ] || { echo "FAIL: the README's snippet '$name' has no cpp block"; exit 1; }
    c++ -std=c++17 -c -Wall -Wextra -Werror -I"$prefix/include" "$work/snippet-$name.cpp" -o "$work/snippet-$name.o" ||
        { echo "FAIL: the README's snippet '$name' does not compile against the install"; exit 1; }
    echo "ok: the README's snippet '$name' compiles ($(wc -l <"$work/snippet-$name.cpp") lines)"
    snippets=$((snippets + 1))
done
[ "$snippets" -ge 2 ] || { echo "FAIL: expected the integration and program-binaries snippets, found $snippets"; exit 1; }

# find_package(ParallaxES), as examples/host_app/CMakeLists.txt does.
cmake -S "$source_dir/examples/host_app" -B "$work/host" -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" 2>&1 ||
    { cat "$work/configure.log"; exit 1; }
cmake --build "$work/host" -j 2 >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
app="$work/host/host_app"
"$app" --es 3 --frames 3
"$app" --es 2 --frames 2

# ParallaxES::planner, the target the library's messages name for effects.
mkdir -p "$work/planned"
cat >"$work/planned/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(planned LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(ParallaxES 0.3 REQUIRED)
add_executable(planned main.cpp)
target_link_libraries(planned PRIVATE ParallaxES::planner)
CMAKE
cat >"$work/planned/main.cpp" <<'CPP'
#include "parallaxes/planner/planner.h"
#include "parallaxes/render/renderer.h"
int main() {
    px::RendererOptions options;
    options.effect_planner = px::effect_planner;
    return options.effect_planner ? 0 : 1;
}
CPP
cmake -S "$work/planned" -B "$work/planned/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/planned.log" 2>&1 &&
    cmake --build "$work/planned/build" >>"$work/planned.log" 2>&1 ||
    { cat "$work/planned.log"; echo "FAIL: an app linking ParallaxES::planner does not build"; exit 1; }
planned_symbols=$(nm -C "$work/planned/build/planned")
grep -q "px::ScenePlanner" <<<"$planned_symbols" || { echo "FAIL: ParallaxES::planner linked no effect planner"; exit 1; }
echo "ok: an app linking ParallaxES::planner builds and holds the effect planner"

# What a host app pulls in: the renderer, none of the rest.
symbols=$(nm -C "$app")
grep -q "px::Renderer::draw" <<<"$symbols" || { echo "FAIL: no px::Renderer::draw in host_app (nm read nothing?)"; exit 1; }
# The app names no file and no effect, so it links no JSON parser, no effect
# planner or cost table, and no image or container reader or codec: those
# come in with RendererOptions::effect_planner and ::texture_files.
# (No pipe into head under pipefail: a grep killed by SIGPIPE on a long
# list would read as "nothing found". PX_LEAK_PATTERN replaces the pattern:
# set it to a symbol the app has, say px::Renderer::draw, to see this fail.)
default_leaks='px::reference::|px::profiling::|px::tools::|CLI::|nlohmann|px::ScenePlanner|px::CostTable|px::measure_relief'
default_leaks+='|px::effect_planner|px::decode_(etc|astc|bc|pvrtc|rgba8)|px::read_(ktx1|ktx2|pvr3|texture)|px::load_image'
default_leaks+='|px::write_png|stbi_|jpeg_|ZSTD_|astcenc_'
leaked=$(grep -E "${PX_LEAK_PATTERN:-$default_leaks}" <<<"$symbols" || true)
if [ -n "$leaked" ]; then
    echo "FAIL: host_app pulls in code a host does not need ($(wc -l <<<"$leaked") symbols), first:"
    sed -n 1,5p <<<"$leaked"; exit 1
fi
# Nor the libraries only files need, at run time.
needed=$(readelf -d "$app" | grep NEEDED || true)
if grep -qE "libjpeg|libzstd|libastcenc" <<<"$needed"; then
    echo "FAIL: host_app needs a file library at run time:"; echo "$needed"; exit 1
fi
strip -o "$work/host_app.stripped" "$app"
echo "ok: host_app built with find_package, $(stat -c %s "$work/host_app.stripped") bytes stripped"

# pkg-config, the same program.
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
flags=$(pkg-config --cflags --libs parallaxes) || { echo "FAIL: pkg-config cannot read parallaxes.pc"; exit 1; }
# shellcheck disable=SC2086
c++ -std=c++17 -O1 "$source_dir/examples/host_app/main.cpp" -o "$work/host_app_pc" $flags -lEGL -Wl,--gc-sections -Wl,--as-needed
"$work/host_app_pc" --es 3
echo "ok: host_app built with pkg-config ($flags)"
