// qrm/noise/channels.hpp: a circuit with its noise written out as a list of events (gates and
// the channels that follow them), at two levels of detail.
//
//   gate_level_noise(decomposed, model)  the noise_model on a program of single-qubit gates and
//       CNOTs (qrm::decompose's output): a Pauli channel after every gate, and relaxation
//       (amplitude damping + dephasing) for the time each qubit spends on the chip. Time comes from
//       an ASAP schedule with the model's gate times, kept in program order: an op starts when the
//       last of its qubits is free; before it, each of its qubits relaxes for the time it waited
//       idle, and for the gate's own duration after it; at the end every qubit relaxes until the
//       last one is done. A qubit relaxes only once an op has touched it (before, it is |0>, which
//       neither damping nor dephasing changes).
//   logical_level_noise(program, model)  a cheaper model on the logical circuit: each op is
//       followed by one Pauli channel on all its qubits (targets, selects, controls) whose error
//       probability is what its decomposition implies, 1 - (1 - p1)^n1 (1 - p2)^n2 for n1
//       single-qubit gates and n2 CNOTs. It ignores the ancillas the decomposition adds (errors on
//       them that spread to data qubits) and how errors inside the decomposition propagate, and it
//       has no relaxation (a model with T1/T2 is rejected).
// A Pauli channel on k qubits applies, with its probability, one of the 4^k - 1 non-identity
// Pauli strings, uniformly.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/decompose.hpp"
#include "../circuit/program.hpp"
#include "model.hpp"

namespace qrm {

enum class noise_event_kind : unsigned char { gate, pauli, damping, dephasing };

struct noise_event {
  noise_event_kind kind = noise_event_kind::gate;
  std::uint32_t op = 0;             // gate: index into noisy_circuit::circuit.ops()
  std::vector<qubit_index> qubits;  // pauli: the channel's qubits; damping, dephasing: one qubit
  double probability = 0;           // pauli: error probability; damping: gamma; dephasing: P(Z)
};

// noisy_circuit: a program and the events that run it with noise, in order.
struct noisy_circuit {
  program circuit;
  std::vector<noise_event> events;
  double seconds = 0;  // the schedule's length (0 without gate times)

  std::size_t width() const { return circuit.width(); }
};

namespace detail {
// Relaxation of one qubit for t seconds under the model, appended to `out`.
template <int = 0>
inline void push_relaxation(std::vector<noise_event>& out, const noise_model& m, qubit_index q, double t) {
  if (!(t > 0)) return;
  if (std::isfinite(m.t1)) {
    const double gamma = -std::expm1(-t / m.t1);
    if (gamma > 0) out.push_back({noise_event_kind::damping, 0, {q}, gamma});
  }
  const double dephasing_rate = (std::isfinite(m.t2) ? 1.0 / m.t2 : 0.0) - (std::isfinite(m.t1) ? 0.5 / m.t1 : 0.0);
  if (dephasing_rate > 0) {
    const double pz = -std::expm1(-t * dephasing_rate) / 2;
    if (pz > 0) out.push_back({noise_event_kind::dephasing, 0, {q}, pz});
  }
}
}  // namespace detail

// gate_level_noise(decomposed, model): see the header comment. Throws std::invalid_argument for an
// op that is not a single-qubit gate or a CNOT (decompose the program first) or a bad model.
template <int = 0>
inline noisy_circuit gate_level_noise(const program& decomposed, const noise_model& m) {
  validate(m);
  noisy_circuit nc{decomposed, {}, 0};
  const std::size_t w = decomposed.width();
  std::vector<double> free_at(w, -1.0);  // -1: not touched yet
  const auto& ops = decomposed.ops();
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const auto* g = std::get_if<op::gate1_op>(&ops[i]);
    if (!g || g->controls.size() > 1)
      throw std::invalid_argument("gate_level_noise: op " + std::to_string(i) +
                                  " is not a single-qubit gate or a CNOT (decompose the program first)");
    std::vector<qubit_index> qs{g->target};
    if (!g->controls.empty()) qs.push_back(g->controls[0].qubit);
    const double duration = qs.size() == 1 ? m.time_1q : m.time_2q;
    double start = 0;
    for (qubit_index q : qs) start = std::max(start, free_at[q]);
    for (qubit_index q : qs)
      if (free_at[q] >= 0) detail::push_relaxation(nc.events, m, q, start - free_at[q]);
    nc.events.push_back({noise_event_kind::gate, static_cast<std::uint32_t>(i), {}, 0});
    const double p = qs.size() == 1 ? m.depolarizing_1q : m.depolarizing_2q;
    if (p > 0) nc.events.push_back({noise_event_kind::pauli, 0, qs, p});
    for (qubit_index q : qs) {
      detail::push_relaxation(nc.events, m, q, duration);
      free_at[q] = start + duration;
    }
  }
  const double end = w ? *std::max_element(free_at.begin(), free_at.end()) : 0.0;
  nc.seconds = std::max(end, 0.0);
  for (qubit_index q = 0; q < w; ++q)
    if (free_at[q] >= 0) detail::push_relaxation(nc.events, m, q, end - free_at[q]);
  return nc;
}

// The error probability a decomposition with n1 single-qubit gates and n2 CNOTs implies.
template <int = 0>
inline double implied_error(const noise_model& m, std::size_t n1, std::size_t n2) {
  return -std::expm1(static_cast<double>(n1) * std::log1p(-m.depolarizing_1q) +
                     static_cast<double>(n2) * std::log1p(-m.depolarizing_2q));
}

// logical_level_noise(program, model, options): see the header comment; `options` are the
// decomposition whose gate counts set each op's rate.
template <int = 0>
inline noisy_circuit logical_level_noise(const program& p, const noise_model& m, decompose_options options = {}) {
  validate(m);
  if (m.has_relaxation())
    throw std::invalid_argument("the logical noise model has no T1/T2 relaxation; use the gate-level model");
  noisy_circuit nc{p, {}, 0};
  const auto& ops = p.ops();
  for (std::size_t i = 0; i < ops.size(); ++i) {
    nc.events.push_back({noise_event_kind::gate, static_cast<std::uint32_t>(i), {}, 0});
    std::vector<qubit_index> qs = op_qubits(ops[i]);
    std::sort(qs.begin(), qs.end());
    qs.erase(std::unique(qs.begin(), qs.end()), qs.end());
    if (qs.size() > 31)
      throw std::invalid_argument("logical_level_noise: op " + std::to_string(i) + " acts on " +
                                  std::to_string(qs.size()) + " qubits (at most 31)");
    program one(p.width());
    one.push(ops[i]);
    const decomposed_counts c = decomposed_metrics(one, options);
    const double rate = implied_error(m, c.single_qubit_count, c.cnot_count + 6 * c.toffoli_count);
    if (rate > 0) nc.events.push_back({noise_event_kind::pauli, 0, std::move(qs), rate});
  }
  return nc;
}

}  // namespace qrm
