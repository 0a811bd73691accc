// Default options of the sanitizers in qrm's own executables when built with QRM_SANITIZE (the
// environment can still override them). A report must fail whatever runs the program -- ctest,
// a test script that expects a usage error and its exit code, a user -- so every ASan, UBSan and
// LeakSanitizer report aborts (SIGABRT: no test expects it; CMake calls it "Subprocess aborted").
extern "C" const char* __asan_default_options() {
  return "abort_on_error=1:halt_on_error=1:detect_leaks=1";
}
extern "C" const char* __ubsan_default_options() {
  return "abort_on_error=1:halt_on_error=1:print_stacktrace=1";
}
