cmake_minimum_required(VERSION 3.25)
# Runs `expanse` on bad input and checks the three promises of the CLI: a non-zero exit,
# stderr naming the problem (file and line, or the point), and no output file left behind.
#
# cmake -DEXPANSE=<binary> -DWORK=<scratch dir> -DFIXTURE=<file to copy into WORK, optional>
#       -DCOMMAND="<args, ; separated, {WORK} replaced>" -DEXPECT=<regex on stderr> -P expect_failure.cmake
foreach(var EXPANSE WORK COMMAND EXPECT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "expect_failure.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(_kept)
if(FIXTURE)
  file(COPY "${FIXTURE}" DESTINATION "${WORK}")
  get_filename_component(_name "${FIXTURE}" NAME)
  list(APPEND _kept "${WORK}/${_name}")
endif()

string(REPLACE "{WORK}" "${WORK}" _args "${COMMAND}")
execute_process(COMMAND "${EXPANSE}" ${_args}
                RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
message(STATUS "exit: ${_rc}\nstdout: ${_out}\nstderr: ${_err}")

if(_rc EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit, got 0")
endif()
if(NOT _rc MATCHES "^[0-9]+$")
  message(FATAL_ERROR "expected an error exit, but the program did not exit normally: ${_rc}")
endif()
if(NOT _err MATCHES "${EXPECT}")
  message(FATAL_ERROR "stderr does not match '${EXPECT}'")
endif()

file(GLOB_RECURSE _left LIST_DIRECTORIES false "${WORK}/*")
foreach(_f IN LISTS _left)
  list(FIND _kept "${_f}" _i)
  if(_i EQUAL -1)
    message(FATAL_ERROR "output file left behind: ${_f}")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
