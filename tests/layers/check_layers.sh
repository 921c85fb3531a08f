#!/usr/bin/env bash
# Builds every layer probe (tests/layers/CMakeLists.txt) and checks that a
# backward include fails with "No such file" for exactly that header and that
# every control builds. (That the final tree has no backward include is shown
# by the tree building at all: every layer compiles with its own view.)
set -uo pipefail
build_dir=$1 probes=$2 source_dir=$3
status=0
while read -r probe layer header expect; do
    [ -z "$probe" ] && continue
    out=$(cmake --build "$build_dir" --target "$probe" 2>&1)
    rc=$?
    if [ "$expect" = fail ]; then
        if [ $rc -eq 0 ]; then
            echo "FAIL: $layer includes $header and it built (a backward include must not)"; status=1
        elif ! grep -q "$header: No such file or directory" <<<"$out"; then
            echo "FAIL: $layer including $header failed, but not for the missing header:"; echo "$out" | tail -5; status=1
        else
            echo "ok: $layer cannot include $header"
        fi
    else
        if [ $rc -ne 0 ]; then
            echo "FAIL: $layer cannot include $header, which is its own layer or below:"; echo "$out" | tail -5; status=1
        else
            echo "ok: $layer includes $header"
        fi
    fi
done <"$probes"
exit $status
