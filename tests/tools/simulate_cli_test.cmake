# Runs `symba simulate` as a user would: the three files appear, the ground
# truth has one trajectory line per keyframe and the documented JSON shape,
# and an unknown scene fails without leaving anything behind; --keyframes
# overrides the long scene's own default, and `symba replay` reads its log;
# --declare-noise false leaves the detections' sigmas out and nothing else.
# Inputs: SYMBA (the binary), WORK_DIR.
cmake_minimum_required(VERSION 3.16)  # quoted strings are not variables
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(out ${WORK_DIR}/out)
execute_process(COMMAND ${SYMBA} simulate --scene disc --out ${out} --seed 3
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "symba simulate failed (${rc}): ${stderr}")
endif()
foreach(name log.jsonl gt_trajectory.tum gt_objects.json)
  if(NOT EXISTS ${out}/${name})
    message(FATAL_ERROR "missing ${name}")
  endif()
endforeach()
file(STRINGS ${out}/gt_trajectory.tum lines)
list(LENGTH lines n)
if(NOT n EQUAL 72)
  message(FATAL_ERROR "gt_trajectory.tum has ${n} lines, expected 72")
endif()
file(STRINGS ${out}/log.jsonl log_lines)
list(LENGTH log_lines n)
if(NOT n EQUAL 73)
  message(FATAL_ERROR "log.jsonl has ${n} lines, expected a header and 72")
endif()
file(READ ${out}/gt_objects.json gt)
if(NOT gt MATCHES "^{\n  \"objects\": \\[\n    {\"id\": 0, " OR
   NOT gt MATCHES "\"class\": \"table\", \"symmetry\": \"discrete\", \"order\": 2" OR
   NOT gt MATCHES "\"detections\": {\n    \"[0-9]+/0\": 0,\n")
  message(FATAL_ERROR "gt_objects.json: unexpected content: ${gt}")
endif()

# --declare-noise false: the same detections (the same ground truth), and
# sigma_t/sigma_r only on the 71 odometry entries, none on the detections.
set(undeclared ${WORK_DIR}/undeclared)
execute_process(COMMAND ${SYMBA} simulate --scene disc --out ${undeclared}
    --seed 3 --declare-noise false
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "symba simulate --declare-noise false failed (${rc}): ${stderr}")
endif()
file(READ ${undeclared}/gt_objects.json undeclared_gt)
if(NOT undeclared_gt STREQUAL gt)
  message(FATAL_ERROR "--declare-noise false changed the detections")
endif()
file(READ ${out}/log.jsonl declared_log)
file(READ ${undeclared}/log.jsonl undeclared_log)
foreach(sigma sigma_t sigma_r)
  string(REGEX MATCHALL "\"${sigma}\"" declared_sigmas "${declared_log}")
  string(REGEX MATCHALL "\"${sigma}\"" undeclared_sigmas "${undeclared_log}")
  list(LENGTH declared_sigmas n_declared)
  list(LENGTH undeclared_sigmas n_undeclared)
  if(NOT n_undeclared EQUAL 71 OR NOT n_declared GREATER 100)
    message(FATAL_ERROR "${sigma}: ${n_declared} in the declared log, "
      "${n_undeclared} without declared noise (expected > 100 and 71)")
  endif()
endforeach()
file(REMOVE_RECURSE ${undeclared})

# An unknown scene is a usage error and writes nothing.
execute_process(COMMAND ${SYMBA} simulate --scene kitchen --out ${WORK_DIR}/bad
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(rc EQUAL 0 OR EXISTS ${WORK_DIR}/bad)
  message(FATAL_ERROR "an unknown scene must fail and write nothing")
endif()
file(GLOB entries RELATIVE ${WORK_DIR} ${WORK_DIR}/* ${WORK_DIR}/.*)
if(NOT entries STREQUAL "out")
  message(FATAL_ERROR "stray files beside the output: ${entries}")
endif()

# The long scene with --keyframes: that many keyframes (not its default of
# 10000), a log `symba replay` accepts.
set(long ${WORK_DIR}/long)
execute_process(COMMAND ${SYMBA} simulate --scene long --keyframes 40 --out ${long}
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0 OR NOT stdout MATCHES "scene long, seed 1: 40 keyframes")
  message(FATAL_ERROR "symba simulate --scene long failed (${rc}): ${stdout}${stderr}")
endif()
file(STRINGS ${long}/gt_trajectory.tum lines)
list(LENGTH lines n)
if(NOT n EQUAL 40)
  message(FATAL_ERROR "long: gt_trajectory.tum has ${n} lines, expected 40")
endif()
execute_process(COMMAND ${SYMBA} replay ${long}/log.jsonl --out ${WORK_DIR}/long_replay
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK_DIR}/long_replay/trajectory.tum)
  message(FATAL_ERROR "symba replay of the long scene failed (${rc}): ${stderr}")
endif()
