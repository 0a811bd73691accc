# cmake -DCOMMAND="prog|arg|arg" -DCODE=n [-DREGEX=re] -P expect_run.cmake
# Runs COMMAND (arguments separated by |), and fails unless it exits with CODE and its combined
# stdout and stderr match REGEX.
string(REPLACE "|" ";" cmd "${COMMAND}")
execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT "${rc}" STREQUAL "${CODE}")
  message(FATAL_ERROR "expected exit code ${CODE}, got ${rc}\nstdout: ${out}\nstderr: ${err}")
endif()
if(DEFINED REGEX AND NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match '${REGEX}'\nstdout: ${out}\nstderr: ${err}")
endif()
