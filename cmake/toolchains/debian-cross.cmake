# The body of the Debian cross toolchain files (aarch64-linux-gnu.cmake,
# arm-linux-gnueabihf.cmake), which set GPORT_CROSS_TRIPLE, _PROCESSOR, _QEMU
# and _DEB_ARCH before including it.
#
# - Compilers: Debian's cross gcc (crossbuild-essential-<arch>), which finds
#   the target's headers and libraries in the multiarch directories.
# - pkg-config reads only the target's .pc files.
# - Tests run under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR), never with
#   `-L /usr/<triple>`: that mixes the cross toolchain's own loader with the
#   target's installed glibc of another version, and a forked child could then
#   spin for ever. The loader and glibc come from one place: the sysroot
#   (QEMU_LD_PREFIX), or the installed libc6:<arch> without one. Programs the
#   tests start by path (gportd, gport-sim, ...) run through binfmt_misc,
#   which scripts/deps.sh registers.
# - CPack labels the .deb with the target's Debian architecture.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${GPORT_CROSS_PROCESSOR})
set(CMAKE_C_COMPILER ${GPORT_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${GPORT_CROSS_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${GPORT_CROSS_TRIPLE})

# try_compile projects see GPORT_SYSROOT too.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES GPORT_SYSROOT)
if(NOT DEFINED GPORT_SYSROOT AND DEFINED ENV{GPORT_SYSROOT})
  set(GPORT_SYSROOT "$ENV{GPORT_SYSROOT}")
endif()
if(GPORT_SYSROOT)
  # A sysroot made by scripts/cross-sysroot.sh (dpkg -x of the target's
  # packages): headers, libraries and CMake packages come from there; the
  # cross compiler keeps its own C++ headers.
  set(CMAKE_SYSROOT "${GPORT_SYSROOT}")
  set(CMAKE_FIND_ROOT_PATH "${GPORT_SYSROOT}")
  set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
  set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
  set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
  set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
  set(ENV{PKG_CONFIG_SYSROOT_DIR} "${GPORT_SYSROOT}")
  set(ENV{PKG_CONFIG_LIBDIR}
      "${GPORT_SYSROOT}/usr/lib/${GPORT_CROSS_TRIPLE}/pkgconfig:${GPORT_SYSROOT}/usr/share/pkgconfig:${GPORT_SYSROOT}/usr/lib/pkgconfig")
else()
  # The target's -dev packages installed with multiarch (dpkg --add-architecture).
  set(ENV{PKG_CONFIG_LIBDIR}
      "/usr/lib/${GPORT_CROSS_TRIPLE}/pkgconfig:/usr/share/pkgconfig:/usr/lib/pkgconfig")
endif()
# Debian's ARM g++ notes every std::vector iterator argument whose passing
# changed in GCC 7.1: about code built with older compilers, never ours.
string(APPEND CMAKE_CXX_FLAGS_INIT " -Wno-psabi")

# qemu-user runs the target's programs: the test binaries through the
# emulator, and everything else the tests start by path (gportd, gport-sim)
# through binfmt_misc. With a sysroot, its loader and glibc (one package
# version) serve both, through QEMU_LD_PREFIX, which scripts/test.sh also
# exports for ctest.
find_program(GPORT_CROSS_EMULATOR ${GPORT_CROSS_QEMU})
if(GPORT_CROSS_EMULATOR AND GPORT_SYSROOT)
  set(CMAKE_CROSSCOMPILING_EMULATOR /usr/bin/env "QEMU_LD_PREFIX=${GPORT_SYSROOT}"
                                    ${GPORT_CROSS_EMULATOR})
elseif(GPORT_CROSS_EMULATOR)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${GPORT_CROSS_EMULATOR})
endif()
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${GPORT_CROSS_DEB_ARCH} CACHE STRING
    "Debian architecture of the package")
