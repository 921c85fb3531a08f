#!/usr/bin/env bash
# Bad input to `parallax render` gets one clear message on stderr naming what
# was wrong and where, a non-zero exit, and no output image.
# Usage: cli_errors.sh PARALLAX_BINARY
set -uo pipefail
parallax=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

# expect_error DESCRIPTION EXPECTED_TEXT ARGS...
expect_error() {
    local description=$1 expected=$2
    shift 2
    local out="$work/out.png"
    rm -f "$out"
    local stderr
    stderr=$("$parallax" "$@" 2>&1 >/dev/null)
    local status=$?
    if grep -q 'Sanitizer' <<<"$stderr"; then
        echo "FAIL: $description: a sanitizer report:"; echo "$stderr" | head -20; failures=$((failures + 1)); return
    fi
    if [ "$status" = 0 ]; then
        echo "FAIL: $description: exit status 0"; failures=$((failures + 1)); return
    fi
    if ! grep -qF -- "$expected" <<<"$stderr"; then
        echo "FAIL: $description: message lacks '$expected':"; echo "  $stderr"; failures=$((failures + 1)); return
    fi
    if [ -e "$out" ]; then
        echo "FAIL: $description: wrote $out anyway"; failures=$((failures + 1)); return
    fi
    echo "ok: $description -> $(head -1 <<<"$stderr")"
}

printf '{\n  "objects": [\n    {"mesh": {"type": "plane"},}\n  ]\n}\n' >"$work/malformed.json"
printf '{"objects": [{"mesh": {"type": "plane"}, "material": "m"}], "materials": [{"name": "m", "technique": "pomm"}]}\n' >"$work/technique.json"
printf '{"objects": [{"mesh": {"type": "plane"}}], "materials": [{"name": "default", "hieght_scale": 0.1}]}\n' >"$work/field.json"
printf '{"objects": [{"mesh": {"type": "plane"}, "material": "m"}], "materials": [{"name": "m", "albedo": "missing.png"}]}\n' >"$work/texture.json"

expect_error "missing scene file" "$work/nope.json" render "$work/nope.json" -o "$work/out.png"
expect_error "unknown built-in scene" "default, lettering, bricks" render no_such_scene -o "$work/out.png"
expect_error "malformed JSON gives line and column" "malformed.json:3:" render "$work/malformed.json" -o "$work/out.png"
expect_error "unknown technique in a scene" "unknown technique 'pomm'" render "$work/technique.json" -o "$work/out.png"
expect_error "unknown field, with a suggestion" "hieght_scale" render "$work/field.json" -o "$work/out.png"
expect_error "missing texture file" "missing.png" render "$work/texture.json" -o "$work/out.png"
expect_error "unknown --technique" "unknown technique 'bump'" render default --technique bump -o "$work/out.png"
expect_error "bad --size" "--size" render default --size 12by3 -o "$work/out.png"
expect_error "overflowing --size" "integers in 1..16384" render default --size 99999999999x2 -o "$work/out.png"
expect_error "zero bench --size" "integers in 1..16384" bench --size 0x5 --out "$work/bench"
expect_error "unsupported --es" "--es" render default --es 4 -o "$work/out.png"
MESA_GLES_VERSION_OVERRIDE=3.1 expect_error "contradicting MESA_GLES_VERSION_OVERRIDE" \
    "MESA_GLES_VERSION_OVERRIDE=3.1 contradicts" render default --es 2 --size 16x16 -o "$work/out.png"

expect_error "unknown bench scene" "unknown bench scene 'nope'" bench --scenes nope --out "$work/bench"
expect_error "bench samples past the loop bound" "300 is outside 1..256 for pom" bench --techniques pom --samples 300 --out "$work/bench"
expect_error "unknown bench technique" "unknown technique 'bump'" bench --techniques bump --out "$work/bench"
# An output folder that cannot be written is refused before anything is
# measured (not after the sweep).
echo "not a folder" >"$work/a-file"
expect_error "bench into a file" "cannot create the output folder '$work/a-file'" bench --quick --out "$work/a-file"
# The same for every command that writes into a folder or a file's folder,
# each refused before it compiles, measures or converts anything.
expect_error "shaders into a file" "cannot create the output folder '$work/a-file'" shaders --out "$work/a-file"
expect_error "profile --out into a file" "--out: cannot create the output folder '$work/a-file'" profile --out "$work/a-file"
expect_error "profile --doc under a file" "--doc: cannot create the output folder '$work/a-file'" profile --doc "$work/a-file/p.md"
expect_error "stability --out under a file" "--out: cannot create the output folder '$work/a-file'" stability --out "$work/a-file/s.md"
expect_error "stability --out naming a folder" "names a folder, not a file" stability --out "$work/"
expect_error "convert into a file" "--out: cannot create the output folder '$work/a-file'" convert --scene default --out "$work/a-file"

# Texture files: texinfo, convert, render --textures, and scenes naming them.
fuzz_corpus=$(dirname "$0")/fuzz/corpus
printf 'KTX junk' >"$work/junk.ktx"
expect_error "texinfo: not a container" "not a texture container" texinfo "$work/junk.ktx"
expect_error "texinfo: missing file" "$work/none.ktx" texinfo "$work/none.ktx"
# A PVR file in colour space 1 is sRGB colour (issue 49): read, and texinfo says so.
if "$parallax" texinfo "$fuzz_corpus/pvr/bad_srgb.pvr" | grep -q '^colour     sRGB, declared by PVR v3 colour space 1'; then
    echo "ok: texinfo: a PVR file in colour space 1 is read as sRGB"
else
    echo "FAIL: texinfo: PVR colour space 1"; failures=$((failures + 1))
fi
expect_error "texinfo: PVR metadata past the end" "bad_metadata_size.pvr" texinfo "$fuzz_corpus/pvr/bad_metadata_size.pvr"
"$parallax" convert --scene default --format etc2 --out "$work/etc2" >/dev/null 2>&1 || { echo "FAIL: convert --scene default"; failures=$((failures + 1)); }
head -c 100 "$work/etc2/0_height.ktx" >"$work/truncated.ktx"
expect_error "texinfo: truncated KTX" "passes the end of the 100-byte file" texinfo "$work/truncated.ktx"
if "$parallax" texinfo "$work/etc2/0_height.ktx" | grep -q 'eac_r11'; then echo "ok: texinfo names the format"; else
    echo "FAIL: texinfo on a converted file"; failures=$((failures + 1)); fi
printf '{"objects": [{"mesh": {"type": "plane"}, "material": "m"}], "materials": [{"name": "m", "height": "truncated.ktx"}]}\n' >"$work/truncated_scene.json"
expect_error "scene naming a truncated KTX" "truncated.ktx" render "$work/truncated_scene.json" -o "$work/out.png"
printf '{"objects": [{"mesh": {"type": "plane"}, "material": "m"}], "materials": [{"name": "m", "height": {"file": "etc2/0_height.ktx", "convention": "depth"}}]}\n' >"$work/depth_ktx.json"
expect_error "depth convention on a texture file" "must hold height" render "$work/depth_ktx.json" -o "$work/out.png"
expect_error "convert: unknown variant" "unknown texture variant 'etc3'" convert --scene default --format etc3 --out "$work/x"
expect_error "convert: normal map in one channel" "a normal map needs two or more channels" convert --scene default --normal-format eac_r11 --out "$work/x"
expect_error "convert: zstd without ktx2" "--zstd needs --container ktx2" convert --scene default --zstd 3 --out "$work/x"
expect_error "convert: no input" "give a HEIGHT image or --scene" convert --out "$work/x"
examples=$(dirname "$0")/../examples/scenes
if "$parallax" render "$examples/bricks_pvrtc.json" --size 64x64 --frames 1 -o "$work/pvrtc.png" 2>&1 |
    grep -q 'pvrtc1_rgb_4bpp 256x256, 9 level(s), .*CPU decode to RGBA8 (this context does not sample'; then
    echo "ok: a PVRTC scene renders through the CPU decode and says so"
else echo "FAIL: the PVRTC example scene"; failures=$((failures + 1)); fi
if "$parallax" render "$examples/bricks_etc2.json" --size 64x64 --frames 1 -o "$work/etc2.png" 2>&1 |
    grep -q 'eac_r11 256x256, 9 level(s), .*direct (glCompressedTexImage2D)'; then
    echo "ok: an ETC2/EAC scene uploads directly and says so"
else echo "FAIL: the ETC2 example scene"; failures=$((failures + 1)); fi
expect_error "render: unknown --textures" "unknown texture variant 'etc3'" render default --textures etc3 -o "$work/out.png"

# Hostile scenes and outputs (tests/unit_hostile.cpp has one test per class).
lights='{"direction": [0, 0, -1]}'
printf '{"lights": [%s, %s, %s, %s, %s], "objects": [{}]}\n' "$lights" "$lights" "$lights" "$lights" "$lights" >"$work/lights.json"
printf '{"objects": [{}], "materials": [{"name": "default", "height": {"procedural": "lines", "size": 64, "line_width": 2147483647}}]}\n' >"$work/lines.json"
printf '{"objects": [{"transform": {"scale": 1e-20}}]}\n' >"$work/scale.json"
printf '{"objects": [{"mesh": {"displaced": true}}], "materials": [{"name": "default", "height": {"procedural": "bricks", "size": 4096}}]}\n' >"$work/displaced.json"
printf '{"objects": [{"mesh": {"type": "sphere", "displaced": true, "vertices_per_texel": 8}}], "materials": [{"name": "default", "height": {"procedural": "bricks", "size": 512}}]}\n' >"$work/dense.json"
printf '{"objects": [{"mesh": {"vertices_per_texel": 2}}]}\n' >"$work/dense_flat.json"
# A small PNG declaring 30000 x 30000 (it used to abort with bad_alloc, exit 134).
printf '\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x75\x30\x00\x00\x75\x30\x08\x00\x00\x00\x00\x43\x4c\xa7\x66\x00\x00\x00\x0c\x49\x44\x41\x54\x78\x9c\x63\x60\xa0\x0c\x00\x00\x00\x40\x00\x01\xb7\x34\x7c\xef\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82' >"$work/huge.png"
printf '{"objects": [{}], "materials": [{"name": "default", "height": "huge.png"}]}\n' >"$work/huge.json"
expect_error "a PNG declaring 30000x30000 is refused from its header" "huge.png: the header declares 30000x30000" render "$work/huge.json" -o "$work/out.png"
expect_error "a fifth light is refused, not dropped" "lights[4]: at most 4 lights" render "$work/lights.json" -o "$work/out.png"
expect_error "an overflowing line width is refused at once" "materials[0].height: field 'lines'" render "$work/lines.json" -o "$work/out.png"
expect_error "an object scale that overflows floats" "objects[0].transform.scale" render "$work/scale.json" -o "$work/out.png"
expect_error "a displaced plane over the vertex budget" "objects[0].mesh: the scene's meshes pass the limit" render "$work/displaced.json" -o "$work/out.png"
expect_error "a dense displaced sphere over the vertex budget" "about 8 per texel along each side" render "$work/dense.json" -o "$work/out.png"
expect_error "vertices per texel on a mesh that is not displaced" "objects[0].mesh.vertices_per_texel: only a displaced mesh" render "$work/dense_flat.json" -o "$work/out.png"

# A symlink planted where the old writer put its temporary file: the
# link's target is untouched and the image is written.
echo precious >"$work/victim"
ln -s "$work/victim" "$work/planted.png.tmp"
if "$parallax" render default --size 16x16 --frames 1 -o "$work/planted.png" >/dev/null 2>&1 &&
    [ "$(cat "$work/victim")" = precious ] && [ -s "$work/planted.png" ]; then
    echo "ok: a symlink planted at OUT.png.tmp is not followed"
else
    echo "FAIL: the planted symlink's target changed or no image was written"; failures=$((failures + 1))
fi
# A write-protected output is refused and kept.
echo old >"$work/protected.png"
chmod a-w "$work/protected.png"
stderr=$("$parallax" render default --size 16x16 --frames 1 -o "$work/protected.png" 2>&1 >/dev/null)
if [ $? != 0 ] && grep -q "write-protected" <<<"$stderr" && [ "$(cat "$work/protected.png")" = old ]; then
    echo "ok: a write-protected output is refused and kept -> $stderr"
else
    echo "FAIL: a write-protected output: $stderr"; failures=$((failures + 1))
fi

# A tiny sweep writes its four files, with one row per setting.
if "$parallax" bench --scenes sine --angles 30 --techniques normal,pom,displaced_mesh --samples 8 --size 32x32 \
        --frames 1 --out "$work/bench" >/dev/null 2>&1 &&
    [ -s "$work/bench/pareto.svg" ] && [ -s "$work/bench/report.md" ] && [ -s "$work/bench/results.json" ] &&
    [ "$(wc -l <"$work/bench/results.csv")" = 4 ]; then
    echo "ok: a tiny bench writes results.csv (3 rows), results.json, pareto.svg, report.md"
else
    echo "FAIL: a tiny bench did not write its four files"; failures=$((failures + 1))
fi

# The sweep on a true OpenGL ES 2.0 context: its own table (the file says
# ES 2.0), every default technique that runs there; those that need ES 3.0
# refused when named, and the modes that need ES 3.0 refused with --es 2.
if "$parallax" bench --es 2 --scenes sine --angles 60 --samples 8 --size 32x32 --frames 1 \
        --out "$work/bench_es2" >/dev/null 2>&1 &&
    python3 - "$work/bench_es2/results.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert "OpenGL ES 2.0" in d["gl_version"], d["gl_version"]
techniques = {r["technique"] for r in d["rows"]}
assert {"normal", "parallax", "offset_limited", "steep", "pom", "relief", "displaced_mesh"} <= techniques, techniques
assert "maxmip" in techniques, techniques  # the exact walk in GLSL ES 1.00
PY
then
    echo "ok: bench --es 2 sweeps every technique that runs on a true ES 2.0 context"
else
    echo "FAIL: bench --es 2 did not write an ES 2.0 table"; failures=$((failures + 1))
fi
expect_error "bench --es 2 --showcase" "--es 2 is for the sweep only" bench --es 2 --showcase showcase --out "$work/bench"
expect_error "bench --es 4" "--es: 4 not in {2,3}" bench --es 4 --out "$work/bench"

# --- The effect planner: bad requests name the object and the field ----------
effects_scene() {  # effects_scene FILE EFFECTS_JSON [CAMERA_JSON]
    printf '{"camera": %s, "objects": [{"name": "wall", "mesh": {"type": "plane", "segments": 8}, "material": "m"}],
  "materials": [{"name": "m", "height": {"procedural": "lines", "size": 256, "count": 8}, "height_scale": 0.05,
                 "effects": %s}]}\n' "${3:-{\"position\": [0, -3, 0.3]\}}" "$2" >"$1"
}
effects_scene "$work/impossible.json" '{"parallax": {"max_error_texels": 0.01}}'
effects_scene "$work/unknown_effect.json" '{"parallax": {}, "bloom": "on"}'
effects_scene "$work/contradiction.json" '{"parallax": "off", "shadow": "soft"}'
effects_scene "$work/both.json" '{"parallax": {}}'
sed -i 's/"effects"/"technique": "pom", "effects"/' "$work/both.json"
effects_scene "$work/fine.json" '{"parallax": {"max_error_texels": 2}, "shadow": "hard"}' '{"position": [0, -2, 2]}'
# On ES 2.0, where maxmip does not run, no search reaches 0.01 texels at 84 degrees.
# Impossible on ES 2.0 without fragment highp: the uv is fp16 there, 1/16
# texel at best on a 256-texel map, whatever the technique.
expect_error "an impossible target" "impossible.json: object 'wall' (material 'm'): materials[0].effects.parallax.max_error_texels: 0.01 texels is below what any technique reaches" \
    plan "$work/impossible.json" --es 2 --no-fragment-highp --calibration-cache off
expect_error "an impossible target, why" "without fragment highp the uv is fp16, which places no hit closer than 0.0625 texels on this 256x256 height map" \
    plan "$work/impossible.json" --es 2 --no-fragment-highp --calibration-cache off
expect_error "an impossible target, render" "materials[0].effects.parallax.max_error_texels" \
    render "$work/impossible.json" --es 2 --no-fragment-highp --size 32x32 --frames 1 --calibration-cache off --program-cache off -o "$work/out.png"
expect_error "--no-fragment-highp on ES 3.0" "--no-fragment-highp is for --es 2: OpenGL ES 3.0 guarantees fragment highp" \
    plan "$work/impossible.json" --es 3 --no-fragment-highp
expect_error "an unknown effect" "unknown field 'bloom' in materials[0].effects" plan "$work/unknown_effect.json"
expect_error "a contradictory request" "materials[0].effects.shadow: \"soft\" contradicts \"parallax\": \"off\"" plan "$work/contradiction.json"
expect_error "effects and a technique" "materials[0].effects: a material declares effects or names a technique, not both" plan "$work/both.json"
expect_error "a bad camera path" "--camera-path must be orbit or dolly" render default --camera-path zoom -o "$work/out.png"
expect_error "a bad plan format" "--format must be table or json" plan default --format xml
# Prices: a GPU without a carried table, both sources at once, a missing or broken table file.
expect_error "a GPU without a priced table" "parallax bench --planner-table FILE --gpu NAME" plan default --cost-target adreno-630
expect_error "two price sources" "--cost-target and --cost-table both name the prices" \
    plan default --cost-target mali-g57 --cost-table "$work/t.json"
expect_error "a missing cost table" "$work/none.json" plan default --cost-table "$work/none.json"
printf '{"date": "d", "renderer": "r", "version": "v", "command": "c", "prices": 7, "reliefs": []}\n' >"$work/prices.json"
expect_error "a cost table with a bad prices field" "$work/prices.json: prices: expected a string" \
    plan default --cost-table "$work/prices.json"
# A fine request plans, in both formats, and --explain prints the plan.
if out=$("$parallax" plan "$work/fine.json" --calibration-cache off 2>&1) && grep -q "variant" <<<"$out" &&
    grep -q "predict" <<<"$out" && "$parallax" plan showcase --format json --calibration-cache off >"$work/plan.json" &&
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert len(d['objects']) == 6" "$work/plan.json" &&
    explained=$("$parallax" render showcase --size 48x48 --frames 1 --explain --calibration-cache off \
        --program-cache off -o "$work/showcase.png") &&
    grep -q "note     normal mapping: height_scale is 0" <<<"$explained"; then
    echo "ok: plan (table and json) and render --explain print the plan"
else
    echo "FAIL: plan or --explain: $out"; failures=$((failures + 1))
fi
# A camera path plans every frame and reports the plan changes.
if out=$("$parallax" render showcase --size 48x48 --frames 4 --camera-path dolly --calibration-cache off \
        --program-cache off -o "$work/dolly.png" 2>&1) && grep -q "plan change(s) over 4 frames" <<<"$out" &&
    grep -q "us per object" <<<"$out"; then
    echo "ok: --camera-path dolly reports plan changes and planning time"
else
    echo "FAIL: --camera-path: $out"; failures=$((failures + 1))
fi

# parallax profile: bad options and files.
printf '{"arithmetic": {"fp32_ops_per_cycle": 1, "fp16_ops_per_cycle": 2, "transcendental_cycles": 4, "branch_cycles": 1}, "texture": {"samples_per_cycle": 0, "latency_cycles": 100, "latency_hidden_share": 0.5}, "varying": {"components_per_cycle": 2}}\n' >"$work/model.json"
expect_error "profile: unknown format" "unknown format 'xml'" profile --no-time --no-nir --format xml
expect_error "profile: no variant matches" "matches no OpenGL ES 3.0 variant" profile --no-time --no-nir --variants nosuch
expect_error "profile: ambiguous --compare" "matches" profile --no-time --no-nir --compare pom steep
expect_error "profile: --compare needs two" "compare" profile --no-time --no-nir --compare pom
expect_error "profile: unknown revision" "is not a commit" profile --no-time --no-nir --against no-such-revision-here
expect_error "profile: an option as revision" "is not a revision" profile --no-time --no-nir --against=--output=$work/x
[ -e "$work/x" ] && { echo "FAIL: --against wrote $work/x"; failures=$((failures + 1)); }
expect_error "profile: missing model file" "$work/none.json" profile --no-time --no-nir --model "$work/none.json"
expect_error "profile: bad model field" "$work/model.json: \$.texture.samples_per_cycle" profile --no-time --no-nir --model "$work/model.json"
expect_error "profile: bad size" "--size" profile --no-nir --size 0x0
expect_error "profile: bad angle" "--angle" profile --no-nir --angle 95

# The calibration cache: only the file named for a material's relief
# (<hash>-depth<depth>.json, as plan --calibrate writes it) is read; any other
# file there is never opened (a large one used to make every render parse it,
# in quadratic time). A matching file that is broken, holds no row to plan
# with, or is a FIFO is not used, and the plan says why; the render still
# succeeds.
cal="$work/calibration"
mkdir -p "$cal"
head -c 8000000 /dev/zero | tr '\0' '[' >"$cal/huge-unrelated.json"
floor_file=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(next(o['relief']['calibration_file'] for o in d['objects'] if o['material'] == 'floor'))" "$work/plan.json")
calibration_note() {  # calibration_note DESCRIPTION EXPECTED_NOTE
    local out status
    out=$(timeout 120 "$parallax" plan showcase --format json --calibration-cache "$cal" 2>&1)
    status=$?
    if [ "$status" != 0 ]; then
        echo "FAIL: $1: exit status $status: $(head -3 <<<"$out")"; failures=$((failures + 1))
    elif grep -q "huge-unrelated" <<<"$out"; then
        echo "FAIL: $1: a calibration not named for any material was read"; failures=$((failures + 1))
    elif ! grep -qF -- "$2" <<<"$out"; then
        echo "FAIL: $1: no note '$2' in the plan"; failures=$((failures + 1))
    else
        echo "ok: $1"
    fi
}
if [ -z "$floor_file" ]; then
    echo "FAIL: plan --format json names no calibration file for the showcase floor"; failures=$((failures + 1))
else
    calibration_note "an unrelated calibration file is never read" '"material": "floor"'
    echo '{"date": "x", "renderer": "x", "version": "x", "command": "x", "reliefs": [' >"$cal/$floor_file"
    calibration_note "a broken calibration is not used, with a note" "calibration not used: $cal/$floor_file: not a JSON object"
    printf '{"date": "d", "renderer": "r", "version": "v", "command": "c", "reliefs": [{"name": "n", "depth_texels": 1,
  "steepness": 1, "thinnest_texels": 1, "range": 1, "hash": "1"}], "rows": []}\n' >"$cal/$floor_file"
    calibration_note "a calibration of another relief is not used, with a note" "it holds no relief with this field's hash and depth"
    rm -f "$cal/$floor_file"
    mkfifo "$cal/$floor_file"
    calibration_note "a FIFO at a calibration's name does not hang" "not a regular file"
fi

# Outputs replace what is at their names, never write through it: a symlink
# planted at an output name (to a file outside the folder) is replaced by the
# output, and the file it pointed at is untouched.
mkdir -p "$work/shaders" "$work/outside"
echo "precious" >"$work/outside/victim"
ln -s "$work/outside/victim" "$work/shaders/flat_es2.frag"
if "$parallax" shaders --es 2 --out "$work/shaders" >/dev/null 2>"$work/err"; then
    if [ "$(cat "$work/outside/victim")" != "precious" ]; then
        echo "FAIL: shaders --out wrote through a planted symlink"; failures=$((failures + 1))
    elif [ -L "$work/shaders/flat_es2.frag" ] || ! grep -q "main" "$work/shaders/flat_es2.frag"; then
        echo "FAIL: shaders --out left the planted symlink in place of its output"; failures=$((failures + 1))
    else
        echo "ok: shaders --out replaces a planted symlink, not its target"
    fi
else
    echo "FAIL: shaders --out failed: $(cat "$work/err")"; failures=$((failures + 1))
fi

[ "$failures" = 0 ] && echo "all CLI error cases behave" || { echo "$failures CLI error case(s) failed"; exit 1; }
