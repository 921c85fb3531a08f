#!/usr/bin/env bash
# `parallax profile` end to end: the SPIR-V and NIR counts in its JSON, a
# comparison, the optimisation ladder with times and errors, the shaders of
# a commit against the working tree, and a vendor compiler found on PATH
# (a fake malioc printing a report written for the tests).
# Usage: profile_cli.sh PARALLAX_BINARY SOURCE_DIR
set -uo pipefail
parallax=$(readlink -f "$1")
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Each technique's default variant: SPIR-V and NIR counts, no vendor tool.
if "$parallax" profile --no-time --format json >"$work/profile.json" 2>"$work/err" &&
    python3 - "$work/profile.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
names = [v["variant"] for v in d["variants"]]
assert any(n.startswith("pom es3") for n in names), names
for v in d["variants"]:
    assert v["nir"]["fragment"]["alu"] > 0, v["variant"]
    assert v["fragment"]["instructions"]["texture"] >= 1, v["variant"]
    assert v["estimate"]["fragment_longest"]["total"] > 0, v["variant"]
pom = next(v for v in d["variants"] if v["variant"].startswith("pom es3"))
assert any(l["trip_count"] == 32 and l["where"].startswith("shaders_es/chunks/march.glsl") for l in pom["fragment"]["loops"])
assert "no vendor compiler" in d["context"]["vendor"] or "malioc" in d["context"]["vendor"]
PY
then echo "ok: profile --format json: SPIR-V, NIR and the model for every default variant"
else fail "profile json: $(cat "$work/err")"; fi

# ES 2.0 variants too (GLSL ES 1.00 through glslang and a true ES 2.0 context).
if out=$("$parallax" profile --es 2 --no-time --variants 'offset_limited es2 packed' 2>&1) &&
    grep -q "offset_limited es2 packed" <<<"$out"; then echo "ok: profile --es 2"
else fail "profile --es 2: $out"; fi

# --out writes the report as Markdown and JSON too.
if "$parallax" profile --no-time --no-nir --variants 'normal es3' --out "$work/out" >/dev/null 2>"$work/err" &&
    grep -q "| normal es3 |" "$work/out/profile.md" && python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$work/out/profile.json"; then
    echo "ok: profile --out writes profile.md and profile.json"
else fail "profile --out: $(cat "$work/err")"; fi

# Two variants compared.
if out=$("$parallax" profile --no-time --compare 'steep es3 samples<=32 exact-view packed' \
        'steep es3 samples<=64 exact-view packed' 2>&1) && grep -q "B - A" <<<"$out" &&
    grep -q "texture samples (longest)" <<<"$out"; then echo "ok: profile --compare"
else fail "profile --compare: $out"; fi

# The ladder, drawn: seven rows with times and errors.
if "$parallax" profile --ladder --size 64x64 --frames 1 --no-nir --format json >"$work/ladder.json" 2>"$work/err" &&
    python3 - "$work/ladder.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
steps = d["steps"]
assert [s["step"] for s in steps] == [1, 2, 3, 4, 5, 6, 0], [s["step"] for s in steps]
for s in steps:
    assert s["measured"]["ns_per_pixel"] > 0, s["variant"]
    assert s["measured"]["uv_error_mean"] >= 0, s["variant"]
# Every step draws offset limiting: its hit error and colour stay near the
# shipped shader's (which normalises the view per fragment).
shipped = steps[-1]["measured"]
for s in steps[:-1]:
    m = s["measured"]
    assert abs(m["uv_error_mean"] - shipped["uv_error_mean"]) <= 0.15 * shipped["uv_error_mean"], (s["step"], m, shipped)
    assert abs(m["color_psnr_db"] - shipped["color_psnr_db"]) <= 1.5, (s["step"], m, shipped)
# Back-to-back reads: one wait fewer than step 4.
assert steps[4]["fragment"]["in_order_waits"] == steps[3]["fragment"]["in_order_waits"] - 1
PY
then echo "ok: profile --ladder draws every step"
else fail "profile --ladder: $(cat "$work/err")"; fi

# The shaders of HEAD against this program's (a clean tree: no change).
if [ -d "$source_dir/.git" ] || git -C "$source_dir" rev-parse HEAD >/dev/null 2>&1; then
    if out=$(cd "$source_dir" && "$parallax" profile --no-time --no-nir --variants 'pom es3 samples<=32 exact-view packed' \
            --against HEAD 2>&1) && grep -q "Changed lines, fragment stage" <<<"$out" && grep -q "@ HEAD" <<<"$out"; then
        echo "ok: profile --against HEAD"
    else fail "profile --against: $out"; fi
else
    echo "skip: profile --against (not a git checkout)"
fi

# --against with a hostile git configuration: prefixes dropped or renamed,
# an external diff program, a textconv driver, colour and quoting forced,
# an fsmonitor hook, context lines from the environment. A repository of
# its own: the commit holds pom.frag with one line more than the program's
# shaders (the working tree), so the changed-line costs are known to be
# non-zero. The report must be the same as with no configuration at all,
# and none of the configured programs may run.
repo="$work/against"
mkdir -p "$repo"
cp -r "$source_dir/shaders_es" "$repo/"
sed -i '0,/^    return hit;$/s//    hit.height = hit.height * 0.5 + 0.25;\n    return hit;/' "$repo/shaders_es/techniques/pom.frag"
if cmp -s "$repo/shaders_es/techniques/pom.frag" "$source_dir/shaders_es/techniques/pom.frag"; then
    fail "profile --against (hostile git): pom.frag has no 'return hit;' line to change any more: update this test"
else
    (cd "$repo" && git init -q . && git add -A && git -c user.name=t -c user.email=t@example.com commit -qm old &&
        cp "$source_dir/shaders_es/techniques/pom.frag" shaders_es/techniques/pom.frag)
    against() {  # ENV... : the report of --against HEAD in the repository
        (cd "$repo" && env "$@" "$parallax" profile --no-time --no-nir --variants 'pom es3' --against HEAD 2>&1)
    }
    plain=$(against GIT_CONFIG_GLOBAL=/dev/null GIT_CONFIG_NOSYSTEM=1)
    cat >"$work/hostile.sh" <<SH
#!/bin/sh
touch "$work/ran"
echo '--- x/shaders_es/techniques/pom.frag'
echo '@@ -1,1000 +1,1000 @@'
SH
    chmod +x "$work/hostile.sh"
    cat >"$work/gitconfig" <<CFG
[diff]
    noprefix = true
    mnemonicPrefix = true
    external = $work/hostile.sh
    relative = true
    interHunkContext = 20
    context = 9
    renames = copies
[diff "hostile"]
    textconv = $work/hostile.sh
[color]
    ui = always
    diff = always
[core]
    quotePath = true
    fsmonitor = $work/hostile.sh
    pager = $work/hostile.sh
[pager]
    diff = $work/hostile.sh
CFG
    echo '*.frag diff=hostile' >"$repo/.gitattributes"
    echo '*.glsl diff=hostile' >>"$repo/.gitattributes"
    hostile=$(against GIT_CONFIG_GLOBAL="$work/gitconfig" GIT_CONFIG_NOSYSTEM=1 GIT_EXTERNAL_DIFF="$work/hostile.sh" \
        GIT_DIFF_OPTS=--unified=7 GIT_PAGER="$work/hostile.sh" PAGER="$work/hostile.sh")
    if ! grep -Eq "Changed lines, fragment stage: [1-9][0-9]* ops" <<<"$plain"; then
        fail "profile --against (no git configuration): the removed line's cost is not reported: $plain"
    elif [ -e "$work/ran" ]; then
        fail "profile --against ran a program from the git configuration"
    elif [ "$plain" != "$hostile" ]; then
        fail "profile --against: a hostile git configuration changed the report: $(diff <(echo "$plain") <(echo "$hostile") | head -20)"
    else
        echo "ok: profile --against reads the same changed lines under a hostile git configuration, running nothing of it"
    fi
fi

# The model against a real compiler: the carried Mali-G78 set's fit meets
# the issue's goal on the held-out half, and says which GPU.
if "$parallax" profile --calibrate --format json >"$work/calibrate.json" 2>"$work/err" &&
    python3 - "$work/calibrate.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert "Mali-G78" in d["gpu"], d["gpu"]
assert d["held_out"]["spearman"] >= 0.9 and d["held_out"]["median_abs_error"] <= 0.3, d["held_out"]
assert d["goal_met"] is True
assert len(d["shaders"]) == d["held_out"]["shaders"] + d["fitted"]["shaders"]
PY
then echo "ok: profile --calibrate: the fit meets the goal on the held-out half"
else fail "profile --calibrate: $(cat "$work/err")"; fi

# A set made at asset-build time from sources and reports, calibrated, and
# the fitted model used by a profile. The reports are written here (a
# compiler that charges 0.25 per texture sample and 0.125 per varying
# component), so the fit must find those rates.
mkdir -p "$work/cal/shaders" "$work/cal/reports/frag"
python3 - "$work/cal" <<'PY'
import sys
root = sys.argv[1]
head = "#version 100\nprecision mediump float;\nuniform highp sampler2D t;\nvarying highp vec2 uv;\n"
for k in range(1, 11):
    reads = " + ".join("texture2D(t, uv * %d.0)" % (j + 1) for j in range(k))
    open("%s/shaders/s%02d.frag" % (root, k), "w").write(head + "void main() { gl_FragColor = %s; }\n" % reads)
    row = "%8.2f%8.2f%8.2f%8.2f" % (0.05 * k, 0.0, 0.25, 0.25 * k)
    open("%s/reports/frag/s%02d.frag.txt" % (root, k), "w").write(
        "Mali Offline Compiler v7.7.0 (Build d01859)\n\nConfiguration\n=============\n\n"
        "Hardware: Mali-G78 r1p1\nArchitecture: Valhall\nDriver: r39p0-00rel0\nShader type: OpenGL ES Fragment\n\n"
        "Main shader\n===========\n\nWork registers: 8 (25%% used at 100%% occupancy)\nUniform registers: 2 (3%% used)\n"
        "Stack spilling: false\n16-bit arithmetic: 0%%\n\n"
        "                                A      LS       V       T    Bound\n"
        "Total instruction cycles:  %s       T\nShortest path cycles:      %s       T\n"
        "Longest path cycles:       %s       T\n\nA = Arithmetic, LS = Load/Store, V = Varying, T = Texture\n"
        % (row, row, row))
PY
echo 'void main() {}' >"$work/cal/shaders/v.vert"
if "$parallax" profile --make-calibration-set "$work/cal/set.json" --shaders "$work/cal/shaders" \
        --reports "$work/cal/reports" --set-source "written for the tests" 2>"$work/err" &&
    grep -q "10 fragment shaders (0 without a report and 1 vertex shaders left out)" "$work/err" &&
    "$parallax" profile --calibrate --calibration-set "$work/cal/set.json" --model-out "$work/cal/model.json"         --format json >"$work/cal/fit.json" 2>>"$work/err" &&
    python3 - "$work/cal/fit.json" <<'PY' &&
import json, sys
d = json.load(open(sys.argv[1]))
w = d["weights"]
assert abs(w["sample"] - 0.25) < 1e-6, w
assert d["source"] == "written for the tests"
assert len(d["shaders"]) == 10
PY
    out=$("$parallax" profile --no-time --no-nir --variants 'normal es3' --model "$work/cal/model.json" 2>&1) &&
    grep -q "calibrated against Mali-G78 r1p1 (Valhall), malioc 7.7.0" <<<"$out" &&
    grep -q "texture samples per cycle: 4$" <<<"$out"; then
    echo "ok: a calibration set made from sources and reports, fitted, and its model used"
else fail "make, calibrate and use a set: $(cat "$work/err") ${out:-}"; fi

# Another GPU class's set: the reports use the model fitted to it, and say
# which GPU; a set that cannot calibrate the model (Midgard: no varying pipe)
# is refused with the reason.
if out=$("$parallax" profile --no-time --no-nir --variants 'normal es3' \
        --calibration-set "$source_dir/profiling/costs/calibration/mali_g710_impeller.json" 2>&1) &&
    grep -q "calibrated against Mali-G710 r0p0 (Valhall), malioc 7.7.0" <<<"$out"; then
    echo "ok: profile --calibration-set: the reports use that GPU's fit and name it"
else fail "profile --calibration-set: $out"; fi

# Refusals: each names what was wrong, nothing is written.
refuse() {  # EXPECTED ARGS...: the command fails and says EXPECTED
    local expected=$1; shift
    if out=$("$parallax" profile "$@" 2>&1); then fail "profile $*: accepted"
    elif ! grep -qF -- "$expected" <<<"$out"; then fail "profile $*: '$out' does not say '$expected'"
    else echo "ok: profile $* is refused: $expected"; fi
}
echo '{"gpu": "g"}' >"$work/cal/bad.json"
refuse "$work/cal/bad.json: \$.compiler" --calibrate --calibration-set "$work/cal/bad.json"
refuse "$work/cal/missing.json" --calibrate --calibration-set "$work/cal/missing.json"
refuse "needs --shaders DIR" --make-calibration-set "$work/cal/x.json"
refuse "go with --make-calibration-set" --shaders "$work/cal/shaders"
refuse "goes with --calibrate" --model-out "$work/cal/m.json"
refuse "one at a time" --calibrate --make-calibration-set "$work/cal/x.json"
refuse "mali_t880_impeller.json: the fit gave a pipe no cost" --no-time --no-nir --variants 'normal es3' \
    --calibration-set "$source_dir/profiling/costs/calibration/mali_t880_impeller.json"
sed -i 's/OpenGL ES Fragment/OpenGL ES Vertex/' "$work/cal/reports/frag/s03.frag.txt"
refuse "s03.frag (report): a OpenGL ES Vertex report for a fragment shader" --make-calibration-set "$work/cal/x.json"     --shaders "$work/cal/shaders" --reports "$work/cal/reports"
[ -e "$work/cal/x.json" ] && fail "a refused --make-calibration-set wrote its file"

# A vendor compiler on PATH: its cycles in the same table.
mkdir -p "$work/bin"
cat >"$work/bin/malioc" <<SH
#!/bin/sh
cat "$source_dir/tests/data/vendor/malioc_valhall.json"
SH
chmod +x "$work/bin/malioc"
if out=$(PATH="$work/bin:$PATH" "$parallax" profile --no-time --no-nir --variants 'normal es3' 2>&1) &&
    grep -q "malioc:" <<<"$out" && grep -q "Vendor compilers: malioc" <<<"$out"; then
    echo "ok: a malioc on PATH is run and its cycles shown"
else fail "vendor compiler: $out"; fi

[ "$failures" = 0 ] && echo "all profile cases behave" || { echo "$failures profile case(s) failed"; exit 1; }
