cmake_minimum_required(VERSION 3.16)
# `symba replay` ends as `symba import` does: one line on stderr naming the
# output directory, the keyframes, detections and map objects replayed and
# the wall time; nothing on stdout. --quiet leaves stderr empty.
# Inputs: SYMBA (the binary), LOG (tests/data/replay/table.jsonl), WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(out ${WORK_DIR}/out)

execute_process(COMMAND ${SYMBA} replay ${LOG} --out ${out} --confirm-keyframes 1
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "expected success, got exit ${rc}: ${stderr}")
endif()
if(NOT stdout STREQUAL "")
  message(FATAL_ERROR "stdout is not empty: '${stdout}'")
endif()
# The four keyframes of table.jsonl, one detection each, all of one object.
set(expected "^symba replay: wrote ${out}: 4 keyframes, 4 detections, 1 map object in [0-9]+\\.[0-9][0-9] s\n$")
if(NOT stderr MATCHES "${expected}")
  message(FATAL_ERROR "stderr is '${stderr}', expected a match of '${expected}'")
endif()

execute_process(COMMAND ${SYMBA} replay ${LOG} --out ${out} --quiet
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0 OR NOT stderr STREQUAL "" OR NOT stdout STREQUAL "")
  message(FATAL_ERROR "--quiet: exit ${rc}, stdout '${stdout}', stderr '${stderr}'")
endif()
