// qrm/support/detail/formatted_error.hpp: error messages formatted with snprintf.
#pragma once

#include <cstdarg>
#include <cstdio>

namespace qrm::detail {

// throw_formatted<E>(format, args...): throws E(message), the message printf-formatted (cut at
// 1 KiB). For the checks in templates every user's file instantiates (typed gates, run, programs):
// in C++20 libstdc++ compiles std::string's operator+ and to_string in each file that calls them
// (120 of the 461 functions the README tour's file compiled at -O0); snprintf is in libc.
template <class E>
[[noreturn]] [[gnu::format(printf, 1, 2)]] void throw_formatted(const char* format, ...) {
  char message[1024];
  std::va_list args;
  va_start(args, format);
  std::vsnprintf(message, sizeof message, format, args);
  va_end(args);
  throw E(message);
}

}  // namespace qrm::detail
