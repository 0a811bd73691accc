// tests/support/errors.hpp: the message of the exception a call throws, for checking that bad
// input is rejected with a message that names the problem.
#pragma once

#include <exception>
#include <string>

namespace qrm_test {

// error_of(f): what f() throws (its what()), or "(no error)".
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace qrm_test
