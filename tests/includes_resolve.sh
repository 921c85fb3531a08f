#!/usr/bin/env bash
# Every `#include "parallaxes/..."` in the tree names a file in the source
# tree at that path under include/ (the public headers sit where a host
# includes them from; the build's per-layer views only link to them), so a
# reader or a tool that follows includes as text finds each one without a
# build. Also: no header is left beside the sources in src/, platform/ or
# profiling/ except the private ones listed here.
#   tests/includes_resolve.sh SOURCE_DIR
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
private="src/texture/container_shape.h
src/planner/planner_detail.h"
missing=0 checked=0
while IFS= read -r file; do
    while IFS= read -r header; do
        checked=$((checked + 1))
        if [ ! -f "include/$header" ]; then
            echo "FAIL: $file includes \"$header\", and include/$header is not in the source tree"
            missing=$((missing + 1))
        fi
    done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\(parallaxes\/[^"]*\)".*/\1/p' "$file")
done < <(find src include platform profiling tools tests examples -type f \( -name '*.cpp' -o -name '*.h' \) | sort)
[ "$checked" -gt 500 ] || { echo "FAIL: only $checked includes found: is this the source tree?"; exit 1; }
stray=$(find src platform profiling -name '*.h' | sort | grep -vxF "$private" || true)
if [ -n "$stray" ]; then
    echo "FAIL: public headers outside include/parallaxes/ (move them, or list them as private here):"
    echo "$stray"
    exit 1
fi
[ "$missing" -eq 0 ] || exit 1
echo "ok: $checked includes of parallaxes/... each resolve to include/parallaxes/... in the source tree"
