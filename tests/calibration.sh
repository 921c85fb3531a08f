#!/usr/bin/env bash
# `parallax plan --calibrate` end to end: without --frames it measures each
# candidate's error on the material's own relief and prices it from the
# built-in table, so two calibrations of one scene write the same table
# (date and command aside) and the plan chooses the same variant whatever
# the machine's load; the plan says where its prediction comes from; a
# calibration file whose "costs" is neither "measured" nor "table" is not
# used, with a note.
# Usage: calibration.sh PARALLAX_BINARY
set -uo pipefail
parallax=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Seen from nearly overhead: two table angles bracket its view (0 and 30).
cat >"$work/scene.json" <<'JSON'
{
  "name": "calibration check",
  "camera": {"position": [0, -0.3, 3.0], "target": [0, 0, 0], "fov_y_deg": 35},
  "lights": [{"type": "directional", "direction": [-0.3, 0.4, -0.8]}],
  "materials": [
    {"name": "cones", "albedo": {"color": [0.7, 0.6, 0.4]},
     "height": {"procedural": "cones", "size": 128, "count": 5}, "height_scale": 0.06,
     "effects": {"parallax": {"max_error_texels": 0.5}}}
  ],
  "objects": [{"name": "ground", "mesh": {"type": "plane", "size": 1.6}, "material": "cones"}]
}
JSON

calibrate() {  # calibrate FOLDER -> the plan's text in FOLDER.plan
    timeout 300 "$parallax" plan "$work/scene.json" --calibrate --calibration-cache "$1" >"$1.plan" 2>"$1.err" ||
        { fail "plan --calibrate into $1: exit $?: $(tail -3 "$1.err")"; return 1; }
}
calibrate "$work/a" && calibrate "$work/b" || { echo "$failures failure(s)"; exit 1; }
files=("$work"/a/*.json)
if [ "${#files[@]}" != 1 ] || [ ! -f "${files[0]}" ]; then
    fail "one calibration file expected in $work/a, found: $(ls "$work/a")"
else
    name=$(basename "${files[0]}")
    strip() { grep -v -e '"date":' -e '"command":' "$1"; }
    if ! cmp -s <(strip "$work/a/$name") <(strip "$work/b/$name"); then
        fail "two calibrations of one scene differ: $(diff <(strip "$work/a/$name") <(strip "$work/b/$name") | head -5)"
    else
        echo "ok: two calibrations write the same table"
    fi
    grep -q '"costs": "table"' "$work/a/$name" || fail "the calibration does not say its costs are the table's"
    variant_a=$(grep -m1 'variant' "$work/a.plan")
    variant_b=$(grep -m1 'variant' "$work/b.plan")
    [ -n "$variant_a" ] && [ "$variant_a" = "$variant_b" ] || fail "the two plans differ: '$variant_a' / '$variant_b'"
    grep -q "from     calibrated on this relief .*errors measured, costs from table '" "$work/a.plan" &&
        echo "ok: the plan names the calibration and the table its costs come from" ||
        fail "the plan does not say its costs come from the table: $(grep from "$work/a.plan")"
    # A file that claims another kind of costs is not a calibration to plan with.
    sed -i 's/"costs": "table"/"costs": "guessed"/' "$work/a/$name"
    out=$("$parallax" plan "$work/scene.json" --calibration-cache "$work/a" 2>&1)
    if grep -qF "calibration not used: $work/a/$name" <<<"$out" && grep -q 'costs: expected "measured" or "table"' <<<"$out"; then
        echo "ok: unknown costs kind refused with a note"
    else
        fail "a calibration with \"costs\": \"guessed\" was not refused by name: $(grep -m2 -e note -e from <<<"$out")"
    fi
fi
[ "$failures" = 0 ] && echo "calibration behaves" || { echo "$failures calibration case(s) failed"; exit 1; }
