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

if(EXPECT STREQUAL "frictions")
  # A user's files as they come: the trajectory in nanoseconds with commas,
  # the detections 2 ms off the frames, an object never detected. The
  # import converts and matches (--time-tolerance), says so on stderr, and
  # writes what the seconds files give.
  file(STRINGS ${SEQ}/orbslam3_T_wc.txt rows LIMIT_COUNT 10)
  set(ns "")
  set(late "")
  foreach(row IN LISTS rows)
    # CMake's REGEX REPLACE repeats a ^ match, so the fields are captured.
    if(NOT row MATCHES "^0\\.([0-9])[0-9]* (.*)$")
      message(FATAL_ERROR "unexpected row of ${SEQ}/orbslam3_T_wc.txt: ${row}")
    endif()
    set(pose "${CMAKE_MATCH_2}")
    set(tenth "${CMAKE_MATCH_1}")
    string(REPLACE " " "," comma_pose "${pose}")
    string(APPEND ns "1700000000${tenth}00000000,${comma_pose}\n")
    string(APPEND late "1700000000.${tenth}02 ${pose}\n")
  endforeach()
  file(WRITE ${WORK_DIR}/fe.csv "${ns}")
  file(WRITE ${WORK_DIR}/late.txt "${late}")
  file(WRITE ${WORK_DIR}/never.txt "")
  execute_process(COMMAND ${SYMBA} import tum --trajectory ${WORK_DIR}/fe.csv
      --object late=${WORK_DIR}/late.txt --object never=${WORK_DIR}/never.txt
      --stride 5 --time-tolerance 0.005 --out ${out}
    RESULT_VARIABLE rc ERROR_VARIABLE stderr)
  set(expected "symba import tum: warning: ${WORK_DIR}/never.txt: no detection (no data line): the object is never seen
symba import tum: note: ${WORK_DIR}/fe.csv: timestamps read as nanoseconds (the first is 1700000000000000000), converted to seconds
symba import tum: wrote ${out}: 2 keyframes, 2 detections\n")
  if(NOT rc EQUAL 0 OR NOT stderr STREQUAL expected)
    message(FATAL_ERROR "exit ${rc}, stderr '${stderr}', expected '${expected}'")
  endif()
  file(REMOVE ${out})
  # Without the tolerance the late rows are at no frame: exit 1, no log.
  execute_process(COMMAND ${SYMBA} import tum --trajectory ${WORK_DIR}/fe.csv
      --object late=${WORK_DIR}/late.txt --out ${out}
    RESULT_VARIABLE rc ERROR_VARIABLE stderr)
  if(rc EQUAL 0 OR NOT stderr MATCHES "late.txt:1: timestamp 1700000000.002 is not the time of any frame")
    message(FATAL_ERROR "exit ${rc}, stderr '${stderr}'")
  endif()
  if(EXISTS ${out})
    message(FATAL_ERROR "a failed import wrote ${out}")
  endif()
  return()
endif()
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
