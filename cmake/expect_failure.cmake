# cmake "-DCOMMAND=prog;arg;..." -DMESSAGE=regex -P expect_failure.cmake
# Passes only if COMMAND exits non-zero *and* prints MESSAGE, so a checker that fails for another
# reason (a missing file, a crash) does not count as rejecting what it was meant to reject.
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE rv OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rv EQUAL 0)
  message(FATAL_ERROR "expected this to fail, but it succeeded: ${COMMAND}\n${out}")
endif()
if(NOT out MATCHES "${MESSAGE}")
  message(FATAL_ERROR "failed, but not with '${MESSAGE}':\n${out}")
endif()
message(STATUS "failed with '${MESSAGE}' as expected:\n${out}")
