cmake_minimum_required(VERSION 3.16)
# Fails when a file refers to a path outside the repository: the sibling
# directory beside the checkout, an absolute path of the machine it was
# written on (a home or work directory). The repository must stand alone.
#
# Inputs: SOURCE_DIR (check every file git tracks there; without git, every
# file under it except build directories), or FILES (a ;-list to check
# instead, used by the test that plants a reference to prove this fails).
#
# The patterns are written with character classes so that this file does not
# match itself. Words such as "shared" or std::make_shared are fine; only a
# path into the sibling directory is not.
set(patterns
  "[.][.][/]shared"
  "shared[/](spec|data|seeds|hooks)"
  "^[/]work[/]"
  "[^A-Za-z0-9_.~-][/]work[/]"
  "^[/](home|Users)[/][A-Za-z]"
  "[^A-Za-z0-9_.~-][/](home|Users)[/][A-Za-z]"
  "[^A-Za-z0-9_.~-][/]root[/]")

if(NOT DEFINED FILES)
  if(NOT DEFINED SOURCE_DIR)
    message(FATAL_ERROR "set SOURCE_DIR or FILES")
  endif()
  find_program(GIT git)
  set(rc 1)
  if(GIT)
    execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} ls-files
      RESULT_VARIABLE rc OUTPUT_VARIABLE listed ERROR_QUIET
      OUTPUT_STRIP_TRAILING_WHITESPACE)
  endif()
  set(FILES "")
  if(rc EQUAL 0)
    string(REPLACE "\n" ";" listed "${listed}")
    foreach(name IN LISTS listed)
      list(APPEND FILES "${SOURCE_DIR}/${name}")
    endforeach()
  else()
    file(GLOB_RECURSE FILES LIST_DIRECTORIES false RELATIVE ${SOURCE_DIR}
      ${SOURCE_DIR}/*)
    list(FILTER FILES EXCLUDE REGEX "^(build[^/]*|\\.git)/")
    list(TRANSFORM FILES PREPEND "${SOURCE_DIR}/")
  endif()
  list(LENGTH FILES count)
  if(count EQUAL 0)
    message(FATAL_ERROR "no files to check under ${SOURCE_DIR}")
  endif()
endif()

set(found "")
foreach(path IN LISTS FILES)
  if(NOT EXISTS "${path}" OR IS_DIRECTORY "${path}")
    continue()
  endif()
  set(file_hits "")
  foreach(pattern IN LISTS patterns)
    file(STRINGS "${path}" hits REGEX "${pattern}")
    list(APPEND file_hits ${hits})
  endforeach()
  list(REMOVE_DUPLICATES file_hits)
  foreach(hit IN LISTS file_hits)
    string(APPEND found "\n  ${path}: ${hit}")
  endforeach()
endforeach()

if(NOT found STREQUAL "")
  message(FATAL_ERROR "references outside the repository:${found}")
endif()
