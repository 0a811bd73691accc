// examples/qrm/cmd_estimate.cpp: `qrm estimate`, amplitude estimation of a Bernoulli amplitude
// (one qubit rotated so that P(1) = P) with any of the library's estimators.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <qrm/qrm.hpp>
#include <set>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "estimator_args.hpp"
#include "json.hpp"

namespace qrm_cli {

namespace {

[[noreturn]] void fail(const std::string& message) {
  throw usage_error(message + " (qrm estimate --help lists the flags)");
}

std::string num(double x) { return json_number(x); }

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
  qrm::estimation_result r;
  try {
    r = qrm::estimate_amplitude(oracle, est.settings, g);
  } catch (const qrm::fae_above_quarter& e) {  // said in the flags' terms
    const auto six_digits = [](double x) { return short_number(x, 6); };
    throw std::runtime_error(
        "--no-rescale: without rescale the amplitude must be at most 1/4, but " +
        (e.shots ? "a k = 0 check of " + std::to_string(e.shots) + " shots puts P(good) in [" + six_digits(e.low) + ", " +
                       six_digits(e.high) + "]"
                 : "P(good) = " + six_digits(e.low)) +
        "; drop --no-rescale");
  }
  const json_object& options = est.options;

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
  json_object j;
  j.add("estimator", r.estimator).add("probability", p).add("estimate", r.estimate).add("raw_estimate", r.raw_estimate);
  j.add("confidence_interval", json_array::of(r.confidence_interval)).add("confidence", r.confidence);
  j.add("oracle_calls", r.a_calls).add("grover_calls", r.grover_calls).add("shots", r.shots);
  if (r.standard_error) j.add("standard_error", *r.standard_error);
  if (r.check_shots) j.add("check_oracle_calls", r.check_a_calls).add("check_shots", r.check_shots);
  j.add("exact_probabilities", exact).add("seed", seed).add("options", options);
  json_array rounds;
  for (const auto& rr : r.rounds) {
    json_object round;
    round.add("power", rr.power).add("shots", rr.shots).add("hits", rr.hits);
    if (r.estimator == "qcoin") round.add("reference", rr.reference);
    rounds.push(round);
  }
  j.add("rounds", rounds);
  if (!r.phase_counts.empty()) j.add("phase_counts", json_array::of(r.phase_counts));
  if (!r.warning.empty()) j.add("warning", r.warning);
  j.add("seconds", r.seconds);
  std::printf("%s\n", j.str().c_str());
  return 0;
}

}  // namespace qrm_cli
