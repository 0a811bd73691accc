// qrm/resources/amplitude_estimate.hpp: what one amplitude estimate would cost on a surface-code
// machine: the Clifford+T content of A and of the Grover iterate Q (clifford_t.hpp), one code
// distance and factory for the longest circuit the estimate runs (Q^k A with the largest k; all
// shorter runs fit the same plan), and the wall time of all its shots, one after another:
//   seconds = shots * t(A) + grover_calls * t(Q),
// with t(C) = T-count(C) logical cycles (surface_code.hpp), shots and Grover calls as the
// estimator reports them (estimation_result). The rotation-synthesis budget is shared by the
// rotations of the longest run.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "../circuit/program.hpp"
#include "../estimation/estimator.hpp"
#include "../estimation/grover.hpp"
#include "../estimation/problem.hpp"
#include "../estimation/result.hpp"
#include "clifford_t.hpp"
#include "surface_code.hpp"

namespace qrm {

// The Clifford+T content and T cost of one circuit.
struct circuit_cost {
  clifford_t_counts counts;
  t_cost t;
  double seconds = 0;  // one application on the planned machine
};

struct estimate_cost {
  circuit_cost a, q;            // A and the Grover iterate Q = A S0 A^dagger S_chi
  std::uint64_t max_power = 0;  // the largest Grover power of the estimate
  std::uint64_t shots = 0, grover_calls = 0;
  double rotation_eps = 0;      // synthesis error allowed per rotation
  surface_code_plan plan;       // for Q^max_power A
  double seconds = 0;           // the whole estimate
};

// runs_rescaled(settings): whether the estimator runs A with FAE's rescaling ancilla (fae.hpp).
template <int = 0>
inline bool runs_rescaled(const estimator_settings& settings) {
  return settings.kind == estimator_kind::fae && settings.fae.rescale;
}

// problem_as_run(problem, settings): the circuit the estimator actually runs.
template <int = 0>
inline estimation_problem problem_as_run(const estimation_problem& problem, const estimator_settings& settings) {
  return runs_rescaled(settings) ? rescaled_problem(problem, fae_rescale_scale) : problem;
}

// estimate_circuits: A and Q of a problem lowered to Clifford+T once, for costing many
// estimates of the same problem (their counts do not depend on the estimate).
struct estimate_circuits {
  program a, q;
  clifford_t_counts a_counts, q_counts;
};

// lower_estimate_circuits(problem, rules): A and Q = A S0 A^dagger S_chi, lowered and counted.
template <int = 0>
inline estimate_circuits lower_estimate_circuits(const estimation_problem& problem, const clifford_t_rules& rules) {
  estimate_circuits c{clifford_t_lowering(problem.a), clifford_t_lowering(grover_operator(problem)), {}, {}};
  c.a_counts = clifford_t_counts_of(c.a, rules);
  c.q_counts = clifford_t_counts_of(c.q, rules);
  return c;
}

// cost_of_estimate(circuits, shots, grover_calls, max_power, rules, hw, error_budget): an
// estimate of `shots` runs of Q^k A with k summing to grover_calls and at most max_power.
template <int = 0>
inline estimate_cost cost_of_estimate(const estimate_circuits& c, double shots, double grover_calls,
                                      std::uint64_t max_power, const clifford_t_rules& rules, const hardware& hw,
                                      double error_budget) {
  estimate_cost e;
  e.a.counts = c.a_counts;
  e.q.counts = c.q_counts;
  e.max_power = max_power;
  e.shots = static_cast<std::uint64_t>(std::llround(shots));
  e.grover_calls = static_cast<std::uint64_t>(std::llround(grover_calls));
  const std::uint64_t rotations = e.a.counts.rotation_count + e.max_power * e.q.counts.rotation_count;
  const error_split split = split_error_budget(error_budget, rotations > 0);
  e.rotation_eps = rotations > 0 ? split.synthesis / static_cast<double>(rotations) : 0;
  e.a.t = t_cost_of(c.a, e.a.counts, rules, e.rotation_eps);
  e.q.t = t_cost_of(c.q, e.q.counts, rules, e.rotation_eps);
  const std::uint64_t qubits = std::max(e.a.counts.logical_qubits, e.q.counts.logical_qubits);
  e.plan = plan_surface_code(hw, qubits, e.a.t.t_count + e.max_power * e.q.t.t_count, split);
  e.a.seconds = static_cast<double>(std::max<std::uint64_t>(e.a.t.t_count, 1)) * e.plan.seconds_per_logical_cycle;
  e.q.seconds = static_cast<double>(std::max<std::uint64_t>(e.q.t.t_count, 1)) * e.plan.seconds_per_logical_cycle;
  e.seconds = shots * e.a.seconds + grover_calls * e.q.seconds;
  return e;
}

// cost_of_estimate(problem, result, rules, hw, error_budget): the estimate `result` (as
// estimate_amplitude returns it) of `problem`.
template <int = 0>
inline estimate_cost cost_of_estimate(const estimation_problem& problem, const estimation_result& result,
                                      const clifford_t_rules& rules, const hardware& hw, double error_budget) {
  std::uint64_t max_power = 0;
  for (const round_record& r : result.rounds) max_power = std::max(max_power, r.power);
  return cost_of_estimate(lower_estimate_circuits(problem, rules), static_cast<double>(result.shots),
                          static_cast<double>(result.grover_calls), max_power, rules, hw, error_budget);
}

}  // namespace qrm
