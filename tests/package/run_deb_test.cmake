cmake_minimum_required(VERSION 3.16)
# Builds the Debian packages of the symba build tree with cpack -G DEB
# (cmake/SymbaPackage.cmake): libsymbaX.Y, libsymba-dev, symba and, when
# PYTHON is given, python3-symba. Checks each package's control fields (its
# name, a description naming what is inside, the dependencies it needs and
# none it does not: no -dev package for the library, the command or the
# module, no BLAS of the build machine, the module bound to one Python X.Y)
# and its contents (its files, a copyright file). Then extracts them all
# into one scratch root (dpkg-deb -x: no installation) and, against that
# root only, runs the command on a log, imports the Python module and builds
# and runs the consumer project with find_package(symba CONFIG REQUIRED).
# Inputs: CPACK, DPKG_DEB, SYMBA_BUILD_DIR, CONSUMER_SOURCE_DIR, WORK_DIR,
# BUILD_TYPE, LIBDIR (the install's library directory), SOVERSION (X.Y),
# VERSION, LOG (a log v1 to replay), PYTHON and PYTHON_VERSION (X.Y;
# optional).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
    ERROR_VARIABLE err WORKING_DIRECTORY ${WORK_DIR})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
  set(step_error "${err}" PARENT_SCOPE)
endfunction()

function(expect_in text what)
  foreach(expected ${ARGN})
    string(FIND "${text}" "${expected}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "${what} lacks '${expected}':\n${text}")
    endif()
  endforeach()
endfunction()

function(expect_not_matching text what)
  foreach(pattern ${ARGN})
    if(text MATCHES "${pattern}")
      message(FATAL_ERROR "${what} matches '${pattern}':\n${text}")
    endif()
  endforeach()
endfunction()

run_step(${CPACK} -G DEB --config ${SYMBA_BUILD_DIR}/CPackConfig.cmake
  -B ${WORK_DIR}/cpack)

set(library libsymba${SOVERSION})
set(packages ${library} libsymba-dev symba)
if(PYTHON)
  list(APPEND packages python3-symba)
endif()
file(GLOB debs RELATIVE ${WORK_DIR}/cpack ${WORK_DIR}/cpack/*.deb)
list(LENGTH debs n)
list(LENGTH packages n_expected)
if(NOT n EQUAL n_expected)
  message(FATAL_ERROR "expected ${n_expected} packages (${packages}), found: ${debs}")
endif()

# Control fields, one package at a time: what it must depend on, and
# regular expressions its Depends must not match.
set(exact "${library} (= ${VERSION})")
set(never_depends "-dev" "atlas" "libf77blas" "liblapack")
foreach(package ${packages})
  file(GLOB deb ${WORK_DIR}/cpack/${package}_${VERSION}_*.deb)
  if(NOT deb)
    message(FATAL_ERROR "no package ${package}_${VERSION}_*.deb: ${debs}")
  endif()
  set(deb_${package} ${deb})
  run_step(${DPKG_DEB} --field ${deb} Package Depends Description)
  set(fields "${step_output}")
  expect_in("${fields}" "${package}" "Package: ${package}\n")
  run_step(${DPKG_DEB} --field ${deb} Depends)
  set(depends "${step_output}")
  run_step(${DPKG_DEB} -c ${deb})
  set(contents "${step_output}")
  expect_in("${contents}" "${package} contents" "./usr/share/doc/${package}/copyright")
  if(package STREQUAL library)
    expect_in("${depends}" "${package} Depends" "libceres3" "libgoogle-glog" "libstdc++6")
    expect_not_matching("${depends}" "${package} Depends" ${never_depends})
    expect_in("${fields}" "${package} fields" "shared library" "libsymba.so.${SOVERSION}")
    expect_in("${contents}" "${package} contents" "./usr/${LIBDIR}/libsymba.so.${SOVERSION}"
      "./usr/${LIBDIR}/libsymba_tools.so.${SOVERSION}")
    expect_not_matching("${contents}" "${package} contents" "include/" "libsymba(_tools)?\\.a" "bin/symba")
  elseif(package STREQUAL "libsymba-dev")
    expect_in("${depends}" "${package} Depends" "${exact}" "libceres-dev" "libeigen3-dev")
    expect_in("${fields}" "${package} fields" "headers" "CMake package")
    expect_in("${contents}" "${package} contents"
      "./usr/include/symba/backend/backend.h" "./usr/${LIBDIR}/libsymba.so "
      "./usr/${LIBDIR}/libsymba.a" "./usr/${LIBDIR}/libsymba_tools.so "
      "./usr/${LIBDIR}/libsymba_tools.a" "./usr/${LIBDIR}/cmake/symba/symbaConfig.cmake")
  elseif(package STREQUAL "symba")
    expect_in("${depends}" "${package} Depends" "${exact}" "libstdc++6")
    expect_not_matching("${depends}" "${package} Depends" ${never_depends})
    expect_in("${fields}" "${package} fields" "command" "symba replay")
    expect_in("${contents}" "${package} contents" "./usr/bin/symba")
    expect_not_matching("${contents}" "${package} contents" "include/" "libsymba")
  else()
    string(REPLACE "." ";" xy "${PYTHON_VERSION}")
    list(GET xy 0 major)
    list(GET xy 1 minor)
    math(EXPR next "${minor} + 1")
    expect_in("${depends}" "${package} Depends" "${exact}"
      "python3 (>= ${PYTHON_VERSION}), python3 (<< ${major}.${next})" "python3-numpy")
    expect_not_matching("${depends}" "${package} Depends" ${never_depends})
    expect_in("${fields}" "${package} fields" "Python ${PYTHON_VERSION} module")
    expect_in("${contents}" "${package} contents"
      "./usr/lib/python3/dist-packages/symba/__init__.py")
    expect_not_matching("${contents}" "${package} contents" "include/" "libsymba")
  endif()
  message(STATUS "${package}: ${depends}")
endforeach()

# Every package extracted into one root; nothing of the build tree is used
# from here on (the command and the module find libsymba in the root).
set(root ${WORK_DIR}/root)
foreach(package ${packages})
  run_step(${DPKG_DEB} -x ${deb_${package}} ${root})
endforeach()
set(ENV{LD_LIBRARY_PATH} ${root}/usr/${LIBDIR})

run_step(${root}/usr/bin/symba replay ${LOG} --out ${WORK_DIR}/replay)
if(NOT step_error MATCHES "^symba replay: wrote ${WORK_DIR}/replay: 4 keyframes, 4 detections")
  message(FATAL_ERROR "the extracted symba replay: ${step_error}")
endif()
run_step(ldd ${root}/usr/bin/symba)
expect_in("${step_output}" "ldd of the extracted symba" "${root}/usr/${LIBDIR}/libsymba.so.${SOVERSION}"
  "${root}/usr/${LIBDIR}/libsymba_tools.so.${SOVERSION}")

if(NOT BUILD_TYPE)
  set(BUILD_TYPE RelWithDebInfo)
endif()
run_step(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${root}/usr -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step(${WORK_DIR}/build/symba_consumer)
run_step(ldd ${WORK_DIR}/build/symba_consumer)
expect_in("${step_output}" "ldd of the consumer" "${root}/usr/${LIBDIR}/libsymba.so.${SOVERSION}")
# The consumer links symba::core alone.
expect_not_matching("${step_output}" "ldd of the consumer" "libsymba_tools")

if(PYTHON)
  set(ENV{PYTHONPATH} ${root}/usr/lib/python3/dist-packages)
  # Newlines, not semicolons: a semicolon would split the CMake list.
  run_step(${PYTHON} -c
    "import symba\nprint(symba.__file__)\nprint(symba.categorize([[0,0,1,0,0,0,1]]).type)")
  if(NOT step_output MATCHES "^${root}/usr/lib/python3/dist-packages/symba/__init__.py\nasymmetric\n$")
    message(FATAL_ERROR "the extracted Python module: ${step_output}")
  endif()
endif()
message(STATUS "the Debian packages built, extracted, consumed and ran")
