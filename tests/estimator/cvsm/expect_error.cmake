# cmake -DCOMMAND="cmd;args" -DEXPECT=regex -P expect_error.cmake
# Passes when the command exits non-zero and its stderr matches EXPECT.
execute_process(COMMAND ${COMMAND} ERROR_VARIABLE err OUTPUT_QUIET RESULT_VARIABLE rc)
if(rc EQUAL 0)
  message(FATAL_ERROR "${COMMAND} succeeded; an error was expected")
endif()
if(NOT err MATCHES "${EXPECT}")
  message(FATAL_ERROR "${COMMAND} exited ${rc} but said:\n${err}\nexpected: ${EXPECT}")
endif()
message(STATUS "exit ${rc}: ${err}")
