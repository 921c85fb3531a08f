#!/usr/bin/env bash
# The planner suite (examples/scenes/planner_suite/, made by make_suite.py):
# every scene planned with --verify on ES 3.0 and ES 2.0, and a table of
# the variant chosen, the hit error predicted and measured (p95, texels of
# the level sampled) beside the target, measured over predicted, the
# verdict, and (--candidates) the cheapest candidate that measures within
# the targets with the plan's time over its time (the goal: at most 1.25).
# A benchmark, not part of `make test` (about ten minutes here).
#   tests/planner_suite.sh PARALLAX [SIZE] > table.md
set -uo pipefail
parallax=${1:-build/parallax}
size=${2:-256x256}
dir=$(cd "$(dirname "$0")/../examples/scenes/planner_suite" && pwd)
echo "Measured by \`tests/planner_suite.sh $parallax $size\` on $(date -u +%Y-%m-%d); $("$parallax" texinfo --formats --es 3 | sed -n 1p | sed 's/^context *//')."
echo
echo "| scene | ES | variant | target | predicted | measured | measured / predicted | verdict | cheapest within the targets | plan time / its time |"
echo "|---|---|---|---|---|---|---|---|---|---|"
met=0 missed=0 failed=0 over=0
for scene in "$dir"/*.json; do
    name=$(basename "$scene" .json)
    for es in 3 2; do
        out=$("$parallax" plan "$scene" --size "$size" --es "$es" --verify --candidates 2>&1)
        line=$(grep '^  ground (' <<<"$out" | head -1)
        if [ -z "$line" ]; then
            echo "| $name | $es | error: $(grep 'error' <<<"$out" | head -1 | cut -c1-120) | | | | | | | |"
            failed=$((failed + 1))
            continue
        fi
        variant=$(sed -E 's/^  ground \(([^)]*)\).*/\1/' <<<"$line")
        hit=${line%%;*}  # the hit part; a shadow's follows the ';'
        hit=${hit% (*px)}
        measured=$(sed -E 's/.*: hit ([^ ]+) measured.*/\1/' <<<"$hit")
        predicted=$(sed -nE 's/.*measured, ([^ ]+) predicted.*/\1/p' <<<"$hit")
        target=$(sed -nE 's/.*target ([^:]+): (met|MISSED).*/\1/p' <<<"$hit")
        verdict=$(grep -q MISSED <<<"$line" && echo MISSED || echo met)
        ratio=$(awk -v m="$measured" -v p="$predicted" 'BEGIN { if (p > 0) printf "%.2f", m / p; else print "-" }')
        shadow=$(sed -nE 's/.*; shadow ([^ ]+) measured, ([^ ]+) predicted, target ([^:]+): (met|MISSED).*/ (shadow \1 vs \2, target \3)/p' <<<"$line")
        cheapest=$(sed -nE 's/.*cheapest within the targets: (.*) at x.*/\1/p' <<<"$out")
        spends=$(sed -nE 's/.*the plan spends ([0-9.]+)x what it must.*/\1/p' <<<"$out")
        [ -n "$spends" ] && awk -v s="$spends" 'BEGIN { exit !(s > 1.25) }' && over=$((over + 1))
        echo "| $name | $es | $variant | $target | $predicted | $measured | $ratio | $verdict$shadow | ${cheapest:-none} | ${spends:--} |"
        if [ "$verdict" = met ]; then met=$((met + 1)); else missed=$((missed + 1)); fi
    done
done
echo
echo "$met met, $missed missed, $failed not planned; $over plans over 1.25 times the cheapest candidate within the targets."
