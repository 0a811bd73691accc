# cmake -DMESSAGE=... -P fail.cmake: a test that fails, saying why.
message(FATAL_ERROR "${MESSAGE}")
