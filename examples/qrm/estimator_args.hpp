// examples/qrm/estimator_args.hpp: the estimator flags shared by `qrm estimate` and `qrm render`:
// --estimator NAME and each estimator's own options, range-checked. A flag that belongs to
// another estimator is an error, not silently ignored.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>

#include <qrm/estimation/estimator.hpp>

#include "args.hpp"
#include "json.hpp"

namespace qrm_cli {

// The estimator flags, for a command's flag table. `qcoin_steps` names qcoin's step count (render
// has its own --steps).
inline flag_table estimator_flag_table(const char* qcoin_steps) {
  const char* g = "amplitude estimation (a flag of another estimator is an error)";
  return {
      {"estimator", "fae|iqae|mlae|canonical|qcoin|mc|chebae", "fae", "the amplitude estimator", g},
      {"delta", "D", "0.01", "fae: failure probability of each Chernoff interval, in (0, 1)", g},
      {"maxiter", "L", "5", "fae: rounds (1..40); the largest Grover power is 2^(L-1)", g},
      {"rescale", "", "on", "fae: rescale the amplitude (the paper's setting)", g},
      {"no-rescale", "", "", "fae: do not rescale", g},
      {"epsilon", "E", "0.01", "iqae, chebae: target half-width of the interval, in (0, 0.5]", g},
      {"alpha", "A", "0.05", "iqae, mlae, canonical, qcoin, mc, chebae: the interval fails with probability <= A", g},
      {"shots", "N", "100 (mc: 1000)",
       "shots per round (iqae), per power (mlae), per step (qcoin), per early batch (chebae), in all (canonical, mc)", g},
      {"interval", "cp|ch", "cp", "iqae: Clopper-Pearson or Chernoff-Hoeffding intervals", g},
      {"schedule", "exponential|linear", "exponential", "mlae: Grover powers 0, 2^0..2^(M-1) or 0, 1..M", g},
      {"m", "M", "5", "mlae: the number of powers (exponential: M <= 30; linear: M <= 256)", g},
      {"evaluation-qubits", "M", "5", "canonical: phase-estimation qubits, 1..12", g},
      {qcoin_steps, "K", "4", "qcoin: steps (Grover counts 0, 1, 2, .., 2^(K-2)), 1..16", g},
  };
}

struct parsed_estimator {
  qrm::estimator_settings settings;
  json_object options;  // the options used (without the estimator's name)
  // json(): {"estimator": name, options...}.
  json_object json() const {
    json_object j;
    j.add("estimator", qrm::estimator_name(settings.kind));
    return j.add_members(options);
  }
};

// parse_estimator_args(a, prefix, fallback): the settings named by --estimator (default
// `fallback`). `prefix` starts every message ("estimate: ").
inline parsed_estimator parse_estimator_args(args& a, const std::string& prefix, const std::string& fallback = "fae",
                                             const std::string& coin_steps_flag = "steps") {
  const std::string name = a.str("estimator", fallback);
  static const std::set<std::string> names{"fae", "iqae", "mlae", "canonical", "qcoin", "mc", "chebae"};
  if (!names.count(name))
    throw usage_error(prefix + "--estimator must be one of fae, iqae, mlae, canonical, qcoin, mc, chebae; got '" + name +
                      "'");
  const std::set<std::string> own = [&]() -> std::set<std::string> {
    if (name == "fae") return {"delta", "maxiter", "rescale", "no-rescale"};
    if (name == "iqae") return {"epsilon", "alpha", "shots", "interval"};
    if (name == "mlae") return {"alpha", "shots", "schedule", "m"};
    if (name == "canonical") return {"alpha", "shots", "evaluation-qubits"};
    if (name == "qcoin") return {"alpha", "shots", coin_steps_flag};
    if (name == "chebae") return {"epsilon", "alpha", "shots"};
    return {"alpha", "shots"};
  }();
  for (const std::string f : {"delta", "maxiter", "rescale", "no-rescale", "epsilon", "alpha", "shots", "interval",
                              "schedule", "m", "evaluation-qubits", coin_steps_flag.c_str()})
    if (a.has(f) && !own.count(f)) throw usage_error(prefix + "--" + f + " does not apply to --estimator " + name);

  auto number_in = [&](const char* flag, double fallback_value, double lo, double hi, bool open_lo, bool open_hi) {
    const double x = a.number(flag, fallback_value);
    const bool ok = (open_lo ? x > lo : x >= lo) && (open_hi ? x < hi : x <= hi);
    if (!ok)
      throw usage_error(prefix + "--" + flag + " must be in " + (open_lo ? "(" : "[") + json_number(lo) + ", " +
                        json_number(hi) + (open_hi ? ")" : "]") + ", got " + a.str(flag, ""));
    return x;
  };
  auto integer_in = [&](const std::string& flag, std::int64_t fallback_value, std::int64_t lo, std::int64_t hi) {
    return a.integer(flag, fallback_value, lo, hi);
  };
  auto word = [&](const char* flag, const std::string& fallback_value, std::initializer_list<const char*> allowed) {
    const std::string v = a.str(flag, fallback_value);
    std::string list;
    for (const char* w : allowed) {
      if (v == w) return v;
      list += (list.empty() ? "" : ", ") + std::string(w);
    }
    throw usage_error(prefix + "--" + flag + " must be one of " + list + "; got '" + v + "'");
  };
  constexpr std::int64_t max_shots = 1000000000000;

  parsed_estimator p;
  qrm::estimator_settings& s = p.settings;
  s.kind = qrm::estimator_from_name(name);
  json_object& options = p.options;
  if (name == "fae") {
    auto& o = s.fae;
    o.delta = number_in("delta", o.delta, 0.0, 1.0, true, true);
    o.maxiter = static_cast<unsigned>(integer_in("maxiter", o.maxiter, 1, 40));
    const bool yes = a.flag("rescale"), no = a.flag("no-rescale");
    if (yes && no) throw usage_error(prefix + "give either --rescale or --no-rescale, not both");
    o.rescale = !no;
    options.add("delta", o.delta).add("maxiter", o.maxiter).add("rescale", o.rescale);
  } else if (name == "iqae") {
    auto& o = s.iqae;
    o.epsilon = number_in("epsilon", o.epsilon, 0.0, 0.5, true, false);
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots = static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots), 1, max_shots));
    o.interval = word("interval", "cp", {"cp", "ch"}) == "cp" ? qrm::iqae_interval::clopper_pearson
                                                              : qrm::iqae_interval::chernoff_hoeffding;
    options.add("epsilon", o.epsilon).add("alpha", o.alpha).add("shots_per_round", o.shots);
    options.add("interval", o.interval == qrm::iqae_interval::clopper_pearson ? "cp" : "ch");
  } else if (name == "mlae") {
    auto& o = s.mlae;
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots = static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots), 1, max_shots));
    o.schedule = word("schedule", "exponential", {"exponential", "linear"}) == "linear" ? qrm::mlae_schedule::linear
                                                                                        : qrm::mlae_schedule::exponential;
    o.m = static_cast<unsigned>(integer_in("m", o.m, 0, o.schedule == qrm::mlae_schedule::linear ? 256 : 30));
    options.add("alpha", o.alpha).add("shots_per_power", o.shots);
    options.add("schedule", o.schedule == qrm::mlae_schedule::linear ? "linear" : "exponential").add("m", o.m);
  } else if (name == "canonical") {
    auto& o = s.canonical;
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots = static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots), 1, max_shots));
    o.evaluation_qubits = static_cast<unsigned>(integer_in("evaluation-qubits", o.evaluation_qubits, 1, 12));
    options.add("alpha", o.alpha).add("shots", o.shots).add("evaluation_qubits", o.evaluation_qubits);
  } else if (name == "qcoin") {
    auto& o = s.qcoin;
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots_per_step =
        static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots_per_step), 1, max_shots));
    o.steps = static_cast<unsigned>(integer_in(coin_steps_flag, o.steps, 1, 16));
    options.add("alpha", o.alpha).add("shots_per_step", o.shots_per_step).add("steps", o.steps);
  } else if (name == "chebae") {
    auto& o = s.chebae;
    o.epsilon = number_in("epsilon", o.epsilon, 0.0, 0.5, true, false);
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots = static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots), 1, 100000));
    options.add("epsilon", o.epsilon).add("alpha", o.alpha).add("shots_per_batch", o.shots);
  } else {
    auto& o = s.mc;
    o.alpha = number_in("alpha", o.alpha, 0.0, 1.0, true, true);
    o.shots = static_cast<std::uint64_t>(integer_in("shots", static_cast<std::int64_t>(o.shots), 1, max_shots));
    options.add("alpha", o.alpha).add("shots", o.shots);
  }
  return p;
}

}  // namespace qrm_cli
