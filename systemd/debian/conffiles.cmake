# Run by CPack (CPACK_PRE_BUILD_SCRIPTS) after it staged the install tree and
# before it builds the package: every file staged under /etc becomes a Debian
# conffile, so dpkg keeps the administrator's edits across upgrades.
file(GLOB_RECURSE gport_etc_files LIST_DIRECTORIES false
     RELATIVE "${CPACK_TEMPORARY_INSTALL_DIRECTORY}" "${CPACK_TEMPORARY_INSTALL_DIRECTORY}/etc/*")
list(SORT gport_etc_files)
set(gport_conffiles "")
foreach(file IN LISTS gport_etc_files)
  string(APPEND gport_conffiles "/${file}\n")
endforeach()
file(WRITE "${CPACK_GPORT_CONFFILES}" "${gport_conffiles}")
