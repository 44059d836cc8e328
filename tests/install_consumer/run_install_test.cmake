# Installs the build tree into a scratch prefix, builds the consumer and the README's library
# consumer (its CMakeLists.txt and its example, both as written there) against it with
# CONSUMER_FLAGS (e.g. -march=native, or sanitizers), runs both.
#   -DMCCD_BUILD_DIR= -DCONSUMER_SOURCE= -DWORK_DIR= -DREADME= [-DCONSUMER_FLAGS=]
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${MCCD_BUILD_DIR} --prefix ${WORK_DIR}/prefix
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
# Internal headers must not be installed.
foreach(internal parallel/stepper.h core/bvh.h core/front.h core/executor.h geometry/kdop.h geometry/ccd_search.h
                 parallel/phc.h parallel/tbb_executor.h)
  if(EXISTS ${WORK_DIR}/prefix/include/mccd/${internal})
    message(FATAL_ERROR "internal header installed: ${internal}")
  endif()
endforeach()

# The README's example: the C++ block between <!-- example:begin --> and <!-- example:end -->.
file(READ ${README} readme)
string(REGEX MATCH "<!-- example:begin -->[^`]*```cpp\n(.*)```[^`]*<!-- example:end -->" found "${readme}")
if(NOT found)
  message(FATAL_ERROR "no example block in ${README}")
endif()
file(WRITE ${WORK_DIR}/app/main.cpp "${CMAKE_MATCH_1}")
# The README's consumer project: the CMake block between <!-- consumer-cmake:begin --> and
# <!-- consumer-cmake:end -->, saved beside the example as the README says.
string(REGEX MATCH "<!-- consumer-cmake:begin -->[^`]*```cmake\n(.*)```[^`]*<!-- consumer-cmake:end -->" found "${readme}")
if(NOT found)
  message(FATAL_ERROR "no consumer-cmake block in ${README}")
endif()
file(WRITE ${WORK_DIR}/app/CMakeLists.txt "${CMAKE_MATCH_1}")

# The consumer is built like the package (same compiler, same TBB) with CONSUMER_FLAGS: a
# sanitized static library needs a sanitized link; -march=native checks the ABI.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER} "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}"
  "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}" -DTBB_DIR=${CONSUMER_TBB_DIR}
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer failed: ${rc}")
endif()
# The README's commands: cmake -S app -B app/build -DCMAKE_PREFIX_PATH=<prefix>, then build
# (plus this test's compiler, flags and TBB).
execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK_DIR}/app -B ${WORK_DIR}/app/build
  -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER}
  "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}" -DTBB_DIR=${CONSUMER_TBB_DIR}
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the README's consumer failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/app/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the README's consumer failed: ${rc}")
endif()
if(CONSUMER_FLAGS MATCHES "-fsanitize=")
  file(STRINGS ${WORK_DIR}/build/consumer instrumented REGEX "__(asan|tsan|ubsan)_" LIMIT_COUNT 1)
  if(NOT instrumented)
    message(FATAL_ERROR "the consumer was built without the sanitizer flags '${CONSUMER_FLAGS}'")
  endif()
endif()
foreach(program build/consumer app/build/app)
  execute_process(COMMAND ${WORK_DIR}/${program} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${program} said: ${out}${err}")
  if(rc)
    message(FATAL_ERROR "${program} failed: ${rc}")
  endif()
endforeach()
execute_process(COMMAND ${WORK_DIR}/build/consumer OUTPUT_VARIABLE out)
if(NOT out MATCHES "faces 8 edges 16 contacts 1 earliest 0.625 host 7 3")
  message(FATAL_ERROR "unexpected consumer output")
endif()
