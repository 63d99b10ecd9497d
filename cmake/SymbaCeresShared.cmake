# SYMBA_CERES_FOR_SHARED: what the shared symba library links for Ceres.
#
# Debian's libceres-dev exports Ceres::ceres as the static libceres.a with a
# link interface that names its build machine's BLAS (libf77blas, libatlas),
# so a shared library or program linked with it carries a private copy of
# Ceres and depends on ATLAS. When the shared libceres.so.3 is beside it,
# the shared symba links that instead, through the imported target
# symba::ceres_shared (Ceres's include directories and compile definitions,
# its libceres.so.3, glog and Eigen); symbaConfig.cmake re-creates the
# target for consumers from the same file name. Otherwise Ceres::ceres.
get_target_property(symba_ceres_location Ceres::ceres IMPORTED_LOCATION_RELEASE)
if(NOT symba_ceres_location)
  get_target_property(symba_ceres_location Ceres::ceres IMPORTED_LOCATION)
endif()
set(SYMBA_CERES_SHARED_NAME "")
if(symba_ceres_location MATCHES "\\.a$")
  get_filename_component(symba_ceres_dir "${symba_ceres_location}" DIRECTORY)
  file(GLOB symba_ceres_shared "${symba_ceres_dir}/libceres.so.[0-9]*")
  foreach(candidate IN LISTS symba_ceres_shared)
    get_filename_component(name "${candidate}" NAME)
    if(name MATCHES "^libceres\\.so\\.[0-9]+$")  # the soname link
      set(SYMBA_CERES_SHARED_NAME ${name})
      set(SYMBA_CERES_SHARED_LIBRARY ${candidate})
    endif()
  endforeach()
endif()

if(SYMBA_CERES_SHARED_NAME)
  add_library(symba::ceres_shared SHARED IMPORTED)
  get_target_property(symba_ceres_includes Ceres::ceres INTERFACE_INCLUDE_DIRECTORIES)
  get_target_property(symba_ceres_definitions Ceres::ceres INTERFACE_COMPILE_DEFINITIONS)
  set_target_properties(symba::ceres_shared PROPERTIES
    IMPORTED_LOCATION ${SYMBA_CERES_SHARED_LIBRARY}
    IMPORTED_SONAME ${SYMBA_CERES_SHARED_NAME}
    INTERFACE_INCLUDE_DIRECTORIES "${symba_ceres_includes}"
    INTERFACE_LINK_LIBRARIES "glog::glog;Eigen3::Eigen")
  if(symba_ceres_definitions)
    set_target_properties(symba::ceres_shared PROPERTIES
      INTERFACE_COMPILE_DEFINITIONS "${symba_ceres_definitions}")
  endif()
  set(SYMBA_CERES_FOR_SHARED symba::ceres_shared)
  if(NOT symba_FIND_QUIETLY)
    message(STATUS "symba: the shared library links ${SYMBA_CERES_SHARED_LIBRARY}")
  endif()
else()
  set(SYMBA_CERES_FOR_SHARED Ceres::ceres)
endif()
