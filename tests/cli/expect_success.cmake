cmake_minimum_required(VERSION 3.25)
# Generates a point set, triangulates it with --check --json, and checks the outputs exist,
# stdout is one JSON object with the promised keys, and the .ele numbering follows the input.
#
# cmake -DEXPANSE=<binary> -DWORK=<scratch dir> -DDIST=<distribution> -DN=<points>
#       [-DFIRST=<0|1>] -P expect_success.cmake
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
if(NOT DEFINED FIRST)
  set(FIRST 0)
endif()

execute_process(COMMAND "${EXPANSE}" generate --dist ${DIST} -n ${N} --seed 7 --first-index ${FIRST}
                        -o "${WORK}/in.node"
                RESULT_VARIABLE _rc ERROR_VARIABLE _err)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "generate failed (${_rc}): ${_err}")
endif()

execute_process(COMMAND "${EXPANSE}" triangulate "${WORK}/in.node" -o "${WORK}/out"
                        --neighbors --svg --png --check --json
                RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
message(STATUS "stdout: ${_out}\nstderr: ${_err}")
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "triangulate failed (${_rc})")
endif()
foreach(key sites triangles seam_triangles gpu_triangles deferred_expansions iterations backend device)
  string(JSON _v ERROR_VARIABLE _e GET "${_out}" ${key})
  if(_e)
    message(FATAL_ERROR "JSON lacks '${key}': ${_e}")
  endif()
endforeach()
string(JSON _total GET "${_out}" time_ms total)
string(JSON _stages TYPE "${_out}" time_ms stages)
if(NOT _stages STREQUAL "OBJECT")
  message(FATAL_ERROR "time_ms.stages is not an object")
endif()
foreach(ext ele neigh svg png)
  if(NOT EXISTS "${WORK}/out.${ext}")
    message(FATAL_ERROR "missing output out.${ext}")
  endif()
endforeach()
# The first triangle's number follows the input's index base.
string(JSON _triangles GET "${_out}" triangles)
if(_triangles GREATER 0)
  file(STRINGS "${WORK}/out.ele" _lines LIMIT_COUNT 2)
  list(GET _lines 1 _first)
  string(REGEX MATCH "^[ ]*[0-9]+" _number "${_first}")
  string(STRIP "${_number}" _number)
  if(NOT _number EQUAL FIRST)
    message(FATAL_ERROR "first triangle numbered ${_number}, expected ${FIRST}")
  endif()
endif()
file(REMOVE_RECURSE "${WORK}")
