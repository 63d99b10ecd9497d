cmake_minimum_required(VERSION 3.16)
# symba replay --bop-out on the worked example of docs/import.md: import
# the bundled BOP scene (its header records scene 7 and the obj_ids),
# replay it with --bop-out and check the rows: one per detection assigned
# to a map object (associations.csv, counted independently), scene 7, the
# image ids and obj_ids of the detections, R nine numbers, t in mm (the
# table's row within 5 cm, 50 mm, of its detected 2282.5 mm depth). Then
# the errors: no scene id, a class without obj_id, a missing directory:
# exit 1, the message, no CSV and no replay directory. Last, symba export
# bop on the imported log, imported again.
# Inputs: SYMBA (the binary), DATA (tests/data/bop), WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(log ${WORK_DIR}/scene7.jsonl)
execute_process(COMMAND ${SYMBA} import bop --results ${DATA}/results.csv
    --scene-camera ${DATA}/scene_camera.json
    --models-info ${DATA}/models_info.json --class-names 1=table,2=mug
    --out ${log} --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "import failed (${rc}): ${stderr}")
endif()
file(STRINGS ${log} header LIMIT_COUNT 1)
string(FIND "${header}" "\"bop\":{\"scene_id\":7,\"obj_ids\":{\"mug\":2,\"table\":1}}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the header must record the BOP source: ${header}")
endif()

set(csv ${WORK_DIR}/refined.csv)
execute_process(COMMAND ${SYMBA} replay ${log} --out ${WORK_DIR}/replay
    --bop-out ${csv} --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "replay --bop-out failed (${rc}): ${stderr}")
endif()
file(STRINGS ${csv} rows)
list(POP_FRONT rows first)
if(NOT first STREQUAL "scene_id,im_id,obj_id,score,R,t,time")
  message(FATAL_ERROR "header line: ${first}")
endif()
# The detections in a map object: associations.csv rows whose object >= 0.
file(STRINGS ${WORK_DIR}/replay/associations.csv associations)
list(POP_FRONT associations)
set(expected "")
foreach(a IN LISTS associations)
  string(REPLACE "," ";" f "${a}")
  list(GET f 0 keyframe)
  list(GET f 2 object)
  if(object GREATER_EQUAL 0)
    list(APPEND expected ${keyframe})
  endif()
endforeach()
list(LENGTH expected expected_count)
list(LENGTH rows count)
if(NOT count EQUAL expected_count OR count LESS 14)
  message(FATAL_ERROR "expected ${expected_count} rows (>= 14), got ${count}")
endif()
set(index 0)
foreach(row IN LISTS rows)
  string(REPLACE "," ";" f "${row}")
  list(LENGTH f fields)
  if(NOT fields EQUAL 7)
    message(FATAL_ERROR "row without 7 fields: ${row}")
  endif()
  list(GET f 0 scene)
  list(GET f 1 im)
  list(GET f 2 obj)
  list(GET f 4 R)
  list(GET f 5 t)
  list(GET f 6 time)
  list(GET expected ${index} expected_im)
  math(EXPR index "${index} + 1")
  if(NOT scene EQUAL 7 OR NOT im EQUAL expected_im OR NOT time EQUAL -1)
    message(FATAL_ERROR "row ${index}: scene 7, image ${expected_im}, time -1 expected: ${row}")
  endif()
  if(NOT obj EQUAL 1 AND NOT obj EQUAL 2)
    message(FATAL_ERROR "row ${index}: obj_id 1 or 2 expected: ${row}")
  endif()
  string(REPLACE " " ";" R_numbers "${R}")
  string(REPLACE " " ";" t_numbers "${t}")
  list(LENGTH R_numbers nR)
  list(LENGTH t_numbers nt)
  if(NOT nR EQUAL 9 OR NOT nt EQUAL 3)
    message(FATAL_ERROR "row ${index}: R 9 and t 3 numbers expected: ${row}")
  endif()
  list(GET t_numbers 2 depth)
  # The detector saw every object 1.73 to 2.78 m in front of the camera: in mm.
  if(depth LESS 1500 OR depth GREATER 3000)
    message(FATAL_ERROR "row ${index}: t_z ${depth} is not in mm: ${row}")
  endif()
  if(obj EQUAL 1 AND im EQUAL 0)
    if(depth LESS 2232 OR depth GREATER 2333)
      message(FATAL_ERROR "the table in image 0 at ${depth} mm, detected at 2282.5: ${row}")
    endif()
  endif()
endforeach()

# symba replay ARGS... --quiet must exit 1 with `expected` on stderr.
function(expect_replay_failure name expected)
  execute_process(COMMAND ${SYMBA} replay ${ARGN} --quiet
    RESULT_VARIABLE rc ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 1)
    message(FATAL_ERROR "${name}: exit 1 expected, got ${rc}: ${stderr}")
  endif()
  string(FIND "${stderr}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${name}: expected \"${expected}\": ${stderr}")
  endif()
endfunction()

# A log without the bop key and with names that are not obj_<id>: without
# --bop-scene the scene is unknown; with it, the class has no obj_id.
execute_process(COMMAND ${SYMBA} import bop --results ${DATA}/results.csv
    --scene-camera ${DATA}/scene_camera.json --class-names 1=table,2=mug
    --out ${WORK_DIR}/plain.jsonl --quiet RESULT_VARIABLE rc)
file(READ ${WORK_DIR}/plain.jsonl plain)
string(REGEX REPLACE ",\"bop\":{[^}]*}}" "" plain "${plain}")
file(WRITE ${WORK_DIR}/plain.jsonl "${plain}")
foreach(case "no_scene;;no BOP scene id: the log header has no \"bop\" key"
              "no_obj_id;--bop-scene;7;class \"table\": no BOP obj_id"
              "no_dir;--bop-scene;7;/absent/refined.csv: parent directory")
  list(GET case 0 name)
  set(flags "")
  set(message_index 1)
  list(GET case 1 flag)
  if(flag STREQUAL "--bop-scene")
    list(GET case 2 scene_value)
    set(flags --bop-scene ${scene_value})
    set(message_index 3)
  endif()
  list(GET case ${message_index} expected_message)
  set(out_csv ${WORK_DIR}/${name}.csv)
  set(input ${WORK_DIR}/plain.jsonl)
  if(name STREQUAL "no_dir")
    set(out_csv ${WORK_DIR}/absent/refined.csv)
    set(input ${log})
  endif()
  expect_replay_failure(${name} "${expected_message}" ${input}
      --out ${WORK_DIR}/${name} --bop-out ${out_csv} ${flags})
  if(EXISTS ${out_csv} OR EXISTS ${WORK_DIR}/${name})
    message(FATAL_ERROR "${name}: a failed replay wrote an output")
  endif()
endforeach()

# Outputs that would destroy an input or are no file: --bop-out onto the
# log, --bop-out a directory, --out holding the log. Exit 1, the message,
# the log untouched and no replay directory.
file(MAKE_DIRECTORY ${WORK_DIR}/a_directory ${WORK_DIR}/holder)
file(COPY_FILE ${log} ${WORK_DIR}/holder/scene7.jsonl)
file(SHA256 ${log} log_hash)
foreach(case "onto_log;${log};${WORK_DIR}/onto_log;${log}: is the input"
              "dir;${WORK_DIR}/a_directory;${WORK_DIR}/dir;exists and is not a regular file"
              "holder;${WORK_DIR}/holder.csv;${WORK_DIR}/holder;holds the input")
  list(GET case 0 name)
  list(GET case 1 bop_out)
  list(GET case 2 out)
  list(GET case 3 expected_message)
  set(input ${log})
  if(name STREQUAL "holder")
    set(input ${WORK_DIR}/holder/scene7.jsonl)
  endif()
  expect_replay_failure(${name} "${expected_message}" ${input}
      --out ${out} --bop-out ${bop_out})
  if(NOT name STREQUAL "holder" AND EXISTS ${out})
    message(FATAL_ERROR "${name}: a failed replay wrote ${out}")
  endif()
endforeach()
file(SHA256 ${log} log_hash_after)
if(NOT log_hash STREQUAL log_hash_after
   OR NOT EXISTS ${WORK_DIR}/holder/scene7.jsonl
   OR EXISTS ${WORK_DIR}/holder.csv)
  message(FATAL_ERROR "a refused replay changed its input or wrote --bop-out")
endif()

# symba export bop on the imported log: the six files, every hypothesis a
# row (17), and the import of the export gives the same 16 detections; an
# output directory whose parent is missing: exit 1, nothing written.
execute_process(COMMAND ${SYMBA} export bop ${log} --out ${WORK_DIR}/exported
    --scene-id 7 --quiet
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "export bop failed (${rc}): ${stderr}")
endif()
foreach(file results.csv scene_camera.json models_info.json image_times.txt
             frontend.tum class_names.txt)
  if(NOT EXISTS ${WORK_DIR}/exported/${file})
    message(FATAL_ERROR "export bop did not write ${file}")
  endif()
endforeach()
file(STRINGS ${WORK_DIR}/exported/results.csv exported_rows)
list(LENGTH exported_rows exported_count)
if(NOT exported_count EQUAL 18)
  message(FATAL_ERROR "expected a header and 17 rows, got ${exported_count}")
endif()
file(READ ${WORK_DIR}/exported/class_names.txt names)
string(STRIP "${names}" names)
if(NOT names STREQUAL "1=mug,2=table")
  message(FATAL_ERROR "class names: ${names}")
endif()
execute_process(COMMAND ${SYMBA} import bop
    --results ${WORK_DIR}/exported/results.csv
    --scene-camera ${WORK_DIR}/exported/scene_camera.json
    --models-info ${WORK_DIR}/exported/models_info.json
    --class-names ${names} --out ${WORK_DIR}/again.jsonl
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
string(FIND "${stderr}" "8 keyframes, 16 detections from 17 rows" at)
if(NOT rc EQUAL 0 OR at EQUAL -1)
  message(FATAL_ERROR "re-import of the export (${rc}): ${stderr}")
endif()
execute_process(COMMAND ${SYMBA} export bop ${log}
    --out ${WORK_DIR}/absent/exported
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
string(FIND "${stderr}" "symba export bop: ${WORK_DIR}/absent/exported: parent directory" at)
if(NOT rc EQUAL 1 OR at EQUAL -1 OR EXISTS ${WORK_DIR}/absent)
  message(FATAL_ERROR "export into a missing parent (${rc}): ${stderr}")
endif()
