#!/usr/bin/env bash
# Makes what `parallax profile --gpu` needs to compile shaders with real
# mobile GPU compilers on this machine: Mesa's own arm64 drivers (Panfrost
# for Mali Midgard/Bifrost/Valhall, Freedreno's ir3 for Adreno, V3D for the
# Raspberry Pi 4, Lima for Mali-400/450), which Debian ships only in its
# arm64 package, loaded under qemu-aarch64 with no device through Mesa's
# drm-shim "noop" libraries, and a small arm64 program that compiles and
# draws each shader so that the drivers print their statistics.
#   tools/cross/make_gpu_compilers.sh [DIR]
# DIR defaults to $PX_GPU_COMPILERS ($HOME/.cache/parallaxes/gpu-compilers);
# a finished one (DIR/.complete naming the same Mesa) is reused.
#
# From Debian's packages only, never touching the host's package state: the
# arm64 sysroot (tools/cross/make_sysroot.sh arm64, which also installs the
# cross compiler and qemu-user), Mesa's source package of the very version
# the sysroot's libgl1-mesa-dri has (`apt-get source`, with a private apt
# state whose Sources index is checked against Debian's archive keyring and
# whose files are checked against the index's SHA256), and libdrm-dev for
# arm64 (its headers). Only src/drm-shim, the four drivers' noop shims and
# the few util files they need are unpacked and cross-compiled (about 10 s);
# Mesa's standalone compilers are not built (22.3's crash on real shaders).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dir=${1:-${PX_GPU_COMPILERS:-$HOME/.cache/parallaxes/gpu-compilers}}
mirror=${PX_DEBIAN_MIRROR:-http://deb.debian.org/debian}
security=${PX_DEBIAN_SECURITY:-http://deb.debian.org/debian-security}
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
triplet=aarch64-linux-gnu

sysroot=$(bash "$here/make_sysroot.sh" arm64 | tail -1)
mesa_version=$(awk '$1 == "libgl1-mesa-dri" {print $2}' "$sysroot/MANIFEST")
[ -n "$mesa_version" ] || { echo "make_gpu_compilers: $sysroot/MANIFEST names no libgl1-mesa-dri" >&2; exit 1; }
probe_hash=$(cat "$root/tools/gpu/shader_probe.c" "$root/tools/cross/es_helpers.h" "$0" | sha256sum | cut -c1-16)
want="mesa $mesa_version probe $probe_hash sysroot $sysroot"
if [ -f "$dir/.complete" ] && [ "$(cat "$dir/.complete")" = "$want" ]; then
    echo "$dir"
    exit 0
fi

state="$dir.apt"
rm -rf "$dir" "$state"
mkdir -p "$dir" "$state/lists/partial" "$state/cache/archives/partial" "$state/src"
: > "$state/status"
cat > "$state/sources.list" <<LIST
deb [signed-by=$keyring] $mirror bookworm main
deb-src [signed-by=$keyring] $mirror bookworm main
deb [signed-by=$keyring] $mirror bookworm-updates main
deb-src [signed-by=$keyring] $mirror bookworm-updates main
deb [signed-by=$keyring] $security bookworm-security main
deb-src [signed-by=$keyring] $security bookworm-security main
LIST
apt_opts=(-o "APT::Architecture=arm64" -o "APT::Architectures::=arm64"
    -o "Dir::Etc::SourceList=$state/sources.list" -o "Dir::Etc::SourceParts=/nonexistent"
    -o "Dir::Etc::Preferences=/nonexistent" -o "Dir::Etc::PreferencesParts=/nonexistent"
    -o "Dir::State::Lists=$state/lists" -o "Dir::State::status=$state/status"
    -o "Dir::Cache=$state/cache" -o "Debug::NoLocking=1" -o "APT::Install-Recommends=0"
    -o "APT::Sandbox::User=root")
echo "make_gpu_compilers: reading Debian's package and source lists" >&2
for try in 1 2 3; do
    apt-get "${apt_opts[@]}" update >"$state/update.log" 2>&1 && ! grep -q '^E:' "$state/update.log" && break
    [ "$try" = 3 ] && { tail -8 "$state/update.log" >&2; exit 1; }
    sleep $((try * 10))
done
echo "make_gpu_compilers: downloading Mesa $mesa_version's source (about 28 MB) and libdrm-dev" >&2
(cd "$state/src" && apt-get "${apt_opts[@]}" source --download-only "mesa=$mesa_version" >"$state/source.log" 2>&1) ||
    { tail -8 "$state/source.log" >&2; echo "make_gpu_compilers: no source package mesa=$mesa_version" >&2; exit 1; }
apt-get "${apt_opts[@]}" install -y -d libdrm-dev >"$state/drm.log" 2>&1 || { tail -8 "$state/drm.log" >&2; exit 1; }
drm_deb=$(ls "$state"/cache/archives/libdrm-dev_*.deb)
dpkg-deb -x "$drm_deb" "$state/drm"
orig=$(ls "$state"/src/mesa_*.orig.tar.*)
upstream=$(basename "$orig" | sed -E 's/^mesa_(.*)\.orig\.tar\..*$/\1/')
src="$state/src/mesa-$upstream"
tar -xf "$orig" -C "$state/src" "mesa-$upstream/include" "mesa-$upstream/src/drm-shim" "mesa-$upstream/src/util" \
    "mesa-$upstream/src/c11" "mesa-$upstream/src/panfrost/drm-shim" "mesa-$upstream/src/freedreno/drm-shim" \
    "mesa-$upstream/src/broadcom/drm-shim" "mesa-$upstream/src/gallium/drivers/lima/drm-shim"

echo "make_gpu_compilers: building the drm-shim noop libraries and the shader probe for arm64" >&2
# What Mesa's meson configuration would define for glibc on Linux.
cc=("$triplet-gcc" --sysroot="$sysroot" -fPIC -O2 -std=gnu11 -D_GNU_SOURCE -DHAVE_PTHREAD -DHAVE_TIMESPEC_GET
    -DHAVE_MEMFD_CREATE -DHAVE_ENDIAN_H -DHAVE_DLFCN_H -DHAVE_STRUCT_TIMESPEC -DHAVE_DL_ITERATE_PHDR
    -I"$src/include" -I"$src/src" -I"$src/src/util" -I"$src/src/mesa" -I"$src/src/gallium/include"
    -I"$src/src/gallium/auxiliary" -I"$src/src/mapi" -I"$state/drm/usr/include" -I"$state/drm/usr/include/libdrm")
obj="$state/obj"
mkdir -p "$obj"
common=()
for f in drm-shim/device.c drm-shim/drm_shim.c util/hash_table.c util/set.c util/vma.c util/u_debug.c \
         util/ralloc.c util/os_misc.c util/os_file.c util/u_printf.c; do
    o="$obj/$(echo "$f" | tr / _).o"
    "${cc[@]}" -c "$src/src/$f" -o "$o"
    common+=("$o")
done
declare -A shim_source=([panfrost]=panfrost/drm-shim/panfrost_noop.c [freedreno]=freedreno/drm-shim/freedreno_noop.c
    [v3d]=broadcom/drm-shim/v3d_noop.c [lima]=gallium/drivers/lima/drm-shim/lima_noop.c)
for name in panfrost freedreno v3d lima; do
    "${cc[@]}" -c "$src/src/${shim_source[$name]}" -o "$obj/$name.o"
    "$triplet-gcc" --sysroot="$sysroot" -shared -Wl,--no-undefined "${common[@]}" "$obj/$name.o" -ldl -lpthread -lm \
        -o "$dir/lib${name}_noop_drm_shim.so"
done
"$triplet-gcc" --sysroot="$sysroot" -Wl,-rpath-link,"$sysroot/usr/lib/$triplet" -Wl,-rpath-link,"$sysroot/lib/$triplet" \
    -O2 -Wall "$root/tools/gpu/shader_probe.c" -lEGL -lGLESv2 -o "$dir/shader_probe"
{
    echo "# made by tools/cross/make_gpu_compilers.sh on $(date -u +%Y-%m-%d)"
    echo "sysroot $sysroot"
    echo "mesa $mesa_version (the sysroot's libgl1-mesa-dri; drm-shim from its source package)"
    for f in "$state"/src/mesa_*; do echo "source $(basename "$f") $(sha256sum "$f" | cut -d' ' -f1)"; done
    echo "libdrm-dev $(dpkg-deb -f "$drm_deb" Version) $(sha256sum "$drm_deb" | cut -d' ' -f1)"
    echo "qemu $(qemu-aarch64 --version | head -1)"
} > "$dir/MANIFEST"
rm -rf "$state/src" "$state/obj" "$state/cache/archives"/*.deb
echo "$want" > "$dir/.complete"
echo "make_gpu_compilers: done, in $dir" >&2
echo "$dir"
