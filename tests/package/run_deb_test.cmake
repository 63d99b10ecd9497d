cmake_minimum_required(VERSION 3.16)
# Builds the Debian package of the symba build tree with cpack -G DEB,
# extracts it into a scratch root (dpkg-deb -x: no installation), checks
# its control fields and contents, builds the consumer project against the
# extracted tree with find_package(symba CONFIG REQUIRED) and runs it, runs
# the extracted `symba` command and, when PYTHON is given, imports the
# extracted Python module.
# Inputs: CPACK, DPKG_DEB, SYMBA_BUILD_DIR, CONSUMER_SOURCE_DIR, WORK_DIR,
# BUILD_TYPE, PYTHON (optional).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
    ERROR_VARIABLE err WORKING_DIRECTORY ${WORK_DIR})
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

run_step(${CPACK} -G DEB --config ${SYMBA_BUILD_DIR}/CPackConfig.cmake
  -B ${WORK_DIR}/cpack)
file(GLOB debs ${WORK_DIR}/cpack/symba_*.deb)
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one symba_*.deb, found: ${debs}")
endif()

run_step(${DPKG_DEB} --field ${debs} Package Depends)
foreach(expected "Package: symba" "libceres-dev" "libeigen3-dev"
    "libgoogle-glog")
  string(FIND "${step_output}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "control fields lack '${expected}':\n${step_output}")
  endif()
endforeach()

set(root ${WORK_DIR}/root)
run_step(${DPKG_DEB} -x ${debs} ${root})
foreach(file bin/symba lib/libsymba.a lib/cmake/symba/symbaConfig.cmake
    include/symba/backend/backend.h)
  if(NOT EXISTS ${root}/usr/${file})
    message(FATAL_ERROR "the package lacks /usr/${file}")
  endif()
endforeach()

if(NOT BUILD_TYPE)
  set(BUILD_TYPE RelWithDebInfo)
endif()
run_step(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${root}/usr -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step(${WORK_DIR}/build/symba_consumer)
run_step(${root}/usr/bin/symba simulate --help)

if(PYTHON)
  set(ENV{PYTHONPATH} ${root}/usr/lib/python3/dist-packages)
  # Newlines, not semicolons: a semicolon would split the CMake list.
  run_step(${PYTHON} -c
    "import symba\nprint(symba.__file__)\nprint(symba.categorize([[0,0,1,0,0,0,1]]).type)")
  if(NOT step_output MATCHES "^${root}/usr/lib/python3/dist-packages/symba/__init__.py\nasymmetric\n$")
    message(FATAL_ERROR "the extracted Python module: ${step_output}")
  endif()
endif()
message(STATUS "the Debian package built, extracted, consumed and ran")
