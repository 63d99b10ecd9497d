cmake_minimum_required(VERSION 3.16)
# Stages an install of the symba build tree, builds the consumer project
# against it with find_package(symba CONFIG REQUIRED) and runs it; then the
# same against the build tree itself (symba_DIR=<build>).
# Inputs: SYMBA_BUILD_DIR, CONSUMER_SOURCE_DIR, WORK_DIR, BUILD_TYPE.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()

if(NOT BUILD_TYPE)
  set(BUILD_TYPE RelWithDebInfo)
endif()
run_step(${CMAKE_COMMAND} --install ${SYMBA_BUILD_DIR} --prefix ${prefix} --config ${BUILD_TYPE})
run_step(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step(${WORK_DIR}/build/symba_consumer)
message(STATUS "consumer built against ${prefix} and ran")

run_step(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build_tree
  -Dsymba_DIR=${SYMBA_BUILD_DIR} -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build_tree)
run_step(${WORK_DIR}/build_tree/symba_consumer)
message(STATUS "consumer built against the build tree ${SYMBA_BUILD_DIR} and ran")
