#!/usr/bin/env bash
# Rebuilds the texture files of tests/data/gallery/ (a few real materials for
# the renderer to draw) from the Debian 12 (bookworm, main) game-data packages
# that ship them: downloads the exact package versions below, extracts only the
# files used, downsizes what is over 512x512 to 256x256, copies the rest
# byte for byte, and copies each package's copyright file beside its files.
# tests/data/gallery/README.md says what every file holds; the scene files
# (<material>/<material>.json) and README.md are written by hand and are not
# touched here.
#
# Usage: tools/assets/gallery_assets.sh
#   GALLERY_DEB_CACHE=DIR  reuse (and keep) the downloaded .deb files in DIR
#   GALLERY_PYTHON=PATH    a python3 with PIL and numpy (default /usr/bin/python3)
# Needs: apt-get (Debian 12 lists: run `apt-get update` once), dpkg-deb, tar,
# unzip, python3-pil, python3-numpy. Downloads about 2.7 GB (0ad-data alone is
# 1.4 GB) and unpacks about 3.3 GB (0ad's public.zip, deleted once unzipped)
# into a temporary folder removed at the end; about 2 minutes on 2 cores, most
# of it decompressing 0ad-data.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT="$ROOT/tests/data/gallery"
PYTHON=${GALLERY_PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/gallery_assets.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
if [[ -n ${GALLERY_DEB_CACHE:-} ]]; then
    DEBS=$GALLERY_DEB_CACHE
    mkdir -p "$DEBS"
else
    DEBS=$WORK/debs
    mkdir -p "$DEBS"
    chmod a+rwx "$WORK" "$DEBS"  # apt downloads as its _apt user where it can
fi

for tool in apt-get dpkg-deb tar unzip sha256sum; do
    command -v "$tool" >/dev/null || { echo "error: $tool is missing" >&2; exit 1; }
done
"$PYTHON" -c 'import PIL, numpy' 2>/dev/null ||
    { echo "error: $PYTHON lacks PIL or numpy (apt-get install python3-pil python3-numpy)" >&2; exit 1; }

# The exact versions the committed files came from (Debian 12 "bookworm", main).
PACKAGES=(
    "redeclipse-data=1.6.0-1"
    "0ad-data=0.0.26-1"
    "cube2-data=1.3-1"
    "castle-game-engine-doc=7.0~alpha.2+dfsg1-5"
)
echo "packages: ${PACKAGES[*]}"

# deb_of NAME=VERSION: the downloaded package file (downloads it if needed).
deb_of() {
    local name=${1%%=*} version=${1#*=}
    local file="$DEBS/${name}_${version}_all.deb"
    if [[ ! -s $file ]]; then
        (cd "$DEBS" && apt-get download -q "$name=$version") >&2 || {
            echo "error: apt-get download $name=$version failed (run 'apt-get update'? is the version still in the archive?)" >&2
            exit 1
        }
    fi
    [[ $(dpkg-deb -f "$file" Package) == "$name" && $(dpkg-deb -f "$file" Version) == "$version" ]] ||
        { echo "error: $file is not $name $version" >&2; exit 1; }
    echo "$file"
}

# extract NAME=VERSION MEMBER...: the named members of the package's data
# (as `dpkg-deb -x` would unpack them, but only these) into $WORK/NAME.
extract() {
    local spec=$1 deb
    shift
    deb=$(deb_of "$spec")
    echo "package ${spec%%=*} $(dpkg-deb -f "$deb" Version)  ($(basename "$deb"), sha256 $(sha256sum "$deb" | cut -c1-64))"
    mkdir -p "$WORK/${spec%%=*}"
    dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$WORK/${spec%%=*}" "${@/#/./}"
    for m in "$@"; do echo "  took /$m"; done
}

RE=usr/share/games/redeclipse/data/trak/trak5
extract "redeclipse-data=1.6.0-1" \
    "$RE/floor2a.jpg" "$RE/floor2_n.png" "$RE/graypanel1.jpg" "$RE/graypanel1_n.png" "$RE/readme.txt" \
    usr/share/doc/redeclipse-data/copyright

ZIP=usr/share/games/0ad/mods/public/public.zip
extract "0ad-data=0.0.26-1" "$ZIP" usr/share/doc/0ad-data/copyright
ZT=art/textures/terrain/types/aegean_anatolia
unzip -q -o "$WORK/0ad-data/$ZIP" "$ZT/paving_01.png.cached.dds" "$ZT/paving_01_norm.png.cached.dds" -d "$WORK/0ad-data/zip"
echo "  took /$ZIP:$ZT/paving_01.png.cached.dds"
echo "  took /$ZIP:$ZT/paving_01_norm.png.cached.dds"
rm "$WORK/0ad-data/$ZIP"  # 3.2 GB

GK=usr/share/games/cube2/packages/gk/fantasy/castell_wall_gk_v01
extract "cube2-data=1.3-1" \
    "$GK/castell_wall_gk_v01_cc.jpg" "$GK/castell_wall_gk_v01_nm.jpg" "$GK/castell_wall_gk_v01_hm.jpg" \
    usr/share/doc/cube2-data/copyright

CG=usr/share/doc/castle-game-engine-doc/examples/terrain/data/textures
extract "castle-game-engine-doc=7.0~alpha.2+dfsg1-5" \
    "$CG/mntn_green_d.jpg" "$CG/mntn_green_n.jpg" "$CG/mntn_green_h.jpg" "$CG/AUTHORS.txt" \
    usr/share/doc/castle-game-engine-doc/copyright

# Copies, downsizing, and a report of what each file holds.
# copy:     byte-identical copy.
# rgb256:   colour, box-filtered to 256x256, saved as JPEG (quality 92, 4:4:4);
#           the source's alpha, if any, must be constant 255 and is dropped.
# nrm256:   normal map, box-filtered to 256x256 channel by channel (no
#           premultiplied alpha, no renormalising, no channel moved or
#           flipped), saved as PNG with the source's channels (RGB or RGBA).
# grey256:  grey height image, to one channel (PIL's "L" luma of a grey
#           image), box-filtered to 256x256, saved as PNG.
"$PYTHON" - "$WORK" "$OUT" <<'EOF'
import os, shutil, sys
import numpy as np
from PIL import Image

work, out = sys.argv[1], sys.argv[2]
RE = "redeclipse-data/usr/share/games/redeclipse/data/trak/trak5/"
ZT = "0ad-data/zip/art/textures/terrain/types/aegean_anatolia/"
GK = "cube2-data/usr/share/games/cube2/packages/gk/fantasy/castell_wall_gk_v01/"
CG = "castle-game-engine-doc/usr/share/doc/castle-game-engine-doc/examples/terrain/data/textures/"
JOBS = [  # material, output file, source (under work), operation
    ("tiles", "floor2a.jpg", RE + "floor2a.jpg", "copy"),
    ("tiles", "floor2_n.png", RE + "floor2_n.png", "copy"),
    ("tiles", "README.trak5.txt", RE + "readme.txt", "copy"),
    ("tiles", "COPYRIGHT", "redeclipse-data/usr/share/doc/redeclipse-data/copyright", "copy"),
    ("metal_panel", "graypanel1.jpg", RE + "graypanel1.jpg", "copy"),
    ("metal_panel", "graypanel1_n.png", RE + "graypanel1_n.png", "copy"),
    ("metal_panel", "README.trak5.txt", RE + "readme.txt", "copy"),
    ("metal_panel", "COPYRIGHT", "redeclipse-data/usr/share/doc/redeclipse-data/copyright", "copy"),
    ("paving", "paving_01_256.jpg", ZT + "paving_01.png.cached.dds", "rgb256"),
    ("paving", "paving_01_norm_256.png", ZT + "paving_01_norm.png.cached.dds", "nrm256"),
    ("paving", "COPYRIGHT", "0ad-data/usr/share/doc/0ad-data/copyright", "copy"),
    ("stone_wall", "castell_wall_gk_v01_cc_256.jpg", GK + "castell_wall_gk_v01_cc.jpg", "rgb256"),
    ("stone_wall", "castell_wall_gk_v01_nm_256.png", GK + "castell_wall_gk_v01_nm.jpg", "nrm256"),
    ("stone_wall", "castell_wall_gk_v01_hm_256.png", GK + "castell_wall_gk_v01_hm.jpg", "grey256"),
    ("stone_wall", "COPYRIGHT", "cube2-data/usr/share/doc/cube2-data/copyright", "copy"),
    ("rock", "mntn_green_d_256.jpg", CG + "mntn_green_d.jpg", "rgb256"),
    ("rock", "mntn_green_n_256.png", CG + "mntn_green_n.jpg", "nrm256"),
    ("rock", "mntn_green_h_256.png", CG + "mntn_green_h.jpg", "grey256"),
    ("rock", "AUTHORS.txt", CG + "AUTHORS.txt", "copy"),
    ("rock", "COPYRIGHT", "castle-game-engine-doc/usr/share/doc/castle-game-engine-doc/copyright", "copy"),
]
N = 256

def box(im):  # channel by channel: PIL premultiplies alpha when it resizes RGBA
    return Image.merge(im.mode, [b.resize((N, N), Image.BOX) for b in im.split()])

def describe(path):
    im = Image.open(path)
    s = f"{im.size[0]}x{im.size[1]} {im.mode}"
    if "A" in im.getbands():
        lo, hi = im.getchannel("A").getextrema()
        s += f", alpha {lo}..{hi}" + (" (constant)" if lo == hi else "")
    if im.mode == "L":
        lo, hi = im.getextrema()
        s += f", grey {lo}..{hi}"
    return s

for material, name, src, op in JOBS:
    os.makedirs(os.path.join(out, material), exist_ok=True)
    src_path, dst = os.path.join(work, src), os.path.join(out, material, name)
    if op == "copy":
        shutil.copyfile(src_path, dst)
    else:
        im = Image.open(src_path)
        im.load()
        what = f"{im.size[0]}x{im.size[1]} {im.mode}" + (f" {im.format}" if im.format else "")
        if op == "rgb256":
            if "A" in im.getbands():
                assert im.getchannel("A").getextrema() == (255, 255), f"{src}: alpha is not constant"
            box(im.convert("RGB")).save(dst, quality=92, subsampling=0)
        elif op == "nrm256":
            box(im if im.mode in ("RGB", "RGBA") else im.convert("RGBA")).save(dst, optimize=True)
        elif op == "grey256":
            box(im.convert("L")).save(dst, optimize=True)
        print(f"  {op}: {src} ({what}) -> {material}/{name}")
    extra = "" if name in ("COPYRIGHT",) or name.endswith(".txt") else "  [" + describe(dst) + "]"
    print(f"{material}/{name}: {os.path.getsize(dst)} bytes{extra}")

# The green convention, measured: slopes of the height against the normal
# map's red and green (rows counted downward). Green up (OpenGL, +y = +v =
# toward the image's top): G - 0.5 follows +dh/drow; green down (DirectX):
# -dh/drow. Red follows -dh/dcol whenever white is high.
def channel(path, c):
    a = np.asarray(Image.open(path).convert("RGBA"), dtype=np.float64) / 255
    return a[..., "rgba".index(c)]

def corr(a, b):
    a, b = a - a.mean(), b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))

CHECKS = [  # material, normal map, height file, height channel
    ("tiles", "floor2_n.png", "floor2_n.png", "a"),
    ("metal_panel", "graypanel1_n.png", "graypanel1_n.png", "a"),
    ("paving", "paving_01_norm_256.png", "paving_01_norm_256.png", "a"),
    ("stone_wall", "castell_wall_gk_v01_nm_256.png", "castell_wall_gk_v01_hm_256.png", "r"),
    ("rock", "mntn_green_n_256.png", "mntn_green_h_256.png", "r"),
]
for material, nm, hf, c in CHECKS:
    n = lambda k: channel(os.path.join(out, material, nm), k) - 0.5
    h = channel(os.path.join(out, material, hf), c)
    dcol = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) / 2
    drow = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) / 2
    r, g = corr(n("r"), -dcol), corr(n("g"), drow)
    print(f"{material}: corr(R, -dh/dcol) = {r:+.2f}, corr(G, +dh/drow) = {g:+.2f}: "
          f"{'white is high' if r > 0 else 'white is LOW'}, green {'up (OpenGL)' if g * r > 0 else 'down (DirectX)'}")
EOF

echo "total: $(find "$OUT" -type f -printf '%s\n' | awk '{s += $1} END {print s}') bytes in $(find "$OUT" -type f | wc -l) files under $OUT (the hand-written README.md and scene files included)"
