// examples/qrm/args.hpp: strict command-line parsing for the qrm tool. Unknown flags, missing
// values and malformed numbers are errors that name the flag and the value. Each command
// describes its flags in one table (flag_table) that both declares what it accepts and prints
// its --help, so the help cannot drift from the parser.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <optional>
#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace qrm_cli {

// number_list("1e-5,1e-4"): the comma-separated numbers, or nothing if an item is empty or not
// a whole number text; each caller says what its flag expects.
inline std::optional<std::vector<double>> number_list(const std::string& text) {
  std::vector<double> out;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    char* stop = nullptr;
    const double v = item.empty() ? 0.0 : std::strtod(item.c_str(), &stop);
    if (item.empty() || stop != item.c_str() + item.size()) return std::nullopt;
    out.push_back(v);
    if (end == text.size()) return out;
    begin = end + 1;
  }
}

struct usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// flag: one row of a command's flag table.
struct flag {
  const char* name;      // without the leading --
  const char* value;     // the value's form (N, FILE, a|b|c), or "" for a switch
  const char* fallback;  // the default as the user would write it, or "" (none, or see meaning)
  const char* meaning;
  const char* group;     // the heading --help lists it under
};
using flag_table = std::vector<flag>;

class args {
 public:
  // argv after the subcommand name.
  args(std::string command, std::vector<std::string> argv) : command_(std::move(command)) {
    for (std::size_t i = 0; i < argv.size(); ++i) {
      std::string a = argv[i];
      if (a.rfind("--", 0) != 0 || a.size() < 3)
        throw usage_error("unexpected argument '" + a + "' (flags start with --)");
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        set(a.substr(2, eq - 2), a.substr(eq + 1));
      } else if (i + 1 < argv.size() && argv[i + 1].rfind("--", 0) != 0) {
        set(a.substr(2), argv[++i]);
      } else {
        set(a.substr(2), "");  // a switch
      }
    }
  }

  // Declares the flags this command knows; any other flag given is an error.
  void allow(const flag_table& flags) {
    for (const qrm_cli::flag& f : flags) allowed_.insert(f.name);
    for (const auto& [k, v] : values_)
      if (!allowed_.count(k))
        throw usage_error("unknown flag --" + k + " (qrm " + command_ + " --help lists the flags)");
  }

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // A switch (--quiet); giving it a value is an error.
  bool flag(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return false;
    if (!it->second.empty()) throw usage_error("--" + name + " takes no value (got '" + it->second + "')");
    return true;
  }
  std::string str(const std::string& name, const std::string& fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    return need_value(name, it->second);
  }
  std::string required(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw usage_error("missing required flag --" + name);
    return need_value(name, it->second);
  }
  double number(const std::string& name, double fallback) const {
    if (!has(name)) return fallback;
    return parse_double(name, str(name, ""));
  }
  double required_number(const std::string& name) const { return parse_double(name, required(name)); }
  std::int64_t integer(const std::string& name, std::int64_t fallback, std::int64_t lo, std::int64_t hi) const {
    if (!has(name)) return fallback;
    const std::string v = str(name, "");
    char* end = nullptr;
    errno = 0;
    const long long x = std::strtoll(v.c_str(), &end, 10);
    if (errno != 0 || end == v.c_str() || *end != '\0')
      throw usage_error("--" + name + " needs an integer, got '" + v + "'");
    if (x < lo || x > hi)
      throw usage_error("--" + name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], got " + v);
    return x;
  }
  const std::string& command() const { return command_; }

 private:
  void set(const std::string& k, const std::string& v) {
    if (values_.count(k)) throw usage_error("--" + k + " given twice");
    values_[k] = v;
  }
  std::string need_value(const std::string& name, const std::string& v) const {
    if (v.empty()) throw usage_error("--" + name + " needs a value");
    return v;
  }
  double parse_double(const std::string& name, const std::string& v) const {
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(v.c_str(), &end);
    if (errno != 0 || end == v.c_str() || *end != '\0' || !std::isfinite(x))
      throw usage_error("--" + name + " needs a finite number, got '" + v + "'");
    return x;
  }

  std::string command_;
  std::map<std::string, std::string> values_;
  std::set<std::string> allowed_;
};

}  // namespace qrm_cli
