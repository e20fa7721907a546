# cmake -DFIRST="cmd;args" -DSECOND="cmd;args" -P compare_outputs.cmake
# Runs both commands; fails unless both succeed and print the same.
foreach(which FIRST SECOND)
  execute_process(COMMAND ${${which}} OUTPUT_VARIABLE out_${which} RESULT_VARIABLE rc_${which})
  if(NOT rc_${which} EQUAL 0)
    message(FATAL_ERROR "${${which}} failed (${rc_${which}})")
  endif()
endforeach()
if(NOT out_FIRST STREQUAL out_SECOND)
  message(FATAL_ERROR "outputs differ:\n  ${FIRST}: ${out_FIRST}  ${SECOND}: ${out_SECOND}")
endif()
message(STATUS "both print: ${out_FIRST}")
