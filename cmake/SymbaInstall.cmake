# Install rules and the exported CMake package:
#   find_package(symba CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE symba::core)    # the backend (shared)
#   target_link_libraries(app PRIVATE symba::tools)   # and the tools
#   target_link_libraries(app PRIVATE symba::core_static)  # static variants:
#   target_link_libraries(app PRIVATE symba::tools_static) # core_static, tools_static
# symba::symba (shared) and symba::symba_static stand for both libraries.
# The build tree is a package as well: symba_DIR=<build>.
#
# Every file belongs to one component, the unit of a Debian package
# (cmake/SymbaPackage.cmake):
#   library      libsymba.so.X.Y, libsymba_tools.so.X.Y     -> libsymbaX.Y
#   development  headers, the .so links, the .a, CMake      -> libsymba-dev
#   cli          bin/symba                                 -> symba
#   python       the Python package (python/CMakeLists.txt) -> python3-symba
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS symba_core symba_tools
  EXPORT symbaTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    COMPONENT library
    NAMELINK_COMPONENT development
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT library
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS symba_core_static symba_tools_static symba_all_shared symba_all_static
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

# The build tree as a package (find_package(symba) with symba_DIR=<build>):
# the same config beside the build tree's own targets file.
export(EXPORT symbaTargets NAMESPACE symba::
  FILE ${CMAKE_CURRENT_BINARY_DIR}/symbaTargets.cmake)
configure_file(cmake/SymbaCeresShared.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/SymbaCeresShared.cmake COPYONLY)
