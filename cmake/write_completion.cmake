# Writes the bash completion script the tool prints: cmake -DPATLAB=<tool> -DOUT=<file> -P this.
execute_process(COMMAND ${PATLAB} completion bash OUTPUT_FILE ${OUT} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${PATLAB} completion bash failed: ${status}")
endif()
