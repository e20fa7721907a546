# Cross-builds for Debian 12 arm64 (the Raspberry Pi OS 64-bit class box)
# with Debian's cross compiler against the arm64 sysroot that
# scripts/arm64-sysroot creates; the `arm64` preset uses it. Built programs
# run on this machine under qemu-user: CMake's emulator runs the tests and
# gtest's test discovery, `-L <sysroot>` (QEMU_LD_PREFIX's option form) makes
# qemu load the arm64 dynamic loader and libraries from the sysroot.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# The try_compile projects CMake configures re-read this file: pass the
# chosen sysroot on to them.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES SPINEWATCH_SYSROOT)
if(NOT SPINEWATCH_SYSROOT)
  if(DEFINED ENV{SPINEWATCH_SYSROOT})
    set(SPINEWATCH_SYSROOT $ENV{SPINEWATCH_SYSROOT})
  else()
    set(SPINEWATCH_SYSROOT /var/cache/spinewatch-sysroot/bookworm-arm64)
  endif()
endif()
set(SPINEWATCH_SYSROOT ${SPINEWATCH_SYSROOT} CACHE PATH "The arm64 sysroot (scripts/arm64-sysroot)")
if(NOT EXISTS ${SPINEWATCH_SYSROOT}/.spinewatch-packages)
  message(FATAL_ERROR "no arm64 sysroot at ${SPINEWATCH_SYSROOT}: run scripts/install-deps "
                      "(it runs scripts/arm64-sysroot), or set SPINEWATCH_SYSROOT to one")
endif()

set(CMAKE_SYSROOT ${SPINEWATCH_SYSROOT})
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc-12)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++-12)

# Libraries, headers and CMake packages from the sysroot only; programs
# (pkg-config, python3, qemu) from this machine.
set(CMAKE_FIND_ROOT_PATH ${SPINEWATCH_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# The host's pkg-config reads the sysroot's .pc files and prefixes the
# paths they give with the sysroot.
set(ENV{PKG_CONFIG_SYSROOT_DIR} ${SPINEWATCH_SYSROOT})
set(ENV{PKG_CONFIG_LIBDIR}
    "${SPINEWATCH_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${SPINEWATCH_SYSROOT}/usr/lib/pkgconfig:${SPINEWATCH_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

find_program(SPINEWATCH_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${SPINEWATCH_QEMU_AARCH64} -L ${SPINEWATCH_SYSROOT})
