// examples/qrm/cmd_estimate.cpp: `qrm estimate`, amplitude estimation of a Bernoulli amplitude
// (one qubit rotated so that P(1) = P) with any of the library's estimators.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <qrm/qrm.hpp>
#include <set>
#include <string>

#include "commands.hpp"
#include "estimator_args.hpp"

namespace qrm_cli {

namespace {

[[noreturn]] void fail(const std::string& message) {
  throw usage_error(message + " (qrm estimate --help lists the flags)");
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else
      out += c;
  }
  return out + "\"";
}

std::string num(double x) { return json_number(x); }
std::string num(std::uint64_t x) {
  return std::to_string(x);
}

}  // namespace

flag_table estimate_flags() {
  const char* g = "problem: A = Ry(2 asin sqrt P) on one qubit, good = the qubit is 1";
  const char* o = "run and output";
  flag_table f = {
      {"probability", "P", "", "the amplitude to estimate, in [0, 1] (required)", g},
      {"exact-probabilities", "", "", "use the exact outcome probabilities instead of shot frequencies", o},
      {"seed", "S", "1", "random seed, integer >= 0", o},
      {"format", "json|text", "json", "output on stdout", o},
  };
  for (const flag& e : estimator_flag_table("steps")) f.push_back(e);
  return f;
}

int cmd_estimate(args& a) {
  try {
    a.allow(estimate_flags());
  } catch (const usage_error& e) {
    fail(e.what());
  }
  double p = 0;
  std::uint64_t seed = 1;
  std::string format;
  bool exact = false;
  parsed_estimator est;
  try {
    est = parse_estimator_args(a, "estimate: ");
    if (!a.has("probability")) fail("estimate: missing required flag --probability");
    p = a.required_number("probability");
    if (!(p >= 0.0 && p <= 1.0)) fail("estimate: --probability must be in [0, 1], got " + a.str("probability", ""));
    seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
    format = a.str("format", "json");
    if (format != "json" && format != "text") fail("estimate: --format must be json or text, got '" + format + "'");
    exact = a.flag("exact-probabilities");
  } catch (const usage_error& e) {
    if (std::string(e.what()).find("--help lists") != std::string::npos) throw;
    fail(e.what());
  }
  est.settings.exact_probabilities = exact;
  qrm::analytic_oracle oracle(p);
  qrm::rng g(seed);
  const qrm::estimation_result r = qrm::estimate_amplitude(oracle, est.settings, g);
  const std::string& options = est.options_json;

  if (format == "text") {
    std::printf("estimator %s, P = %s%s\n", r.estimator.c_str(), num(p).c_str(), exact ? " (exact probabilities)" : "");
    std::printf("estimate  %s\ninterval  [%s, %s] (confidence %s)\n", num(r.estimate).c_str(),
                num(r.confidence_interval[0]).c_str(), num(r.confidence_interval[1]).c_str(),
                num(r.confidence).c_str());
    std::printf("A calls   %" PRIu64 "\nQ calls   %" PRIu64 "\nshots     %" PRIu64 "\n", r.a_calls, r.grover_calls,
                r.shots);
    if (r.check_a_calls)
      std::printf("check     %" PRIu64 " A calls (k = 0 domain check, not counted above)\n", r.check_a_calls);
    if (!r.warning.empty()) std::printf("warning   %s\n", r.warning.c_str());
    return 0;
  }
  std::string j = "{\"estimator\":" + json_string(r.estimator) + ",\"probability\":" + num(p) +
                  ",\"estimate\":" + num(r.estimate) + ",\"raw_estimate\":" + num(r.raw_estimate) +
                  ",\"confidence_interval\":[" + num(r.confidence_interval[0]) + "," + num(r.confidence_interval[1]) +
                  "],\"confidence\":" + num(r.confidence) + ",\"oracle_calls\":" + num(r.a_calls) +
                  ",\"grover_calls\":" + num(r.grover_calls) + ",\"shots\":" + num(r.shots);
  if (r.standard_error) j += ",\"standard_error\":" + num(*r.standard_error);
  if (r.check_shots) j += ",\"check_oracle_calls\":" + num(r.check_a_calls) + ",\"check_shots\":" + num(r.check_shots);
  j += ",\"exact_probabilities\":" + std::string(exact ? "true" : "false") + ",\"seed\":" + num(seed) +
       ",\"options\":{" + options + "}";
  j += ",\"rounds\":[";
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const auto& rr = r.rounds[i];
    j += std::string(i ? "," : "") + "{\"power\":" + num(rr.power) + ",\"shots\":" + num(rr.shots) +
         ",\"hits\":" + num(rr.hits);
    if (r.estimator == "qcoin") j += ",\"reference\":" + num(rr.reference);
    j += "}";
  }
  j += "]";
  if (!r.phase_counts.empty()) {
    j += ",\"phase_counts\":[";
    for (std::size_t i = 0; i < r.phase_counts.size(); ++i) j += (i ? "," : "") + num(r.phase_counts[i]);
    j += "]";
  }
  if (!r.warning.empty()) j += ",\"warning\":" + json_string(r.warning);
  j += ",\"seconds\":" + num(r.seconds) + "}";
  std::printf("%s\n", j.c_str());
  return 0;
}

}  // namespace qrm_cli
