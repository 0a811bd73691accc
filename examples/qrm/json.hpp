// examples/qrm/json.hpp: the JSON the qrm tool writes (summaries, manifests, reports), built by
// value instead of by concatenating strings: keys and strings are escaped, numbers are the
// shortest text that reads back exactly (0.2, not 0.20000000000000001), and non-finite numbers,
// which JSON cannot hold, are null. The output is compact (no spaces), one value per call.
#pragma once

#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include <qrm/io/csv.hpp>

namespace qrm_cli {

// json_number(x): the shortest text that reads back as exactly x (csv_number); "null" if x is
// not finite (JSON has no inf or nan).
inline std::string json_number(double x) { return std::isfinite(x) ? qrm::io::csv_number(x) : "null"; }

// short_number(x, digits): that many significant digits (three by default), for the text people read.
inline std::string short_number(double v, int digits = 3) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// json_string(s): s as a JSON string literal, quotes included.
inline std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

class json_object;
class json_array;

namespace detail {

// One JSON value's text: the overloads below are everything the tool writes.
inline std::string json_text(std::string_view v) { return json_string(v); }
inline std::string json_text(const char* v) { return json_string(v); }
inline std::string json_text(const std::string& v) { return json_string(v); }
inline std::string json_text(bool v) { return v ? "true" : "false"; }
inline std::string json_text(std::nullptr_t) { return "null"; }
template <std::floating_point T>
std::string json_text(T v) {
  return json_number(static_cast<double>(v));
}
template <std::integral T>
  requires(!std::same_as<T, bool> && !std::same_as<T, char>)
std::string json_text(T v) {
  return std::to_string(v);
}
std::string json_text(const json_object& v);
std::string json_text(const json_array& v);

// The text of an object or array being built: opening bracket, members so far.
class json_container {
 public:
  explicit json_container(char open) : text_(1, open) {}

 protected:
  void separate() {
    if (text_.size() > 1) text_ += ',';
  }
  std::string text_;
};

}  // namespace detail

// json_object: {"key":value,...} in the order the members are added.
class json_object : public detail::json_container {
 public:
  json_object() : json_container('{') {}
  // add(key, value): one member; value is a string, number, bool, json_object or json_array.
  template <class T>
  json_object& add(std::string_view key, const T& value) {
    separate();
    text_ += json_string(key);
    text_ += ':';
    text_ += detail::json_text(value);
    return *this;
  }
  // add_verbatim(key, text): a member whose value is already JSON text (read back from a file
  // this tool wrote, e.g. a tile's settings), copied as it is.
  json_object& add_verbatim(std::string_view key, std::string_view text) {
    separate();
    text_ += json_string(key);
    text_ += ':';
    text_ += text;
    return *this;
  }
  // add_members(other): every member of `other`, in its order.
  json_object& add_members(const json_object& other) {
    if (other.text_.size() > 1) {
      separate();
      text_.append(other.text_, 1);
    }
    return *this;
  }
  // str(): the finished object's text.
  std::string str() const { return text_ + '}'; }
};

// json_array: [value,...].
class json_array : public detail::json_container {
 public:
  json_array() : json_container('[') {}
  template <class T>
  json_array& push(const T& value) {
    separate();
    text_ += detail::json_text(value);
    return *this;
  }
  // of(range): an array of every element of the range.
  template <class Range>
  static json_array of(const Range& values) {
    json_array a;
    for (const auto& v : values) a.push(v);
    return a;
  }
  std::string str() const { return text_ + ']'; }
};

inline std::string detail::json_text(const json_object& v) { return v.str(); }
inline std::string detail::json_text(const json_array& v) { return v.str(); }

}  // namespace qrm_cli
