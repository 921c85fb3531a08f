# Shared by the ARM toolchain files: Debian's cross g++ for PX_CROSS_TRIPLET
# against a sysroot of Debian packages for that architecture
# (tools/cross/make_sysroot.sh), and qemu-user to run what is built (ctest,
# gtest discovery) on this machine.
#   PX_SYSROOT: the sysroot (-DPX_SYSROOT=... or the environment variable;
#   default $HOME/.cache/parallaxes/sysroot/<arch>, where make_sysroot.sh
#   puts it).
set(CMAKE_SYSTEM_NAME Linux)
if(NOT PX_SYSROOT)
  if(DEFINED ENV{PX_SYSROOT})
    set(PX_SYSROOT "$ENV{PX_SYSROOT}")
  else()
    set(PX_SYSROOT "$ENV{HOME}/.cache/parallaxes/sysroot/${PX_CROSS_ARCH}")
  endif()
endif()
if(NOT EXISTS "${PX_SYSROOT}/.complete")
  message(FATAL_ERROR "No ${PX_CROSS_ARCH} sysroot at ${PX_SYSROOT}: run tools/cross/make_sysroot.sh ${PX_CROSS_ARCH}"
                      " (or set PX_SYSROOT to one it made)")
endif()
# try_compile projects read this file again: hand them the sysroot.
set(ENV{PX_SYSROOT} "${PX_SYSROOT}")
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES PX_SYSROOT)

find_program(PX_CROSS_CXX ${PX_CROSS_TRIPLET}-g++)
find_program(PX_CROSS_CC ${PX_CROSS_TRIPLET}-gcc)
if(NOT PX_CROSS_CXX OR NOT PX_CROSS_CC)
  message(FATAL_ERROR "No ${PX_CROSS_TRIPLET}-g++: apt-get install g++-${PX_CROSS_TRIPLET}"
                      " (tools/cross/make_sysroot.sh installs it)")
endif()
set(CMAKE_C_COMPILER "${PX_CROSS_CC}")
set(CMAKE_CXX_COMPILER "${PX_CROSS_CXX}")
set(CMAKE_SYSROOT "${PX_SYSROOT}")
set(CMAKE_LIBRARY_ARCHITECTURE ${PX_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH "${PX_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# The sysroot's libraries pull in others (libEGL: libgbm, libdrm, ...): the
# linker finds those there too.
foreach(d "${PX_SYSROOT}/usr/lib/${PX_CROSS_TRIPLET}" "${PX_SYSROOT}/lib/${PX_CROSS_TRIPLET}")
  string(APPEND CMAKE_EXE_LINKER_FLAGS_INIT " -Wl,-rpath-link,${d}")
  string(APPEND CMAKE_SHARED_LINKER_FLAGS_INIT " -Wl,-rpath-link,${d}")
endforeach()

find_program(PX_QEMU ${PX_CROSS_QEMU})
if(PX_QEMU)
  # -L: the target's loader and libraries; Mesa's llvmpipe under it.
  set(CMAKE_CROSSCOMPILING_EMULATOR "${PX_QEMU};-L;${PX_SYSROOT}")
  if(PX_QEMU_CPU)
    list(APPEND CMAKE_CROSSCOMPILING_EMULATOR "-cpu" "${PX_QEMU_CPU}")
  endif()
endif()
