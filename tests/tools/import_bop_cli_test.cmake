cmake_minimum_required(VERSION 3.16)
# The worked example of docs/import.md ("symba import bop"), as a user runs
# it: import the bundled BOP scene, replay the log, and check the counts; and
# a malformed results file: exit 1, FILE:LINE in the message, no log.
# Inputs: SYMBA (the binary), DATA (tests/data/bop), WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(log ${WORK_DIR}/scene7.jsonl)
execute_process(COMMAND ${SYMBA} import bop --results ${DATA}/results.csv
    --scene-camera ${DATA}/scene_camera.json
    --models-info ${DATA}/models_info.json --class-names 1=table,2=mug
    --out ${log}
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "import failed (${rc}): ${stderr}")
endif()
string(FIND "${stderr}" "8 keyframes, 16 detections from 17 rows" at)
if(at EQUAL -1)
  message(FATAL_ERROR "unexpected summary: ${stderr}")
endif()
execute_process(COMMAND ${SYMBA} replay ${log} --out ${WORK_DIR}/replay --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "replay failed (${rc}): ${stderr}")
endif()
file(READ ${WORK_DIR}/replay/summary.json summary)
string(FIND "${summary}" "\"objects\": 2," at)
if(at EQUAL -1)
  message(FATAL_ERROR "expected 2 map objects (a table, a mug): ${summary}")
endif()

file(READ ${DATA}/results.csv csv)
file(WRITE ${WORK_DIR}/bad.csv "${csv}7,1,1,0.5,1 0 0 0 1 0,0 0 1000,0\n")
set(bad_log ${WORK_DIR}/bad.jsonl)
execute_process(COMMAND ${SYMBA} import bop --results ${WORK_DIR}/bad.csv
    --scene-camera ${DATA}/scene_camera.json --out ${bad_log}
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "a malformed row must exit 1, got ${rc}: ${stderr}")
endif()
string(FIND "${stderr}" "bad.csv:19: R: expected 9 space-separated numbers" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the message must name FILE:LINE: ${stderr}")
endif()
if(EXISTS ${bad_log})
  message(FATAL_ERROR "a failed import wrote ${bad_log}")
endif()

# A gate of nan is refused by the parser (it used to mean "not given").
execute_process(COMMAND ${SYMBA} import bop --results ${DATA}/results.csv
    --scene-camera ${DATA}/scene_camera.json --gate nan --out ${bad_log}
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
string(FIND "${stderr}" "--gate: Value nan is not a finite number" at)
if(rc EQUAL 0 OR at EQUAL -1 OR EXISTS ${bad_log})
  message(FATAL_ERROR "--gate nan must be refused, no log (${rc}): ${stderr}")
endif()
