# Runs at install time (install(CODE) in systemd/CMakeLists.txt), so that the
# paths written into the units and the directories chosen follow the prefix
# actually used: `cmake --install --prefix ...`, or /usr when CPack stages the
# .deb. Inputs (set by the caller): GPORT_SRC_DIR,
# GPORT_BINDIR_REL, GPORT_DOCDIR_REL, GPORT_SYSCONFDIR_REL, GPORT_CONFIG_DIR,
# GPORT_CMAKE_DIR, the forced and the
# system directories (GPORT_SYSTEMD_UNITDIR / GPORT_SYSTEM_UNITDIR, ...).

# The directory for one kind of file: the forced one if set; the system's own
# under prefix /usr; else relative to the prefix.
function(gport_system_dir out forced system relative)
  if(NOT forced STREQUAL "")
    set(dir "${forced}")
  elseif(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
    set(dir "${system}")
  else()
    set(dir "${CMAKE_INSTALL_PREFIX}/${relative}")
  endif()
  set(${out} "${dir}" PARENT_SCOPE)
endfunction()

gport_system_dir(unitdir "${GPORT_SYSTEMD_UNITDIR}" "${GPORT_SYSTEM_UNITDIR}" lib/systemd/system)
gport_system_dir(sysusersdir "${GPORT_SYSUSERSDIR}" "${GPORT_SYSTEM_SYSUSERSDIR}" lib/sysusers.d)
gport_system_dir(rulesdir "${GPORT_UDEV_RULESDIR}" "${GPORT_SYSTEM_UDEV_RULESDIR}"
                 lib/udev/rules.d)

# The configuration directory the units name: where config/ installs
# gportd.json for this prefix.
include("${GPORT_CMAKE_DIR}/GportConfDir.cmake")
gport_confdir(GPORT_CONFDIR "${CMAKE_INSTALL_PREFIX}" "${GPORT_SYSCONFDIR_REL}" "${GPORT_CONFIG_DIR}")

# Units: substitute the installed paths and the shared sandbox.
file(READ "${GPORT_SRC_DIR}/units/sandbox.conf" GPORT_UNIT_SANDBOX)
file(READ "${GPORT_SRC_DIR}/units/mavlink-sandbox.conf" GPORT_MAVLINK_SANDBOX)
file(READ "${GPORT_SRC_DIR}/units/web-sandbox.conf" GPORT_WEB_SANDBOX)
set(GPORT_BINDIR "${CMAKE_INSTALL_PREFIX}/${GPORT_BINDIR_REL}")
set(GPORT_DOC_DIR "${CMAKE_INSTALL_PREFIX}/${GPORT_DOCDIR_REL}")
# They are staged in a private directory under the temporary directory, not
# in the build tree: whoever installs (a user installing to a prefix of
# their own, CPack) may be unable to write the build tree, and an install
# writes nothing there.
if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
  set(stage_parent "$ENV{TMPDIR}")
else()
  set(stage_parent "/tmp")
endif()
string(RANDOM LENGTH 12 stage_suffix)
set(stage "${stage_parent}/gportd-units-${stage_suffix}")
file(MAKE_DIRECTORY "${stage}")
set(units "")
foreach(unit gportd.service gportd.socket gportd@.service gportd@.socket gport-mavlink.service
             gport-mavlink@.service gport-web.service)
  configure_file("${GPORT_SRC_DIR}/units/${unit}.in" "${stage}/${unit}" @ONLY)
  list(APPEND units "${stage}/${unit}")
endforeach()

# file(INSTALL) prefixes DESTDIR, prints and records in install_manifest.txt
# like install() does.
file(INSTALL DESTINATION "${unitdir}" TYPE FILE FILES ${units})
file(REMOVE_RECURSE "${stage}")
file(INSTALL DESTINATION "${sysusersdir}" TYPE FILE
     FILES "${GPORT_SRC_DIR}/sysusers/gportd.conf" "${GPORT_SRC_DIR}/sysusers/gport-mavlink.conf"
           "${GPORT_SRC_DIR}/sysusers/gport-web.conf")
file(INSTALL DESTINATION "${rulesdir}" TYPE FILE
     FILES "${GPORT_SRC_DIR}/udev/60-gportd.rules")
