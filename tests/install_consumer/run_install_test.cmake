# Installs the build tree into a scratch prefix, builds the consumer against it, runs it.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${MCCD_BUILD_DIR} --prefix ${WORK_DIR}/prefix
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
# The consumer is built like the package: same compiler, same sanitizer flags (a sanitized
# static library needs a sanitized link), same TBB.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER} "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}"
  "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}" -DTBB_DIR=${CONSUMER_TBB_DIR} RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer failed: ${rc}")
endif()
if(CONSUMER_FLAGS MATCHES "-fsanitize=")
  file(STRINGS ${WORK_DIR}/build/consumer instrumented REGEX "__(asan|tsan|ubsan)_" LIMIT_COUNT 1)
  if(NOT instrumented)
    message(FATAL_ERROR "the consumer was built without the sanitizer flags '${CONSUMER_FLAGS}'")
  endif()
endif()
execute_process(COMMAND ${WORK_DIR}/build/consumer RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "consumer said: ${out}")
if(rc)
  message(FATAL_ERROR "the consumer failed: ${rc}")
endif()
if(NOT out MATCHES "faces 8 edges 16 contacts 1 earliest 0.625")
  message(FATAL_ERROR "unexpected consumer output")
endif()
