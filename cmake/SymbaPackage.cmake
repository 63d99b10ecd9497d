# The Debian package (cpack -G DEB in a build tree): the library, its
# headers, the CMake package, the `symba` command and, when it is built, the
# Python module. Debian runtime dependencies of the command and the module
# come from dpkg-shlibdeps; a consumer of the static library and headers
# also needs the -dev packages that symbaConfig.cmake finds.
set(CPACK_PACKAGE_NAME symba)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "Object-SLAM backend for symmetric objects (library, headers, CMake package, command)")
set(CPACK_PACKAGE_CONTACT "symba developers")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(symba_deb_depends "libceres-dev (>= 2.1)" "libeigen3-dev (>= 3.4)")
if(SYMBA_PYTHON_ENABLED)
  list(APPEND symba_deb_depends python3 python3-numpy)
endif()
string(REPLACE ";" ", " CPACK_DEBIAN_PACKAGE_DEPENDS "${symba_deb_depends}")
# The command and the Python module are stripped; the static library keeps
# its symbols (strip does not touch archives installed by CMake).
set(CPACK_STRIP_FILES ON)
set(CPACK_GENERATOR DEB)
include(CPack)

# A RelWithDebInfo archive is mostly debug information (over 300 MB): a
# stripping install (cpack with CPACK_STRIP_FILES) drops it and keeps the
# symbols, so the archive still links.
install(CODE "
  if(CMAKE_INSTALL_DO_STRIP AND NOT \"${CMAKE_STRIP}\" STREQUAL \"\")
    execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug
      \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:symba>\"
      RESULT_VARIABLE strip_result)
    if(NOT strip_result EQUAL 0)
      message(FATAL_ERROR \"strip --strip-debug failed on the symba archive\")
    endif()
  endif()")
