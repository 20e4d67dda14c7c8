# Installs the built Expanse into a scratch prefix, then configures, builds and runs a consumer
# that uses find_package(expanse CONFIG) — or, with MODE=subdirectory, add_subdirectory.
# -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK=... -DMODE=install|subdirectory -DWITH_VULKAN=ON|OFF
# -DWITH_CUDA=ON|OFF
file(REMOVE_RECURSE ${WORK})
if(MODE STREQUAL "install")
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK}/prefix
                  RESULT_VARIABLE rc OUTPUT_QUIET)
  if(rc)
    message(FATAL_ERROR "cmake --install failed (${rc})")
  endif()
  # An interop header is installed exactly when its backend was built.
  foreach(api vulkan cuda)
    string(TOUPPER ${api} API)
    set(header ${WORK}/prefix/include/expanse/${api}_interop.hpp)
    if(WITH_${API} AND NOT EXISTS ${header})
      message(FATAL_ERROR "the ${api} backend was built but ${api}_interop.hpp is not installed")
    elseif(NOT WITH_${API} AND EXISTS ${header})
      message(FATAL_ERROR "${api}_interop.hpp is installed without the ${api} backend")
    endif()
  endforeach()
  set(configure_args -DCMAKE_PREFIX_PATH=${WORK}/prefix)
else()
  set(configure_args -DEXPANSE_SOURCE_DIR=${SOURCE_DIR})
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK}/build
                        -DCMAKE_BUILD_TYPE=Release ${configure_args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "building the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${WORK}/build/consumer RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(rc)
  message(FATAL_ERROR "the consumer's mesh is wrong")
endif()
