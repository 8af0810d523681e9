# Cross-building gportd for 64-bit ARM (Raspberry Pi 4/5, Jetson, Radxa) on a
# Debian 12 amd64 machine (docs/operations.md, "Building for ARM"):
#
#   source scripts/deps.sh && gport_install_cross_deps arm64   # g++, qemu-user
#   scripts/cross-sysroot.sh arm64 build/sysroot-arm64         # the target's -dev
#   cmake -S . -B build/arm64 -G Ninja \
#     -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#     -DGPORT_SYSROOT=$PWD/build/sysroot-arm64
#
# scripts/test-arm.sh does all of it and runs the tests. Without GPORT_SYSROOT
# the target's libraries come from this machine's multiarch directories
# (dpkg --add-architecture arm64 and the :arm64 -dev packages).
set(GPORT_CROSS_TRIPLE aarch64-linux-gnu)
set(GPORT_CROSS_PROCESSOR aarch64)
set(GPORT_CROSS_QEMU qemu-aarch64-static)
set(GPORT_CROSS_DEB_ARCH arm64)
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
