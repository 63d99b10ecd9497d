# Install rules and the exported CMake package:
#   find_package(symba CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE symba::symba)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS symba
  EXPORT symbaTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/symba DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The command-line tool, as `symba`.
install(TARGETS symba_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

set(SYMBA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/symba)
install(EXPORT symbaTargets
  NAMESPACE symba::
  DESTINATION ${SYMBA_CMAKE_DIR})
configure_package_config_file(cmake/symbaConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfig.cmake
  INSTALL_DESTINATION ${SYMBA_CMAKE_DIR})
write_basic_package_version_file(
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/symbaConfigVersion.cmake
  DESTINATION ${SYMBA_CMAKE_DIR})
