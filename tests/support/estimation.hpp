// tests/support/estimation.hpp: random real estimation problems and a uniform way to run every
// estimator, for the amplitude-estimation tests.
#pragma once

#include <cstdint>
#include <qrm/qrm.hpp>
#include <string>
#include <vector>

#include "random_ops.hpp"

namespace qrm_test {

// A random real circuit on n qubits (Ry layers, CNOTs, controlled Ry, H, random orthogonal
// two-qubit blocks); good = the last qubit ("out") is 1, plus `extra_condition` (qubit 0 is 0).
inline qrm::estimation_problem random_real_problem(std::size_t n, qrm::rng& g, bool extra_condition = false) {
  qrm::estimation_problem e{qrm::program(n), {qrm::control{static_cast<qrm::qubit_index>(n - 1), true}}};
  auto q = [&](std::size_t below) { return static_cast<qrm::qubit_index>(g.below(below)); };
  for (int layer = 0; layer < 3; ++layer) {
    for (qrm::qubit_index i = 0; i < n; ++i) e.a.apply_gate1(qrm::gate::ry(6.28 * g.uniform()), i, {});
    for (int j = 0; j < 4; ++j) {
      const qrm::qubit_index c = q(n), t = static_cast<qrm::qubit_index>((c + 1 + q(n - 1)) % n);
      const qrm::control ctl{c, g.uniform() < 0.5};
      if (j % 2 == 0)
        e.a.apply_gate1(qrm::gate::x(), t, std::span<const qrm::control>(&ctl, 1));
      else
        e.a.apply_gate1(qrm::gate::ry(3.0 * g.uniform()), t, std::span<const qrm::control>(&ctl, 1));
    }
    e.a.apply_gate1(qrm::gate::h(), q(n), {});
    const qrm::qubit_index u0 = q(n), u1 = static_cast<qrm::qubit_index>((u0 + 1 + q(n - 1)) % n);
    const qrm::qubit_index targets[] = {u0, u1};
    e.a.apply_unitary(random_unitary(2, g, false), targets, {});
  }
  if (extra_condition) e.good.push_back({0, false});
  return e;
}

using dense_real = qrm::state_vector<double>;
using simulated = qrm::simulated_oracle<dense_real>;

// Every estimator behind one name, with options suited to tests; `alpha` sets the interval level
// of all of them (FAE: delta = alpha / (2 maxiter), so its union bound is at most alpha).
template <class O>
qrm::estimation_result run_named(const std::string& name, O& o, qrm::rng& g, bool exact, double alpha) {
  if (name == "fae") {
    qrm::fae_options opt;
    opt.maxiter = 5;
    opt.delta = alpha / (2.0 * opt.maxiter);
    opt.exact_probabilities = exact;
    return qrm::faster_amplitude_estimation(o, opt, g);
  }
  if (name == "iqae") {
    qrm::iqae_options opt;
    opt.alpha = alpha;
    opt.epsilon = 0.005;
    opt.exact_probabilities = exact;
    return qrm::iterative_amplitude_estimation(o, opt, g);
  }
  if (name == "iqae_ch") {
    qrm::iqae_options opt;
    opt.alpha = alpha;
    opt.epsilon = 0.005;
    opt.interval = qrm::iqae_interval::chernoff_hoeffding;
    opt.exact_probabilities = exact;
    return qrm::iterative_amplitude_estimation(o, opt, g);
  }
  if (name == "mlae") {
    qrm::mlae_options opt;
    opt.alpha = alpha;
    opt.exact_probabilities = exact;
    return qrm::maximum_likelihood_amplitude_estimation(o, opt, g);
  }
  if (name == "mlae_linear") {
    qrm::mlae_options opt;
    opt.alpha = alpha;
    opt.schedule = qrm::mlae_schedule::linear;
    opt.m = 8;
    opt.exact_probabilities = exact;
    return qrm::maximum_likelihood_amplitude_estimation(o, opt, g);
  }
  if (name == "canonical") {
    qrm::canonical_options opt;
    opt.alpha = alpha;
    opt.exact_probabilities = exact;
    return qrm::canonical_amplitude_estimation(o, opt, g);
  }
  if (name == "qcoin") {
    qrm::qcoin_options opt;
    opt.alpha = alpha;
    opt.exact_probabilities = exact;
    return qrm::quantum_coin_estimation(o, opt, g);
  }
  qrm::monte_carlo_options opt;
  opt.alpha = alpha;
  opt.exact_probabilities = exact;
  return qrm::monte_carlo_estimation(o, opt, g);
}

inline const std::vector<std::string>& estimator_names() {
  static const std::vector<std::string> names{"fae",         "iqae",      "iqae_ch", "mlae",
                                              "mlae_linear", "canonical", "qcoin",   "mc"};
  return names;
}

}  // namespace qrm_test
