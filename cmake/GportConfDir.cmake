# gport_confdir(<out> <prefix> <sysconfdir> <forced>): gportd's configuration
# directory for an install prefix, decided at *install* time (included from
# install(CODE), so `cmake --install --prefix X` and CPack's /usr both count):
#   <forced> set  -> it (GPORT_CONFIG_DIR, absolute);
#   prefix /usr   -> /etc/gportd (also prefix /);
#   /opt/NAME     -> /etc/opt/NAME/gportd;
#   other prefix  -> <prefix>/etc/gportd,
# which is GNUInstallDirs' CMAKE_INSTALL_FULL_SYSCONFDIR for that prefix, plus
# gportd. gportd itself derives the same directory from where it runs
# (config/src/default_path.cpp), so both must change together.
function(gport_confdir out prefix sysconfdir forced)
  if(NOT forced STREQUAL "")
    set(dir "${forced}")
  elseif(IS_ABSOLUTE "${sysconfdir}")
    set(dir "${sysconfdir}/gportd")
  elseif(prefix STREQUAL "/usr" OR prefix STREQUAL "/")
    set(dir "/${sysconfdir}/gportd")
  elseif(prefix MATCHES "^/opt/")
    set(dir "/${sysconfdir}${prefix}/gportd")
  else()
    set(dir "${prefix}/${sysconfdir}/gportd")
  endif()
  set(${out} "${dir}" PARENT_SCOPE)
endfunction()
