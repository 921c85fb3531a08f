# 64-bit ARM Linux (Raspberry Pi 3/4/5 64-bit, i.MX8, Rockchip, Jetson):
#   tools/cross/make_sysroot.sh arm64 && cmake --preset arm64
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(PX_CROSS_ARCH arm64)
set(PX_CROSS_TRIPLET aarch64-linux-gnu)
set(PX_CROSS_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
