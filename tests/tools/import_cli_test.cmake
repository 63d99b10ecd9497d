cmake_minimum_required(VERSION 3.16)
# Runs `symba import tum` as a user would on a real sequence (SEQ, a
# directory of data/real/ycbv). EXPECT unset: both DOPE files, ground-truth
# first pose; the log must have EXPECT_KEYFRAMES keyframe lines and
# EXPECT_DETECTIONS detections. EXPECT=failure: line 7 of a copy of the
# cracker box file is cut short; the command must exit non-zero with
# "FILE:7:" and leave no file besides the input.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(out ${WORK_DIR}/log.jsonl)

# Fails unless WORK_DIR holds exactly the file `name`.
function(expect_only name)
  file(GLOB entries RELATIVE ${WORK_DIR} ${WORK_DIR}/* ${WORK_DIR}/.*)
  if(NOT entries STREQUAL name)
    message(FATAL_ERROR "files besides ${name}: ${entries}")
  endif()
endfunction()

if(EXPECT STREQUAL "failure")
  file(STRINGS ${SEQ}/dope_003_cracker_box_T_co.txt rows)
  list(GET rows 6 row)
  string(REGEX REPLACE " [^ ]+$" "" cut "${row}")
  list(REMOVE_AT rows 6)
  list(INSERT rows 6 "${cut}")
  string(REPLACE ";" "\n" text "${rows}")
  set(box ${WORK_DIR}/box.txt)
  file(WRITE ${box} "${text}\n")
  execute_process(COMMAND ${SYMBA} import tum
      --trajectory ${SEQ}/orbslam3_T_wc.txt --object 003_cracker_box=${box}
      --out ${out}
    RESULT_VARIABLE rc ERROR_VARIABLE stderr)
  if(rc EQUAL 0)
    message(FATAL_ERROR "expected a failure, got exit 0")
  endif()
  set(expected "symba import tum: ${box}:7: expected 8 numbers (timestamp tx ty tz qx qy qz qw), found 7\n")
  if(NOT stderr STREQUAL expected)
    message(FATAL_ERROR "stderr is '${stderr}', expected '${expected}'")
  endif()
  expect_only("box.txt")
  return()
endif()
execute_process(COMMAND ${SYMBA} import tum
    --trajectory ${SEQ}/orbslam3_T_wc.txt
    --object 003_cracker_box=${SEQ}/dope_003_cracker_box_T_co.txt
    --object 004_sugar_box=${SEQ}/dope_004_sugar_box_T_co.txt
    --first-pose ${SEQ}/gt_T_wc.txt --out ${out}
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "expected success, got exit ${rc}: ${stderr}")
endif()
file(STRINGS ${out} lines)
list(LENGTH lines n)
math(EXPR keyframes "${n} - 1")
if(NOT keyframes EQUAL EXPECT_KEYFRAMES)
  message(FATAL_ERROR "${keyframes} keyframes, expected ${EXPECT_KEYFRAMES}")
endif()
file(READ ${out} text)
string(REGEX MATCHALL "\"class\":" classes "${text}")
list(LENGTH classes detections)
if(NOT detections EQUAL EXPECT_DETECTIONS)
  message(FATAL_ERROR "${detections} detections, expected ${EXPECT_DETECTIONS}")
endif()
list(GET lines 1 first)
if(NOT first MATCHES "^{\"keyframe\":0,\"t\":0.0,\"T_wc\":{\"t\":\\[-0.174718,-0.77447,0.750517\\]")
  message(FATAL_ERROR "the first keyframe is not at the ground truth's first pose: ${first}")
endif()
expect_only("log.jsonl")
