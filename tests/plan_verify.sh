#!/usr/bin/env bash
# parallax plan --verify (and render --verify): the plan drawn and measured against the exact
# reference, on ES 3.0 and ES 2.0, for planned and technique-named
# materials; its exit status says whether every target was met.
#   tests/plan_verify.sh PARALLAX
set -euo pipefail
parallax=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
for es in 3 2; do
    if ! "$parallax" plan showcase --size 128x128 --es "$es" --verify >"$work/out" 2>"$work/err"; then
        echo "FAIL: plan showcase --verify --es $es exited non-zero:"; cat "$work/out" "$work/err"; failures=$((failures + 1))
        continue
    fi
    measured=$(grep -c '): hit .* measured' "$work/out" || true)
    if [ "$measured" -ne 6 ]; then
        echo "FAIL: --es $es: $measured objects measured, not the showcase's 6"; cat "$work/out"; failures=$((failures + 1))
    fi
    grep -q '^verify     every target met' "$work/out" || { echo "FAIL: --es $es: no 'every target met'"; failures=$((failures + 1)); }
    grep -q 'technique named: no target\|no parallax asked' "$work/out" ||
        { echo "FAIL: --es $es: an object without a target is not said to be one"; failures=$((failures + 1)); }
    echo "ok: plan showcase --verify --es $es"
done
# Priced in a real GPU compiler's cycles (the Mali-G57 table the program
# carries): the plan says so and still meets every target.
if "$parallax" plan showcase --size 128x128 --cost-target mali-g57 --verify >"$work/out" 2>"$work/err" &&
    grep -q '^prices     Mali-G57 (Valhall) cycles per pixel' "$work/out" && grep -q '^verify     every target met' "$work/out"; then
    echo "ok: plan showcase --cost-target mali-g57 --verify"
else
    echo "FAIL: plan showcase --cost-target mali-g57 --verify:"; cat "$work/out" "$work/err"; failures=$((failures + 1))
fi
# render --verify: the same measurement after the render.
if ! "$parallax" render showcase --size 128x128 --frames 1 -o "$work/s.png" --verify >"$work/out" 2>"$work/err" ||
    ! grep -q '^verify     every target met' "$work/out"; then
    echo "FAIL: render showcase --verify:"; cat "$work/out" "$work/err"; failures=$((failures + 1))
else
    echo "ok: render showcase --verify"
fi
# A small part of the planner suite (examples/scenes/planner_suite, all of
# it in tests/planner_suite.sh): a fine sine the table's nearest relief
# mispredicted 13 times, a 60-unit single quad, text under a low hard light.
suite=$(cd "$(dirname "$0")/../examples/scenes/planner_suite" && pwd)
for scene in sine_fine_05 bricks_quad_big text_shadow_low; do
    for es in 3 2; do
        if "$parallax" plan "$suite/$scene.json" --size 128x128 --es "$es" --verify >"$work/out" 2>"$work/err" &&
            grep -q '^verify     every target met' "$work/out"; then
            echo "ok: planner suite $scene --es $es: $(grep '^  ground (' "$work/out" | cut -c1-110)"
        else
            echo "FAIL: planner suite $scene --es $es:"; cat "$work/out" "$work/err"; failures=$((failures + 1))
        fi
    done
done
# A relief unlike the cost table's (one-texel lines, seen low): whatever the
# planner picks, a miss must be printed as MISSED and exit 1, a pass exit 0.
cat >"$work/lines.json" <<'JSON'
{"name": "fine-lines",
 "camera": {"position": [0, -2.2, 1.2], "target": [0, 0.2, 0], "fov_y_deg": 45},
 "lights": [{"type": "directional", "direction": [-0.5, 0.3, -0.8]}],
 "materials": [{"name": "lines", "albedo": {"color": [0.7, 0.6, 0.5]},
   "height": {"procedural": "lines", "size": 256, "count": 40}, "height_scale": 0.08,
   "effects": {"parallax": {"max_error_texels": 0.5}}}],
 "objects": [{"name": "ground", "mesh": {"type": "plane", "size": 2.4, "segments": 16}, "material": "lines"}]}
JSON
set +e
"$parallax" plan "$work/lines.json" --size 128x128 --verify >"$work/out" 2>"$work/err"
rc=$?
set -e
line=$(grep '^  ground' "$work/out" || true)
echo "lines scene: $line (exit $rc)"
if grep -q 'MISSED' <<<"$line"; then
    [ "$rc" -eq 1 ] || { echo "FAIL: a missed target exited $rc, not 1"; failures=$((failures + 1)); }
    grep -q 'missed their target' "$work/err" || { echo "FAIL: no message for the miss"; failures=$((failures + 1)); }
elif grep -q ': met' <<<"$line"; then
    [ "$rc" -eq 0 ] || { echo "FAIL: a met target exited $rc"; failures=$((failures + 1)); }
else
    echo "FAIL: no verdict for the ground:"; cat "$work/out" "$work/err"; failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] || exit 1
echo "ok: plan --verify"
