#!/usr/bin/env bash
# `parallax compare` and `parallax render --golden` end to end (README
# "Regression runs"): a render of a built-in scene passes its committed golden
# under tests/golden/tolerances.json, another scene fails it, and bad input
# (size mismatch, missing or unreadable file, bad tolerances) exits 2 with a
# message naming the file. Exit statuses: 0 pass, 1 fail, 2 bad input.
# Usage: compare_cli.sh PARALLAX_BINARY SOURCE_DIR
set -uo pipefail
parallax=$1
source_dir=$2
golden=$source_dir/tests/golden
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The goldens are defined with llvmpipe's 8-bit filtering shortcut off
# (tests/CMakeLists.txt); caches of our own, none of the user's.
export GALLIVM_PERF=${GALLIVM_PERF:-no_aos_sampling}
export XDG_CACHE_HOME=$work/cache
render=(render --es 3 --frames 1 --program-cache off --calibration-cache off)
tolerances=(--tolerances "$golden/tolerances.json")
failures=0

# expect STATUS DESCRIPTION EXPECTED_TEXT ARGS...: the exit status, and the
# text in stdout + stderr.
expect() {
    local want=$1 description=$2 expected=$3
    shift 3
    local out
    out=$("$parallax" "$@" 2>&1)
    local status=$?
    if grep -q 'Sanitizer' <<<"$out"; then
        echo "FAIL: $description: a sanitizer report:"; echo "$out" | head -20; failures=$((failures + 1)); return
    fi
    if [ "$status" != "$want" ]; then
        echo "FAIL: $description: exit status $status, expected $want:"; echo "$out" | tail -5
        failures=$((failures + 1)); return
    fi
    if ! grep -qF -- "$expected" <<<"$out"; then
        echo "FAIL: $description: output lacks '$expected':"; echo "$out" | tail -5; failures=$((failures + 1)); return
    fi
    echo "ok: $description -> $(grep -F -- "$expected" <<<"$out" | head -1)"
}

# A render passes its golden (at the golden's size, 128x128), and the image it
# wrote passes compare.
expect 0 "render --golden: default matches its golden" "PASS $work/default.png vs $golden/default_es3.png" \
    "${render[@]}" default -o "$work/default.png" --golden "$golden/default_es3.png" "${tolerances[@]}"
expect 0 "compare: default with the golden tests' tolerances" "PASS $work/default.png" \
    compare "$work/default.png" "$golden/default_es3.png" "${tolerances[@]}" --scene default --es 3
expect 0 "compare --format json" '"verdict": "pass"' \
    compare "$work/default.png" "$golden/default_es3.png" "${tolerances[@]}" --scene default --format json

# Another scene against default's golden fails, with the limits it broke.
expect 1 "render --golden: bricks against default's golden" "mean difference over its limit" \
    "${render[@]}" bricks -o "$work/bricks.png" --golden "$golden/default_es3.png" --tolerances "$golden/tolerances.json"
expect 1 "compare: bricks against default's golden" "FAIL $work/bricks.png vs $golden/default_es3.png" \
    compare "$work/bricks.png" "$golden/default_es3.png" --diff "$work/diff.png"
[ -s "$work/diff.png" ] && echo "ok: --diff wrote the diff image" || { echo "FAIL: no diff image"; failures=$((failures + 1)); }
expect 0 "flags over the file's limits" "allowed 100%), mean" \
    compare "$work/bricks.png" "$golden/default_es3.png" "${tolerances[@]}" --scene default \
    --threshold 255 --max-share 1 --max-mean 255

# Bad input: exit 2, the file named, nothing compared.
"$parallax" "${render[@]}" default --size 64x64 -o "$work/small.png" >/dev/null 2>&1
expect 2 "size mismatch names both files" "size mismatch: $work/small.png is 64x64, $golden/default_es3.png is 128x128" \
    compare "$work/small.png" "$golden/default_es3.png"
expect 2 "render --golden: --size against the golden's" "size mismatch: --size 64x64" \
    "${render[@]}" default --size 64x64 -o "$work/small2.png" --golden "$golden/default_es3.png"
[ ! -e "$work/small2.png" ] && echo "ok: nothing rendered" || { echo "FAIL: rendered anyway"; failures=$((failures + 1)); }
expect 2 "missing actual image" "actual image: $work/none.png" compare "$work/none.png" "$golden/default_es3.png"
expect 2 "missing golden image" "golden image: $work/none.png" compare "$work/default.png" "$work/none.png"
expect 2 "render --golden: missing golden" "golden image: $work/none.png" \
    "${render[@]}" default -o "$work/x.png" --golden "$work/none.png"
echo "not a PNG" >"$work/text.png"
expect 2 "unreadable PNG" "$work/text.png" compare "$work/default.png" "$work/text.png"
printf '{\n  "default": {"pixel_threshold": 8,\n}\n' >"$work/malformed.json"
expect 2 "malformed tolerance file: line and column" "$work/malformed.json:3:1: malformed JSON" \
    compare "$work/default.png" "$golden/default_es3.png" --tolerances "$work/malformed.json" --scene default
# A diff image that cannot be written (its folder would be under a file) is
# refused before the comparison (it used to print PASS, then exit 2), and
# before a render.
echo "not a folder" >"$work/a-file"
out=$("$parallax" compare "$work/default.png" "$golden/default_es3.png" --diff "$work/a-file/diff.png" 2>&1)
status=$?
if [ "$status" != 2 ] || grep -q PASS <<<"$out" || ! grep -qF -- "--diff" <<<"$out"; then
    echo "FAIL: compare --diff under a file: exit $status: $out"; failures=$((failures + 1))
else
    echo "ok: compare --diff under a file is refused before the verdict"
fi
expect 2 "render --golden --diff under a file" "--diff" \
    "${render[@]}" default -o "$work/unused.png" --golden "$golden/default_es3.png" --diff "$work/a-file/d.png"
[ -e "$work/unused.png" ] && { echo "FAIL: the render ran before --diff was refused"; failures=$((failures + 1)); }

printf '{"default": {"pixel_threshold": 8, "max_differing_share": "0.1%%", "max_mean_difference": 0.15}}\n' \
    >"$work/typed.json"
expect 2 "tolerance of the wrong type: the JSON path" "typed.json: default.max_differing_share: expected a number" \
    compare "$work/default.png" "$golden/default_es3.png" --tolerances "$work/typed.json" --scene default
expect 2 "unknown scene in the tolerance file" "no entry for scene 'brick'" \
    compare "$work/default.png" "$golden/default_es3.png" "${tolerances[@]}" --scene brick
expect 2 "negative flag" "--max-mean '-1'" compare "$work/default.png" "$golden/default_es3.png" --max-mean=-1

[ "$failures" = 0 ] || { echo "$failures failure(s)"; exit 1; }
