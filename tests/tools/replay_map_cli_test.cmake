cmake_minimum_required(VERSION 3.16)
# symba replay --map-out / --map-in (docs/map-format.md): a simulated room
# (36 keyframes) replayed with --map-out writes a map file with its five
# objects; another run through the room (its poses in the map's frame up to
# the front ends' drift) replayed from that map with --map-in writes a
# complete replay, and with --relocalize finds where it is; a map file that
# is not one is refused with its name, the member and exit 1, and no
# output.
# Inputs: SYMBA (the binary), WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
execute_process(COMMAND ${SYMBA} simulate --scene room --seed 3
    --keyframes 36 --out ${WORK_DIR}/sim
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "simulate failed (${rc}): ${stderr}")
endif()
set(map ${WORK_DIR}/map.json)
execute_process(COMMAND ${SYMBA} replay ${WORK_DIR}/sim/log.jsonl
    --out ${WORK_DIR}/first --map-out ${map}
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "replay --map-out failed (${rc}): ${stderr}")
endif()
string(FIND "${stderr}" "; map ${map}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the summary line must name the map: ${stderr}")
endif()
file(READ ${map} text)
string(FIND "${text}" "\"format\": \"symba-map\"" at)
if(at EQUAL -1)
  message(FATAL_ERROR "not a map file: ${text}")
endif()
string(REGEX MATCHALL "\"class\": \"[a-z_]+\",\n      \"symmetry\"" objects "${text}")
list(LENGTH objects count)
if(NOT count EQUAL 5)
  message(FATAL_ERROR "expected 5 objects in the map, found ${count}")
endif()

# Another run through the same room (seed 4, 20 keyframes) for the runs
# from the map.
execute_process(COMMAND ${SYMBA} simulate --scene room --seed 4
    --keyframes 20 --out ${WORK_DIR}/sim4
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "simulate failed (${rc}): ${stderr}")
endif()
execute_process(COMMAND ${SYMBA} replay ${WORK_DIR}/sim4/log.jsonl
    --out ${WORK_DIR}/again --map-in ${map} --map-out ${WORK_DIR}/map2.json
    --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK_DIR}/again/objects.json
   OR NOT EXISTS ${WORK_DIR}/map2.json)
  message(FATAL_ERROR "replay --map-in failed (${rc}): ${stderr}")
endif()

# --relocalize: the same run finds where it is from the map's objects and
# says so on stderr and in summary.json.
execute_process(COMMAND ${SYMBA} replay ${WORK_DIR}/sim4/log.jsonl
    --out ${WORK_DIR}/reloc --map-in ${map} --relocalize
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "replay --relocalize failed (${rc}): ${stderr}")
endif()
string(REGEX MATCH "; relocalised at keyframe [0-9]+ on [0-9]+ objects"
  said "${stderr}")
if(said STREQUAL "")
  message(FATAL_ERROR "the summary line must say where it relocalised: ${stderr}")
endif()
file(READ ${WORK_DIR}/reloc/summary.json summary)
string(FIND "${summary}" "\"state\": \"relocalized\"" at)
if(at EQUAL -1)
  message(FATAL_ERROR "summary.json must report the relocalisation: ${summary}")
endif()
execute_process(COMMAND ${SYMBA} replay ${WORK_DIR}/sim4/log.jsonl
    --out ${WORK_DIR}/no_map --relocalize --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
string(FIND "${stderr}" "--relocalize needs --map-in" at)
if(NOT rc EQUAL 1 OR at EQUAL -1 OR EXISTS ${WORK_DIR}/no_map)
  message(FATAL_ERROR "--relocalize without a map must exit 1 (${rc}): ${stderr}")
endif()

string(REPLACE "\"symba-map\"" "\"symba-log\"" bad "${text}")
file(WRITE ${WORK_DIR}/bad.json "${bad}")
execute_process(COMMAND ${SYMBA} replay ${WORK_DIR}/sim/log.jsonl
    --out ${WORK_DIR}/bad --map-in ${WORK_DIR}/bad.json --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "a bad map must exit 1, got ${rc}")
endif()
string(FIND "${stderr}" "${WORK_DIR}/bad.json: format: expected \"symba-map\"" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the message must name the file and member: ${stderr}")
endif()
if(EXISTS ${WORK_DIR}/bad)
  message(FATAL_ERROR "a refused map must leave no replay output")
endif()
