# cmake -DCXX=... -DSOURCE=... -DINCLUDE=... -DEXPECT=fail|pass [-DDEFINE=...] [-DMESSAGE=regex]
#       [-DCULPRIT=regex] [-DERRORS=n] -P expect_compile.cmake
# A must-fail check passes only if the compiler rejects SOURCE *and* its first error line matches
# MESSAGE (the rule's name), so a failure for another reason (a typo, a missing header) does not
# count. CULPRIT must match somewhere in the output (the register, qubit or value at fault), and
# with ERRORS the output must hold exactly that many "error:" lines (no cascade after the rule).
set(args -std=c++20 -fsyntax-only -I${INCLUDE} ${SOURCE})
if(DEFINE)
  list(APPEND args -D${DEFINE})
endif()
execute_process(COMMAND ${CXX} ${args} RESULT_VARIABLE rv OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(EXPECT STREQUAL "pass")
  if(NOT rv EQUAL 0)
    message(FATAL_ERROR "expected ${SOURCE} to compile, but:\n${out}")
  endif()
else()
  if(rv EQUAL 0)
    message(FATAL_ERROR "expected ${SOURCE} (-D${DEFINE}) to be rejected, but it compiled")
  endif()
  string(REGEX MATCH "[^\n]*error:[^\n]*" first_error "${out}")
  if(NOT first_error MATCHES "${MESSAGE}")
    message(FATAL_ERROR "${SOURCE} was rejected, but its first error is not '${MESSAGE}':\n${out}")
  endif()
  if(DEFINED CULPRIT AND NOT out MATCHES "${CULPRIT}")
    message(FATAL_ERROR "${SOURCE} was rejected with '${MESSAGE}', but the output does not name the culprit "
                        "'${CULPRIT}':\n${out}")
  endif()
  if(DEFINED ERRORS)
    string(REPLACE ";" "," out_as_list_safe "${out}")  # a ';' in a message would split a line in two
    string(REGEX MATCHALL "[^\n]*error:[^\n]*" error_lines "${out_as_list_safe}")
    list(LENGTH error_lines n)
    if(NOT n EQUAL ERRORS)
      message(FATAL_ERROR "${SOURCE} was rejected with '${MESSAGE}', but with ${n} error lines, not ${ERRORS}:\n${out}")
    endif()
  endif()
  message(STATUS "rejected with '${MESSAGE}' as expected")
endif()
