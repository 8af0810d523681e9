# Cross-building gportd for 32-bit ARM with hardware floating point (Debian
# armhf: older Raspberry Pi and Raspberry Pi OS 32-bit) on a Debian 12 host;
# see aarch64-linux-gnu.cmake beside this file for the steps (with armhf).
set(GPORT_CROSS_TRIPLE arm-linux-gnueabihf)
set(GPORT_CROSS_PROCESSOR arm)
set(GPORT_CROSS_QEMU qemu-arm-static)
set(GPORT_CROSS_DEB_ARCH armhf)
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
