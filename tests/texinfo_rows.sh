#!/usr/bin/env bash
# texinfo's rows line for each container, on files the field's tools wrote
# (tests/fixtures/third_party/), and --formats on an ES 2.0 context.
#   tests/texinfo_rows.sh PARALLAX SOURCE_DIR
set -euo pipefail
parallax=$1 dir=$(cd "$2/tests/fixtures/third_party" && pwd)
failures=0
expect() {  # expect FILE TEXT: texinfo FILE prints a rows line holding TEXT
    local out
    out=$("$parallax" texinfo "$dir/$1" --es 3) || { echo "FAIL: texinfo $1 exited non-zero"; failures=$((failures + 1)); return; }
    local rows
    rows=$(grep '^rows ' <<<"$out" || true)
    if ! grep -qF "$2" <<<"$rows"; then
        echo "FAIL: texinfo $1: rows line '$rows' lacks '$2'"; failures=$((failures + 1))
    else
        echo "ok: $1: $rows"
    fi
}
expect ptt_etc2_rgb.ktx 'top row first (KTXOrientation "S=r,T=d,R=i")'
expect ptt_etc2_rgb_flipped.ktx 'bottom row first (KTXOrientation "S=r,T=u,R=i")'
expect ptt_etc1.pvr 'top row first (PVR v3 orientation metadata (y down))'
expect ptt_etc1_flipped.pvr 'bottom row first (PVR v3 orientation metadata (y up))'
expect ktxparse_etc2_rgb.ktx2 'top row first (no KTXorientation: "rd", the KTX 2.0 default)'
expect ktxparse_etc2_rgb_ru.ktx2 'bottom row first (KTXorientation "ru")'
expect astcenc_4x4.ktx 'top row first (no KTXorientation'
expect astcenc_6x6.astc 'top row first (.astc declares none'
expect ours_etc2_albedo.ktx 'top row first (KTXorientation "S=r,T=d")'
formats=$("$parallax" texinfo --formats --es 2)
grep -qE '^etc1 +0x8D64 +direct' <<<"$formats" || { echo "FAIL: --formats --es 2 does not list etc1 as direct"; failures=$((failures + 1)); }
grep -qE '^pvrtc1_rgb_4bpp .*CPU decode' <<<"$formats" || { echo "FAIL: --formats --es 2 does not list PVRTC as decoded"; failures=$((failures + 1)); }
# A Basis Universal file is refused with how to convert it.
if out=$("$parallax" texinfo "$dir/basisu_bc7.ktx" 2>&1); then
    echo "FAIL: texinfo accepted a BC7 file"; failures=$((failures + 1))
elif ! grep -q "BC7 (GL_COMPRESSED_RGBA_BPTC_UNORM)" <<<"$out"; then
    echo "FAIL: the BC7 refusal does not name the format: $out"; failures=$((failures + 1))
fi
# The render log says the same, beside the upload, for a scene that reads
# a third-party height map under a PNG albedo.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/scene.json" <<JSON
{"name": "third-party", "camera": {"position": [0, -1.6, 2.3], "target": [0, 0, 0], "fov_y_deg": 40},
 "lights": [{"type": "directional", "direction": [0, -0.6, -0.8]}],
 "materials": [{"name": "relief", "albedo": "$dir/marker.png",
                "height": {"file": "$dir/ptt_relief_etc2.ktx"}, "height_scale": 0.1,
                "technique": "pom"}],
 "objects": [{"name": "plane", "mesh": {"type": "plane", "size": 2}, "material": "relief"}]}
JSON
log=$("$parallax" render "$work/scene.json" -o "$work/out.png" --size 64x64) || { echo "FAIL: render of the third-party scene: $log"; exit 1; }
grep -q 'rows: top row first (KTXOrientation "S=r,T=d,R=i")' <<<"$log" ||
    { echo "FAIL: the render log has no rows line for the KTX height map:"; echo "$log"; failures=$((failures + 1)); }
[ "$failures" -eq 0 ] || exit 1
echo "ok: texinfo rows lines and --formats"
