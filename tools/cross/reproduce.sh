#!/usr/bin/env bash
# Builds one of the minimal reproducers in tools/cross/ for ARCH (arm64,
# armhf or native) and runs it under qemu-user with each of llvmpipe's two
# filtering paths (the packed 8-bit "AoS" one and the float one,
# GALLIVM_PERF=no_aos_sampling) and, on armhf, with an emulated CPU with NEON
# (qemu's default) and without it (-cpu cortex-r5f: VFPv3-D16, Debian armhf's
# baseline). A header line per run, then the reproducer's own lines; exit 0
# when every run was right.
#   tools/cross/reproduce.sh linear_sampling|msaa_depth arm64|armhf|native [SYSROOT]
#     linear_sampling  a 4x4 texture sampled nearest and linear (ES 2.0)
#     msaa_depth       depth-tested draws into multisampled targets (ES 3.0),
#                      each case in its own process so a crash is a result
set -uo pipefail
name=${1:-}
arch=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
usage="usage: $0 linear_sampling|msaa_depth arm64|armhf|native [SYSROOT]"
case "$name" in
    linear_sampling|msaa_depth) ;;
    *) echo "$usage" >&2; exit 2 ;;
esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
case "$arch" in
    native) cc=(gcc); run=() ;;
    arm64|armhf)
        triplet=$([ "$arch" = arm64 ] && echo aarch64-linux-gnu || echo arm-linux-gnueabihf)
        qemu=$([ "$arch" = arm64 ] && echo qemu-aarch64 || echo qemu-arm)
        sysroot=${3:-${PX_SYSROOT:-$HOME/.cache/parallaxes/sysroot/$arch}}
        [ -f "$sysroot/.complete" ] || { echo "no $arch sysroot at $sysroot: run tools/cross/make_sysroot.sh $arch" >&2; exit 2; }
        cc=("$triplet-gcc" --sysroot="$sysroot" -Wl,-rpath-link,"$sysroot/usr/lib/$triplet" -Wl,-rpath-link,"$sysroot/lib/$triplet")
        run=("$qemu" -L "$sysroot") ;;
    *) echo "$usage" >&2; exit 2 ;;
esac
"${cc[@]}" -O1 -Wall "$here/$name.c" -lEGL -lGLESv2 -o "$work/$name" || exit 2
cpus=("")
[ "$arch" = armhf ] && cpus=("" "-cpu cortex-r5f")
status=0
for cpu in "${cpus[@]}"; do
    for perf in "" no_aos_sampling; do
        # shellcheck disable=SC2086
        out=$(GALLIVM_PERF=$perf "${run[@]}" $cpu "$work/$name" 2>&1)
        rc=$?
        [ "$rc" = 0 ] || status=1
        printf '%s %-8s %-16s GALLIVM_PERF=%-16s %s\n' "$name" "$arch" "${cpu:-(default cpu)}" "${perf:-(unset)}" \
            "$([ "$rc" = 0 ] && echo right || echo "WRONG (exit $rc)")"
        sed 's/^/    /' <<<"$out"
    done
done
exit "$status"
