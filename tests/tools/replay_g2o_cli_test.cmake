cmake_minimum_required(VERSION 3.16)
# `symba replay GRAPH.g2o`: a small graph whose vertices start far from the
# measurements (a square of four poses, one loop closure). Both
# --g2o-initialization modes write trajectory.tum and a summary.json with
# the cost at the file's poses (given_cost), where the solver started
# (initial_cost) and the final cost; from the chordal guess the start is
# already the optimum of this noise-free graph. A third value is refused.
# Inputs: SYMBA (the binary), WORK_DIR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(graph ${WORK_DIR}/square.g2o)
set(info "1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1")
# The truth: (0,0), (1,0), (1,1), (0,1), each turned 90 deg about z from
# the last; every edge measures "1 m ahead, 90 deg left".
file(WRITE ${graph}
"VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1
VERTEX_SE3:QUAT 1 2 0.5 0 0 0 0 1
VERTEX_SE3:QUAT 2 -1 3 0 0 0 1 0
VERTEX_SE3:QUAT 3 4 4 1 0.6 0 0 0.8
EDGE_SE3:QUAT 0 1 1 0 0 0 0 0.70710678118654757 0.70710678118654757 ${info}
EDGE_SE3:QUAT 1 2 1 0 0 0 0 0.70710678118654757 0.70710678118654757 ${info}
EDGE_SE3:QUAT 2 3 1 0 0 0 0 0.70710678118654757 0.70710678118654757 ${info}
EDGE_SE3:QUAT 3 0 1 0 0 0 0 0.70710678118654757 0.70710678118654757 ${info}
")
foreach(mode chordal given)
  set(out ${WORK_DIR}/${mode})
  execute_process(COMMAND ${SYMBA} replay ${graph} --out ${out} --quiet
      --g2o-initialization ${mode}
    RESULT_VARIABLE rc ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${mode}: exit ${rc}: ${stderr}")
  endif()
  file(READ ${out}/summary.json summary)
  string(JSON given GET "${summary}" given_cost)
  string(JSON initial GET "${summary}" initial_cost)
  string(JSON final GET "${summary}" final_cost)
  if(NOT given GREATER 1.0 OR NOT final LESS 1e-12)
    message(FATAL_ERROR "${mode}: given ${given}, final ${final}")
  endif()
  if(mode STREQUAL "chordal" AND NOT initial LESS 1e-12)
    message(FATAL_ERROR "chordal: the start ${initial} is not the optimum")
  endif()
  if(mode STREQUAL "given" AND NOT initial EQUAL given)
    message(FATAL_ERROR "given: started at ${initial}, not at ${given}")
  endif()
  file(STRINGS ${out}/trajectory.tum lines)
  list(GET lines 2 third)  # vertex 2 at (1, 1)
  if(NOT third MATCHES "^2 (1|0\\.9999[0-9]*|1\\.0000[0-9]*) (1|0\\.9999[0-9]*|1\\.0000[0-9]*) ")
    message(FATAL_ERROR "${mode}: vertex 2 is '${third}', expected at (1, 1)")
  endif()
endforeach()
execute_process(COMMAND ${SYMBA} replay ${graph} --out ${WORK_DIR}/bad
    --g2o-initialization random
  RESULT_VARIABLE rc ERROR_VARIABLE stderr)
if(rc EQUAL 0 OR NOT stderr MATCHES "--g2o-initialization")
  message(FATAL_ERROR "a bad mode: exit ${rc}, '${stderr}'")
endif()
if(EXISTS ${WORK_DIR}/bad)
  message(FATAL_ERROR "a bad mode wrote ${WORK_DIR}/bad")
endif()
