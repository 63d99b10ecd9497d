# Install rules and the exported CMake package:
#   find_package(symba CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE symba::symba)          # the shared library
#   target_link_libraries(app PRIVATE symba::symba_static)   # or the static one
#
# Every file belongs to one component, the unit of a Debian package
# (cmake/SymbaPackage.cmake):
#   library      libsymba.so.MAJOR.MINOR(.PATCH)           -> libsymbaMAJOR.MINOR
#   development  headers, libsymba.so, libsymba.a, CMake   -> libsymba-dev
#   cli          bin/symba                                 -> symba
#   python       the Python package (python/CMakeLists.txt) -> python3-symba
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS symba_shared
  EXPORT symbaTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    COMPONENT library
    NAMELINK_COMPONENT development
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT library
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS symba
  EXPORT symbaTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/symba DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  COMPONENT development)
# The command-line tool, as `symba`.
install(TARGETS symba_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  COMPONENT cli)

set(SYMBA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/symba)
install(EXPORT symbaTargets
  NAMESPACE symba::
  DESTINATION ${SYMBA_CMAKE_DIR}
  COMPONENT development)
configure_package_config_file(cmake/symbaConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfig.cmake
  INSTALL_DESTINATION ${SYMBA_CMAKE_DIR})
write_basic_package_version_file(
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfigVersion.cmake
  cmake/SymbaCeresShared.cmake
  DESTINATION ${SYMBA_CMAKE_DIR}
  COMPONENT development)
