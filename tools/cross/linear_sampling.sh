#!/usr/bin/env bash
# Builds tools/cross/linear_sampling.c for ARCH (arm64, armhf or native) and
# runs it under qemu-user with each of llvmpipe's two filtering paths (the
# packed 8-bit "AoS" one and the float one, GALLIVM_PERF=no_aos_sampling)
# and, on armhf, with an emulated CPU with NEON (qemu's default) and without
# it (-cpu cortex-r5f: VFPv3-D16, Debian armhf's baseline). One line per run;
# exit 0 when every run's texels were right.
#   tools/cross/linear_sampling.sh arm64|armhf|native [SYSROOT]
set -uo pipefail
arch=${1:-}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
case "$arch" in
    native) cc=(gcc); run=() ;;
    arm64|armhf)
        triplet=$([ "$arch" = arm64 ] && echo aarch64-linux-gnu || echo arm-linux-gnueabihf)
        qemu=$([ "$arch" = arm64 ] && echo qemu-aarch64 || echo qemu-arm)
        sysroot=${2:-${PX_SYSROOT:-$HOME/.cache/parallaxes/sysroot/$arch}}
        [ -f "$sysroot/.complete" ] || { echo "no $arch sysroot at $sysroot: run tools/cross/make_sysroot.sh $arch" >&2; exit 2; }
        cc=("$triplet-gcc" --sysroot="$sysroot" -Wl,-rpath-link,"$sysroot/usr/lib/$triplet" -Wl,-rpath-link,"$sysroot/lib/$triplet")
        run=("$qemu" -L "$sysroot") ;;
    *) echo "usage: $0 arm64|armhf|native [SYSROOT]" >&2; exit 2 ;;
esac
"${cc[@]}" -O1 "$here/linear_sampling.c" -lEGL -lGLESv2 -o "$work/linear_sampling" || exit 2
cpus=("")
[ "$arch" = armhf ] && cpus=("" "-cpu cortex-r5f")
status=0
for cpu in "${cpus[@]}"; do
    for perf in "" no_aos_sampling; do
        # shellcheck disable=SC2086
        out=$(GALLIVM_PERF=$perf "${run[@]}" $cpu "$work/linear_sampling" 2>&1)
        rc=$?
        [ "$rc" = 0 ] || status=1
        printf '%-8s %-16s GALLIVM_PERF=%-16s %s | %s\n' "$arch" "${cpu:-(default cpu)}" "${perf:-(unset)}" \
            "$([ "$rc" = 0 ] && echo right || echo "WRONG (exit $rc)")" \
            "$(grep -E '^(NEAREST|LINEAR)' <<<"$out" | sed 's/ channels wrong//' | paste -sd';')"
    done
done
exit "$status"
