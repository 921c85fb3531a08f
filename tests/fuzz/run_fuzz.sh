#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time from the committed seed
# corpus. New inputs go to the build folder, never into the repository.
# Usage: run_fuzz.sh TARGET SEED_DIR WORK_DIR SECONDS [DICTIONARY]
set -uo pipefail
target=$1 seeds=$2 work=$3 seconds=$4 dict=${5:-}
mkdir -p "$work/corpus" "$work/artifacts"
args=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=3072 -malloc_limit_mb=3072
      -print_final_stats=1 -artifact_prefix="$work/artifacts/")
[ -n "$dict" ] && [ -f "$dict" ] && args+=(-dict="$dict")
# Leaks count as findings: the library is GL-free here.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
"$target" "${args[@]}" "$work/corpus" "$seeds" >"$work/log.txt" 2>&1
status=$?
grep -E '^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb)' "$work/log.txt" || true
if [ "$status" != 0 ]; then
    tail -60 "$work/log.txt"
    echo "FUZZ FINDING in $(basename "$target"): the input is in $work/artifacts/;"
    echo "reproduce with: $target $work/artifacts/<file>, then add it as a test in tests/unit_hostile.cpp"
    exit 1
fi
echo "$(basename "$target"): no finding in $seconds s"
