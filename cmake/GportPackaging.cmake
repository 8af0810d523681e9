# Installation layout and the Debian package (CPack).
#
# Include once from the top-level CMakeLists.txt, after project() and before
# the parts are added: the parts read the GPORT_*DIR variables defined here.
#
# Where the system files go. The unit, sysusers.d and udev directories are
# decided at *install* time, from the prefix actually used (cmake --install
# --prefix, or /usr when CPack stages the .deb):
#   prefix /usr  -> the directories the system's pkg-config files name
#                   (systemd.pc, udev.pc), e.g. /lib/systemd/system on
#                   Debian 12, with /usr/lib/... fallbacks when absent;
#   other prefix -> <prefix>/lib/systemd/system, <prefix>/lib/sysusers.d,
#                   <prefix>/lib/udev/rules.d; systemd and udev search
#                   /usr/local/lib/... too, so the default prefix just works.
# Setting GPORT_SYSTEMD_UNITDIR, GPORT_SYSUSERSDIR or GPORT_UDEV_RULESDIR
# forces a directory whatever the prefix.
#
# The configuration directory follows the prefix too, as GNUInstallDirs maps
# SYSCONFDIR (/etc/gportd for /usr, <prefix>/etc/gportd otherwise;
# cmake/GportConfDir.cmake), and gportd finds it from where it was installed.
# GPORT_CONFIG_DIR forces one directory, for the files and for gportd.

include_guard(GLOBAL)
include(GNUInstallDirs)
find_package(PkgConfig QUIET)

set(GPORT_SYSTEMD_UNITDIR "" CACHE PATH "systemd system unit directory (empty: automatic)")
set(GPORT_SYSUSERSDIR "" CACHE PATH "sysusers.d directory (empty: automatic)")
set(GPORT_UDEV_RULESDIR "" CACHE PATH "udev rules directory (empty: automatic)")
set(GPORT_CONFIG_DIR "" CACHE PATH
    "gportd's configuration directory, absolute (empty: automatic, from the install prefix)")
unset(GPORT_CONFDIR CACHE)  # the old, always absolute /etc/gportd

# _gport_pkg_var(<out> <module> <variable> <fallback>): a pkg-config variable
# of an installed .pc file, or the fallback when pkg-config or the file is
# missing.
function(_gport_pkg_var out module variable fallback)
  set(value "")
  if(PKG_CONFIG_FOUND)
    pkg_get_variable(value ${module} ${variable})
  endif()
  # pkg-config prefixes the paths it reports with PKG_CONFIG_SYSROOT_DIR (a
  # cross build's sysroot); the package installs to the target's own paths.
  if(DEFINED ENV{PKG_CONFIG_SYSROOT_DIR} AND NOT "$ENV{PKG_CONFIG_SYSROOT_DIR}" STREQUAL ""
     AND NOT "$ENV{PKG_CONFIG_SYSROOT_DIR}" STREQUAL "/")
    string(REGEX REPLACE "/+$" "" _sysroot "$ENV{PKG_CONFIG_SYSROOT_DIR}")
    string(FIND "${value}" "${_sysroot}/" _at)
    if(_at EQUAL 0)
      string(LENGTH "${_sysroot}" _length)
      string(SUBSTRING "${value}" ${_length} -1 value)
    endif()
  endif()
  if(value STREQUAL "")
    set(value "${fallback}")
  endif()
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

# The system's own directories, used when installing to /usr.
_gport_pkg_var(_gport_utildir systemd systemdutildir /usr/lib/systemd)
_gport_pkg_var(GPORT_SYSTEM_UNITDIR systemd systemdsystemunitdir /usr/lib/systemd/system)
_gport_pkg_var(GPORT_SYSTEM_SYSUSERSDIR systemd sysusersdir /usr/lib/sysusers.d)
# No udev.pc (Debian ships it with libudev-dev only): udev's directory sits
# beside systemd's (/lib/systemd -> /lib/udev, /usr/lib/systemd -> /usr/lib/udev).
get_filename_component(_gport_libdir "${_gport_utildir}" DIRECTORY)
_gport_pkg_var(_gport_udevdir udev udevdir "${_gport_libdir}/udev")
set(GPORT_SYSTEM_UDEV_RULESDIR "${_gport_udevdir}/rules.d")
unset(_gport_utildir)
unset(_gport_libdir)
unset(_gport_udevdir)

# Each part installs its own program (install(TARGETS ... RUNTIME DESTINATION
# ${CMAKE_INSTALL_BINDIR})); the documentation is installed from here, to
# ${CMAKE_INSTALL_DOCDIR}, which the units' Documentation= lines point to.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        FILES_MATCHING PATTERN "*.md")
# gport-mavlink's config with every key at its default, to copy to
# /etc/gportd/mavlink.json and edit (docs/mavlink.md, "Options").
install(FILES ${CMAKE_SOURCE_DIR}/config/mavlink.json DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)

# ---- Debian package: cpack -G DEB -----------------------------------------
set(CPACK_PACKAGE_NAME "gportd")
set(CPACK_PACKAGE_VENDOR "gportd project")
set(CPACK_PACKAGE_CONTACT "gportd maintainers <gportd@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Shared, safe, observable G-Port gimbal service")
set(CPACK_PACKAGE_DESCRIPTION
    "gportd owns the UART of a HEQUAV G-Port camera gimbal and serves it to any number of local \
processes over a Unix socket (newline-delimited JSON-RPC). Includes gportctl, the command-line \
client, gport-sim, a simulated gimbal on a pseudo-terminal, libgport-client, the C++ client \
library, with its headers, pkg-config file and CMake package, and gport, the Python client module.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
# The package's architecture is the target's, not the build machine's (CPack
# asks dpkg, which names the host: an arm64 build packaged on amd64 was once
# labelled amd64). The toolchain files set it; a native build names its own.
if(NOT CPACK_DEBIAN_PACKAGE_ARCHITECTURE)
  set(_gport_deb_arches "x86_64-linux-gnu=amd64" "aarch64-linux-gnu=arm64"
      "arm-linux-gnueabihf=armhf" "i386-linux-gnu=i386" "riscv64-linux-gnu=riscv64")
  foreach(_pair IN LISTS _gport_deb_arches)
    string(REPLACE "=" ";" _pair "${_pair}")
    list(GET _pair 0 _triple)
    list(GET _pair 1 _arch)
    if(CMAKE_LIBRARY_ARCHITECTURE STREQUAL _triple)
      set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${_arch})
    endif()
  endforeach()
  if(NOT CPACK_DEBIAN_PACKAGE_ARCHITECTURE AND CMAKE_CROSSCOMPILING)
    message(FATAL_ERROR "cross-building for ${CMAKE_LIBRARY_ARCHITECTURE}: set "
                        "CPACK_DEBIAN_PACKAGE_ARCHITECTURE to its Debian architecture")
  endif()
endif()
# A cross build's libraries are the target's: dpkg-shlibdeps must read them
# with the target's objdump and find their packages (DEB_HOST_ARCH), in the
# sysroot's own dpkg database when there is one (scripts/cross-sysroot.sh
# writes it; dpkg-query reads DPKG_ADMINDIR). cpack runs this file first.
if(CMAKE_CROSSCOMPILING)
  set(_gport_cpack_env "set(ENV{DEB_HOST_ARCH} \"${CPACK_DEBIAN_PACKAGE_ARCHITECTURE}\")\n")
  if(GPORT_SYSROOT)
    string(APPEND _gport_cpack_env "set(ENV{DPKG_ADMINDIR} \"${GPORT_SYSROOT}/var/lib/dpkg\")\n")
    set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${GPORT_SYSROOT}/lib/${CMAKE_LIBRARY_ARCHITECTURE}"
        "${GPORT_SYSROOT}/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}")
  endif()
  file(WRITE ${CMAKE_BINARY_DIR}/cpack/cross-env.cmake "${_gport_cpack_env}")
  set(CPACK_PROJECT_CONFIG_FILE ${CMAKE_BINARY_DIR}/cpack/cross-env.cmake)
  unset(_gport_cpack_env)
endif()
set(CPACK_DEBIAN_PACKAGE_SECTION "misc")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
# Library dependencies come from dpkg-shlibdeps (package dpkg-dev); the rest
# are the tools the maintainer scripts call: systemd-sysusers and systemctl
# (systemd), udevadm (udev), deb-systemd-helper/-invoke (init-system-helpers).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd, udev, init-system-helpers (>= 1.54~)")
# Building against libgport-client's headers: AsyncClient needs Boost.Asio.
# The Python client (client/python, pure Python, standard library only) ships
# in this package under /usr/lib/python3/dist-packages rather than in a
# separate python3-gport: it is a few small files, versioned with the daemon
# whose protocol it speaks. Python is only suggested: the daemon runs without it.
# `gportctl geotag` runs exiftool (libimage-exiftool-perl): suggested too.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS
    "libboost-dev (>= 1.74), pkg-config, python3 (>= 3.11), libimage-exiftool-perl")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

# Maintainer scripts, plus a conffiles list generated from what was actually
# staged under /etc (so a local edit of /etc/gportd/gportd.json survives an
# upgrade), written by a script CPack runs after staging and before packing.
set(_gport_debian_dir ${CMAKE_SOURCE_DIR}/systemd/debian)
set(CPACK_GPORT_CONFFILES ${CMAKE_BINARY_DIR}/cpack/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${_gport_debian_dir}/postinst ${_gport_debian_dir}/prerm ${_gport_debian_dir}/postrm
    ${CPACK_GPORT_CONFFILES})
set(CPACK_PRE_BUILD_SCRIPTS ${_gport_debian_dir}/conffiles.cmake)
unset(_gport_debian_dir)

set(CPACK_GENERATOR "DEB")
set(CPACK_SOURCE_GENERATOR "TGZ")
set(CPACK_SOURCE_IGNORE_FILES "/\\\\.git/" "/build[^/]*/")
include(CPack)
