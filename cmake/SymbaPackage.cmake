# The Debian packages (cpack -G DEB in a build tree), split as Debian splits
# a library (one package per install component, cmake/SymbaInstall.cmake):
#   libsymbaX.Y     the shared libraries libsymba.so.X.Y (symba::core) and
#                   libsymba_tools.so.X.Y (symba::tools); X.Y: their soname
#   libsymba-dev    headers, the .so links, the .a, the CMake package;
#                   depends on libsymbaX.Y and the -dev packages that
#                   symbaConfig.cmake finds (Ceres, Eigen)
#   symba           the command `symba`
#   python3-symba   the Python module, for the build's Python X.Y only
# Runtime dependencies come from dpkg-shlibdeps on what each package holds
# (the shared Ceres, glog, the C++ runtime); the library and the programs
# are linked --as-needed, so the BLAS that Debian's Ceres build names is not
# a dependency. Each package has /usr/share/doc/PACKAGE/copyright.
set(symba_soversion ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
set(symba_deb_library libsymba${symba_soversion})
set(symba_deb_exact "(= ${PROJECT_VERSION})")

set(CPACK_PACKAGE_NAME symba)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "symba developers")
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The programs need libsymba(_tools).so.X.Y, which are in the build tree, not yet in
# a package: dpkg-shlibdeps finds it here and the Depends below name it.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${PROJECT_BINARY_DIR}/lib)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
set(CPACK_STRIP_FILES ON)
set(CPACK_GENERATOR DEB)

set(symba_deb_components library development cli)
if(SYMBA_PYTHON_ENABLED)
  list(APPEND symba_deb_components python)
endif()
set(CPACK_COMPONENTS_ALL ${symba_deb_components})

set(CPACK_DEBIAN_LIBRARY_PACKAGE_NAME ${symba_deb_library})
set(CPACK_DEBIAN_LIBRARY_PACKAGE_SECTION libs)
set(CPACK_COMPONENT_LIBRARY_DESCRIPTION
  "object-SLAM backend for symmetric objects - shared library
symba categorises each multi-hypothesis object detection as asymmetric,
discrete- or continuous-symmetric and jointly optimises cameras, objects
and points with Ceres max-mixture costs. This package holds the shared
libraries libsymba.so.${symba_soversion} (the backend) and
libsymba_tools.so.${symba_soversion} (simulation, import, export,
evaluation, replay).")

set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libsymba-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS
  "${symba_deb_library} ${symba_deb_exact}, libceres-dev (>= 2.1), libeigen3-dev (>= 3.4)")
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION
  "object-SLAM backend for symmetric objects - development files
The C++17 headers (include/symba), the libraries libsymba and
libsymba_tools (.so links and .a), and the CMake package: find_package(symba)
gives symba::core and symba::tools (shared), symba::core_static and
symba::tools_static, and symba::symba / symba::symba_static for both.")

set(CPACK_DEBIAN_CLI_PACKAGE_NAME symba)
set(CPACK_DEBIAN_CLI_PACKAGE_SECTION science)
set(CPACK_DEBIAN_CLI_PACKAGE_DEPENDS "${symba_deb_library} ${symba_deb_exact}")
set(CPACK_COMPONENT_CLI_DESCRIPTION
  "object-SLAM backend for symmetric objects - command-line tool
The command symba: import TUM or BOP files into a log (symba import),
replay a log through the backend (symba replay), evaluate against ground
truth (symba eval), simulate scenes (symba simulate) and export BOP files
(symba export).")

if(SYMBA_PYTHON_ENABLED)
  # The module is built for one Python X.Y (its file name says so).
  set(symba_py ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR})
  math(EXPR symba_py_next "${Python3_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-symba)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
    "${symba_deb_library} ${symba_deb_exact}, python3 (>= ${symba_py}), python3 (<< ${Python3_VERSION_MAJOR}.${symba_py_next}), python3-numpy")
  set(CPACK_COMPONENT_PYTHON_DESCRIPTION
    "object-SLAM backend for symmetric objects - Python ${symba_py} module
The Python module symba (import symba): the backend, categorisation, logs,
replay, the importers and the simulator, with NumPy arrays.")
endif()

include(CPack)

# Each package's copyright file.
foreach(component ${symba_deb_components})
  string(TOUPPER ${component} upper)
  install(FILES cmake/debian/copyright
    DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${CPACK_DEBIAN_${upper}_PACKAGE_NAME}
    COMPONENT ${component})
endforeach()

# A RelWithDebInfo archive is mostly debug information (over 300 MB): a
# stripping install (cpack with CPACK_STRIP_FILES) drops it and keeps the
# symbols, so the archives still link.
foreach(archive symba_core_static symba_tools_static)
  install(CODE "
    if(CMAKE_INSTALL_DO_STRIP AND NOT \"${CMAKE_STRIP}\" STREQUAL \"\")
      execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug
        \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:${archive}>\"
        RESULT_VARIABLE strip_result)
      if(NOT strip_result EQUAL 0)
        message(FATAL_ERROR \"strip --strip-debug failed on $<TARGET_FILE_NAME:${archive}>\")
      endif()
    endif()"
    COMPONENT development)
endforeach()
