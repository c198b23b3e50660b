# Configures, builds and runs tests/build/consumer against lieservo.
# MODE=installed: install this build tree into a prefix, then find_package(lieservo).
# MODE=subdirectory: the consumer add_subdirectory()s the source tree.
file(REMOVE_RECURSE ${WORK_DIR})
set(_args -S ${CONSUMER_DIR} -B ${WORK_DIR}/build -DCMAKE_CXX_COMPILER=${CXX}
          -DEigen3_DIR=${EIGEN_DIR} -DCMAKE_BUILD_TYPE=Release)
if(MODE STREQUAL "installed")
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/prefix
                  RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "install failed: ${rc}")
  endif()
  list(APPEND _args -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
else()
  list(APPEND _args -DLIESERVO_SOURCE_DIR=${SOURCE_DIR})
endif()
foreach(step "${_args}" "--build;${WORK_DIR}/build" "${WORK_DIR}/build/consumer")
  if(step STREQUAL "${WORK_DIR}/build/consumer")
    execute_process(COMMAND ${step} RESULT_VARIABLE rc)
  else()
    execute_process(COMMAND ${CMAKE_COMMAND} ${step} RESULT_VARIABLE rc)
  endif()
  if(rc)
    message(FATAL_ERROR "consumer step failed (${rc}): ${step}")
  endif()
endforeach()
