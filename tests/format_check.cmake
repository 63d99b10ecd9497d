cmake_minimum_required(VERSION 3.16)
# Fails when any C++ file of the project is not clang-format clean.
# Inputs: CLANG_FORMAT, SOURCE_DIR.
file(GLOB_RECURSE files
  ${SOURCE_DIR}/include/*.h
  ${SOURCE_DIR}/src/*.h ${SOURCE_DIR}/src/*.cc
  ${SOURCE_DIR}/tests/*.h ${SOURCE_DIR}/tests/*.cc
  ${SOURCE_DIR}/benchmarks/*.h ${SOURCE_DIR}/benchmarks/*.cc
  ${SOURCE_DIR}/python/*.h ${SOURCE_DIR}/python/*.cc)
execute_process(
  COMMAND ${CLANG_FORMAT} --dry-run --Werror --style=file ${files}
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "clang-format finds unformatted code (fix with "
    "clang-format -i):\n${err}")
endif()
