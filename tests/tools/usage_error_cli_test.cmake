cmake_minimum_required(VERSION 3.16)
# Runs `symba replay` on a valid log with one bad flag and checks that the bad
# flag alone makes it fail: CLI11's usage exit status, the flag named in the
# message, and no output directory.
# Inputs: SYMBA (the binary), LOG (a valid log), WORK_DIR, FLAGS (a ;-list,
# the bad flag and its value), EXPECT_RC (exit status), EXPECT_MESSAGE (a
# substring of stderr).
if(NOT EXISTS ${LOG})
  # Otherwise the missing log, not the flag, could be what fails.
  message(FATAL_ERROR "the log ${LOG} does not exist")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(out ${WORK_DIR}/out)
execute_process(COMMAND ${SYMBA} replay ${LOG} --out ${out} --quiet ${FLAGS}
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc STREQUAL EXPECT_RC)
  message(FATAL_ERROR
    "expected exit ${EXPECT_RC}, got ${rc}: ${stdout}${stderr}")
endif()
string(FIND "${stderr}" "${EXPECT_MESSAGE}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "stderr lacks '${EXPECT_MESSAGE}': ${stderr}")
endif()
if(EXISTS ${out})
  message(FATAL_ERROR "a usage error wrote ${out}")
endif()
