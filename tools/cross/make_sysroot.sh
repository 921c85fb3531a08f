#!/usr/bin/env bash
# Makes a sysroot for cross-building ParallaxES and running it under qemu-user:
# Debian 12's own packages for ARCH (the Mesa EGL/GLES stack with llvmpipe
# and the mobile drivers, and the -dev packages the build links), fetched
# with a private apt state and unpacked with dpkg -x. The host's package
# state is never touched: no foreign architecture is added (multiarch would
# upgrade the host's own Mesa). apt checks every index against the Debian
# archive keyring and every .deb against the index's SHA256 before it is
# unpacked; the manifest lists each package, version and SHA256.
# Also installs the cross compiler and qemu-user on the host (apt, as root).
#   tools/cross/make_sysroot.sh arm64|armhf [DIR]
# DIR defaults to $PX_SYSROOT_CACHE/ARCH ($HOME/.cache/parallaxes/sysroot/ARCH);
# a finished sysroot (DIR/.complete with the same package list) is reused.
set -euo pipefail
arch=${1:-}
case "$arch" in
    arm64) triplet=aarch64-linux-gnu; qemu=qemu-aarch64 ;;
    armhf) triplet=arm-linux-gnueabihf; qemu=qemu-arm ;;
    *) echo "usage: $0 arm64|armhf [DIR]" >&2; exit 2 ;;
esac
dir=${2:-${PX_SYSROOT_CACHE:-$HOME/.cache/parallaxes/sysroot}/$arch}
mirror=${PX_DEBIAN_MIRROR:-http://deb.debian.org/debian}
security=${PX_DEBIAN_SECURITY:-http://deb.debian.org/debian-security}
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
# What runs (EGL, GLES, Mesa's drivers) and what the build links (glslang-tools:
# glslang's CMake package names its validator, which the build never runs).
packages="libc6 libstdc++6 libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri libgbm1
  libegl-dev libgles-dev libglm-dev libstb-dev libjpeg62-turbo-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev glslang-dev glslang-tools libastcenc-dev libzstd-dev"
want=$(echo $packages | tr ' ' '\n' | sort | tr '\n' ' ')

# The host's tools.
need=""
for p in g++-$triplet qemu-user; do
    dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q '^install ok installed$' || need="$need $p"
done
if [ -n "$need" ]; then
    [ "$(id -u)" = 0 ] || { echo "make_sysroot: missing host packages:$need (run as root, or: apt-get install$need)" >&2; exit 1; }
    echo "make_sysroot: installing$need" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $need >/dev/null ||
        { apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $need >/dev/null; }
fi
[ -r "$keyring" ] || { echo "make_sysroot: $keyring missing (package debian-archive-keyring)" >&2; exit 1; }

if [ -f "$dir/.complete" ] && [ "$(cat "$dir/.complete")" = "$want" ]; then
    echo "$dir"
    exit 0
fi

state="$dir.apt"
rm -rf "$dir" "$state"
mkdir -p "$dir" "$state/lists/partial" "$state/cache/archives/partial" "$state/etc"
: > "$state/status"
cat > "$state/sources.list" <<LIST
deb [signed-by=$keyring] $mirror bookworm main
deb [signed-by=$keyring] $mirror bookworm-updates main
deb [signed-by=$keyring] $security bookworm-security main
LIST
apt_opts=(-o "APT::Architecture=$arch" -o "APT::Architectures::=$arch"
    -o "Dir::Etc::SourceList=$state/sources.list" -o "Dir::Etc::SourceParts=/nonexistent"
    -o "Dir::Etc::Preferences=/nonexistent" -o "Dir::Etc::PreferencesParts=/nonexistent"
    -o "Dir::State::Lists=$state/lists" -o "Dir::State::status=$state/status"
    -o "Dir::Cache=$state/cache" -o "Debug::NoLocking=1" -o "APT::Install-Recommends=0")
echo "make_sysroot: reading Debian's $arch package lists" >&2
# A mirror caught mid-sync serves an index whose size or hash does not match
# its signed Release file: apt refuses it; try again a little later.
for try in 1 2 3 4; do
    apt-get "${apt_opts[@]}" update >"$state/update.log" 2>&1 && ! grep -q '^E:' "$state/update.log" && break
    if [ "$try" = 4 ]; then
        # Only the security suite's index still failing: go on with the
        # main suite's versions, and say so in the manifest.
        if grep '^E: Failed to fetch' "$state/update.log" | grep -qv debian-security; then
            tail -8 "$state/update.log" >&2; exit 1
        fi
        security_note="# bookworm-security's $arch index did not check out (mirror mid-sync): main-suite versions where it has newer ones"
        echo "make_sysroot: warning: ${security_note#\# }" >&2
        break
    fi
    echo "make_sysroot: the package lists did not check out (try $try of 4), trying again" >&2
    sleep $((try * 10))
done
echo "make_sysroot: downloading $arch packages (about 50 MB)" >&2
# -d: download only, the whole dependency closure, hashes checked by apt.
apt-get "${apt_opts[@]}" install -y -d $packages >"$state/install.log" 2>&1 ||
    { tail -20 "$state/install.log" >&2; exit 1; }
debs=("$state"/cache/archives/*.deb)
[ -e "${debs[0]}" ] || { echo "make_sysroot: apt downloaded nothing" >&2; exit 1; }
manifest="$dir/MANIFEST"
echo "# Debian bookworm $arch packages unpacked here by tools/cross/make_sysroot.sh on $(date -u +%Y-%m-%d)" > "$manifest"
[ -n "${security_note:-}" ] && echo "$security_note" >> "$manifest"
for d in "${debs[@]}"; do
    dpkg-deb -x "$d" "$dir"
    printf '%s %s %s\n' "$(dpkg-deb -f "$d" Package)" "$(dpkg-deb -f "$d" Version)" "$(sha256sum "$d" | cut -d' ' -f1)" >> "$manifest"
done
# Absolute symlinks (libfoo.so -> /lib/...) point into the host: make them
# relative to the sysroot, so that the linker and qemu -L find the target's.
find "$dir" -type l | while read -r link; do
    target=$(readlink "$link")
    case "$target" in
        /*) ln -sfn "$(realpath -m --relative-to="$(dirname "$link")" "$dir$target")" "$link" ;;
    esac
done
rm -rf "$state/cache/archives"/*.deb
echo "$want" > "$dir/.complete"
echo "make_sysroot: $(grep -vc '^#' "$manifest") packages, $(du -sh "$dir" | cut -f1) in $dir" >&2
echo "$dir"
