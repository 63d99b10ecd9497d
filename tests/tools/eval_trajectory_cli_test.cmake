cmake_minimum_required(VERSION 3.19)
# `symba eval --gt-trajectory` on a vendored real sequence gives the numbers
# symba-real-bench gives for the same replay (docs/evaluation.md):
#   camera ATE and front-end ATE (--align first) to 1e-6 m, and the object
#   position errors of the ground-truth object list to 1e-6 m;
# --align none gives the same ATE (the log starts at the ground truth's
# first pose); a ground truth at half the rate matches every other keyframe
# and one with commas the same ATE; bad input exits 1 with
# the file and line named and no --json written.
# Inputs: SYMBA, REAL_BENCH (the binaries), DATA (data/real/ycbv), SEQUENCE,
# GT_OBJECTS, WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(seq ${DATA}/${SEQUENCE})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
    ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# A JSON number below 1 in whole nanometres (the first 9 decimals).
function(to_nanometres value out)
  if(NOT value MATCHES "^0\\.([0-9]+)$")
    message(FATAL_ERROR "not a number in [0, 1) without exponent: ${value}")
  endif()
  string(SUBSTRING "${CMAKE_MATCH_1}000000000" 0 9 digits)
  string(REGEX REPLACE "^0+" "" digits "${digits}")
  if(digits STREQUAL "")
    set(digits 0)
  endif()
  set(${out} ${digits} PARENT_SCOPE)
endfunction()

function(expect_equal_to_a_micrometre what a b)
  to_nanometres(${a} na)
  to_nanometres(${b} nb)
  math(EXPR diff "${na} - ${nb}")
  if(diff GREATER 1000 OR diff LESS -1000)
    message(FATAL_ERROR "${what}: ${a} and ${b} differ by more than 1e-6")
  endif()
  message(STATUS "${what}: ${a} = ${b}")
endfunction()

run(${REAL_BENCH} --data ${DATA} --sequences ${SEQUENCE} --methods symba
  --out-dir ${WORK_DIR}/real --json ${WORK_DIR}/real.json --quiet)
file(READ ${WORK_DIR}/real.json bench)
string(JSON bench_ate GET "${bench}" sequences 0 methods symba ate)
string(JSON bench_fe_ate GET "${bench}" sequences 0 front_end_ate)
set(result ${WORK_DIR}/real/${SEQUENCE}/symba)

run(${SYMBA} eval --gt-trajectory ${seq}/gt_T_wc.txt --result ${result}
  --frontend ${seq}/orbslam3_T_wc.txt --gt-objects ${GT_OBJECTS}
  --json ${WORK_DIR}/eval.json)
if(NOT run_output MATCHES "\nATE result / front end: [0-9]+\\.[0-9][0-9][0-9]\n")
  message(FATAL_ERROR "the report lacks the ATE ratio:\n${run_output}")
endif()
file(READ ${WORK_DIR}/eval.json eval)
string(JSON ate GET "${eval}" camera ate)
string(JSON fe_ate GET "${eval}" frontend_camera ate)
string(JSON matched GET "${eval}" camera matched)
expect_equal_to_a_micrometre("camera ATE" ${ate} ${bench_ate})
expect_equal_to_a_micrometre("front-end ATE" ${fe_ate} ${bench_fe_ate})
foreach(i 0 1)
  string(JSON bench_error GET "${bench}" sequences 0 methods symba object_errors ${i})
  string(JSON error GET "${eval}" objects ${i} position_error)
  expect_equal_to_a_micrometre("object ${i} position error" ${error} ${bench_error})
endforeach()

run(${SYMBA} eval --gt-trajectory ${seq}/gt_T_wc.txt --result ${result}
  --align none --json ${WORK_DIR}/none.json)
file(READ ${WORK_DIR}/none.json none)
string(JSON none_ate GET "${none}" camera ate)
expect_equal_to_a_micrometre("camera ATE, --align none" ${none_ate} ${bench_ate})

# The ground truth at half the rate (frames 0, 2, 4, ...): keyframes 0, 10,
# 20, ... have a pose at their time, keyframes 5, 15, ... none within 0.02 s.
# The same with commas: the same ATE.
file(STRINGS ${seq}/gt_T_wc.txt rows)
set(half "")
set(comma "")
set(i 0)
foreach(row IN LISTS rows)
  math(EXPR odd "${i} % 2")
  if(odd EQUAL 0)
    string(APPEND half "${row}\n")
  endif()
  string(REPLACE " " ", " fields "${row}")
  string(APPEND comma "${fields}\n")
  math(EXPR i "${i} + 1")
endforeach()
file(WRITE ${WORK_DIR}/gt_half.txt "${half}")
file(WRITE ${WORK_DIR}/gt_comma.csv "${comma}")
run(${SYMBA} eval --gt-trajectory ${WORK_DIR}/gt_half.txt --result ${result}
  --json ${WORK_DIR}/half.json)
file(READ ${WORK_DIR}/half.json half_json)
string(JSON half_matched GET "${half_json}" camera matched)
if(NOT matched EQUAL 223 OR NOT half_matched EQUAL 112)
  message(FATAL_ERROR "matched keyframes ${matched} and ${half_matched}, expected 223 and 112")
endif()
run(${SYMBA} eval --gt-trajectory ${WORK_DIR}/gt_comma.csv --result ${result}
  --json ${WORK_DIR}/comma.json)
file(READ ${WORK_DIR}/comma.json comma_json)
string(JSON comma_ate GET "${comma_json}" camera ate)
expect_equal_to_a_micrometre("camera ATE, commas" ${comma_ate} ${bench_ate})

# Bad input: exit 1, the file and line named, no --json.
file(WRITE ${WORK_DIR}/objects.txt "003_cracker_box 0 0 0 0 0 0\n")
execute_process(COMMAND ${SYMBA} eval --gt-trajectory ${seq}/gt_T_wc.txt
    --result ${result} --gt-objects ${WORK_DIR}/objects.txt
    --json ${WORK_DIR}/bad.json
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(expected "symba eval: ${WORK_DIR}/objects.txt:1: expected a class and 7 numbers (CLASS tx ty tz qx qy qz qw), found 7 fields\n")
if(NOT rc EQUAL 1 OR NOT err STREQUAL expected OR NOT out STREQUAL ""
   OR EXISTS ${WORK_DIR}/bad.json)
  message(FATAL_ERROR "bad objects: exit ${rc}, stdout '${out}', stderr '${err}'")
endif()
execute_process(COMMAND ${SYMBA} eval --result ${result}
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err STREQUAL "symba eval: give the ground truth as --gt DIR or --gt-trajectory FILE\n")
  message(FATAL_ERROR "no ground truth: exit ${rc}, stderr '${err}'")
endif()
