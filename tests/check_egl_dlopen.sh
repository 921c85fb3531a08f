#!/usr/bin/env bash
# libEGL is opened with dlopen in every build type, never linked: a missing or
# broken libEGL then gets platform/'s message instead of a loader error. The
# binaries that use platform/ must not list libEGL among their needed
# libraries, and must carry the name they dlopen.
set -euo pipefail
status=0
for binary in "$@"; do
    needed=$(readelf -d "$binary" | grep NEEDED) || { echo "FAIL: readelf found no NEEDED entries in $binary"; exit 1; }
    grep -q 'libc\.so' <<<"$needed" || { echo "FAIL: no libc among $binary's needed libraries (readelf output changed?)"; exit 1; }
    if grep -q 'libEGL' <<<"$needed"; then
        echo "FAIL: $binary links libEGL directly:"; grep libEGL <<<"$needed"; status=1
    elif ! grep -q 'libEGL.so.1' <(strings "$binary"); then
        echo "FAIL: $binary neither links nor names libEGL.so.1"; status=1
    else
        echo "ok: $(basename "$binary") opens libEGL.so.1 with dlopen"
    fi
done
exit $status
