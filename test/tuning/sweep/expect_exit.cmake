# cmake -DCMD=<prog;args...> -DEXPECT_CODE=<n> -DREGEX=<text> -P expect_exit.cmake
# Passes when CMD exits with EXPECT_CODE and its stdout+stderr contain REGEX (a plain substring).
execute_process(COMMAND ${CMD} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(NOT code STREQUAL "${EXPECT_CODE}")
  message(FATAL_ERROR "exit code ${code}, expected ${EXPECT_CODE}; output:\n${all}")
endif()
string(FIND "${all}" "${REGEX}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "output lacks '${REGEX}':\n${all}")
endif()
message(STATUS "ok: exit ${code}, found '${REGEX}'")
