# The last install step. After it CMake writes install_manifest.txt into the
# build tree (a path its generated cmake_install.cmake fixes). Whoever cannot
# write the build tree — a user installing a tree root built, or a tree
# mounted read-only — would see every file installed and then the install
# fail on that one write. Nothing else an install does writes into the build
# tree (the units are staged in a temporary directory), so when the build
# tree is not writable the manifest goes beside what was installed,
# <prefix>/share/gportd/install_manifest.txt, and the install succeeds.
# docs/operations.md, "Installing from source".
install(CODE "set(_gport_build_dir \"${CMAKE_BINARY_DIR}\")")
install(CODE [[
  execute_process(COMMAND test -w "${_gport_build_dir}" RESULT_VARIABLE _gport_writable)
  if(NOT _gport_writable EQUAL 0)
    set(_gport_manifest_dir "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/share/gportd")
    # CMake's own last step is file(WRITE <build tree>/install_manifest*.txt
    # ...): this function stands in for file() for that step only (the
    # script ends after it), and passes every other use to the original.
    function(file mode)
      get_filename_component(_dir "${ARGV1}" DIRECTORY)
      get_filename_component(_name "${ARGV1}" NAME)
      if(mode STREQUAL "WRITE" AND _dir STREQUAL _gport_build_dir
         AND _name MATCHES "^install_manifest.*\\.txt$")
        _file(MAKE_DIRECTORY "${_gport_manifest_dir}")
        _file(WRITE "${_gport_manifest_dir}/${_name}" "${ARGV2}")
        message(STATUS "The build tree is not writable: the install manifest is "
                       "${_gport_manifest_dir}/${_name}")
      else()
        _file(${ARGV})
      endif()
    endfunction()
  endif()
]])
