# 32-bit ARM Linux, hard float (ARMv7 with VFPv3-D16, Debian's armhf: Raspberry
# Pi 2/3 32-bit, i.MX6, older boards):
#   tools/cross/make_sysroot.sh armhf && cmake --preset armhf
set(CMAKE_SYSTEM_PROCESSOR arm)
set(PX_CROSS_ARCH armhf)
set(PX_CROSS_TRIPLET arm-linux-gnueabihf)
set(PX_CROSS_QEMU qemu-arm)
# The CPU qemu-arm emulates. Under qemu 7.2, llvmpipe's linear texture
# filtering is wrong on every emulated CPU with NEON (cortex-a7/a8/a9/a15,
# max: the default): its packed path returns texel (0,0) for every sample,
# its float path (GALLIVM_PERF=no_aos_sampling) drops the filter weights.
# On a CPU without NEON (cortex-r5f: VFPv3-D16, Debian armhf's baseline)
# llvmpipe generates VFP code and both paths are exact
# (tools/cross/reproduce.sh linear_sampling armhf; README "ARM builds").
set(PX_QEMU_CPU cortex-r5f CACHE STRING "The CPU qemu-arm emulates for the tests (empty: qemu's default, with NEON)")
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
# GCC's note that the ABI of passing some aggregates changed in GCC 7.1 (on
# every std::vector<double> insert): about nothing this project exposes.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
