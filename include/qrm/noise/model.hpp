// qrm/noise/model.hpp: what goes wrong on a noisy (not error-corrected) quantum computer, as the
// few numbers a hardware data sheet gives, and two named machines.
//
// A noise_model acts on a circuit of single-qubit gates and CNOTs (qrm::decompose's output):
//   - depolarizing: after every single-qubit gate, with probability p1, one of X, Y, Z (each
//     p1 / 3) on its qubit; after every CNOT, with probability p2, one of the 15 non-identity
//     two-qubit Paulis (each p2 / 15) on its two qubits (Qiskit Aer's depolarizing_error with
//     these as the error probabilities of the Pauli mixture, not its "lambda" parameter);
//   - relaxation: a qubit decays for as long as it lives on the chip, busy or idle: amplitude
//     damping gamma = 1 - exp(-t / T1) and pure dephasing (Z with probability
//     (1 - exp(-t / T_phi)) / 2, 1 / T_phi = 1 / T2 - 1 / (2 T1)), so that coherences decay as
//     exp(-t / T2) in all; t is the time the ASAP schedule with gate times t1q and t2q gives
//     (noise/channels.hpp);
//   - readout: each measured qubit reads the wrong bit with probability `readout`.
// Zero (and infinite T1, T2) switches a part off; the all-zero model is the ideal machine.
//
// Presets, order-of-magnitude figures of published devices (not one device's calibration):
//   superconducting: p1 = 1e-4, p2 = 1e-3 (the physical error the surface-code preset of
//     resources/surface_code.hpp assumes), T1 = T2 = 100 us, t1q = 50 ns, t2q = 300 ns,
//     readout 1e-2 (transmon processors of 2023-2025);
//   ion: p1 = 1e-5, p2 = 1e-4 (the ion surface-code preset), T1 = 1000 s (hyperfine qubits do not
//     decay on circuit time scales), T2 = 1 s, t1q = 10 us, t2q = 100 us, readout 1e-3.
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace qrm {

struct noise_model {
  std::string name = "custom";
  double depolarizing_1q = 0;  // p1: probability of a Pauli error after each single-qubit gate
  double depolarizing_2q = 0;  // p2: probability of a two-qubit Pauli error after each CNOT
  double t1 = std::numeric_limits<double>::infinity();  // seconds
  double t2 = std::numeric_limits<double>::infinity();  // seconds, at most 2 T1
  double time_1q = 0;                                   // seconds per single-qubit gate
  double time_2q = 0;                                   // seconds per CNOT
  double readout = 0;                                   // probability a measured bit is flipped

  bool has_relaxation() const { return std::isfinite(t1) || std::isfinite(t2); }
  // The ideal machine: every error probability 0 and no relaxation.
  template <int = 0>
  bool is_ideal() const {
    return depolarizing_1q == 0 && depolarizing_2q == 0 && readout == 0 && !has_relaxation();
  }
};

// depolarizing_noise(p1, p2): gate errors only (p2 = p1 when not given).
template <int = 0>
inline noise_model depolarizing_noise(double p1, double p2) {
  noise_model m;
  m.name = "depolarizing";
  m.depolarizing_1q = p1;
  m.depolarizing_2q = p2;
  return m;
}

// noise_preset(name): "superconducting", "ion" or "ideal" (see the header comment).
template <int = 0>
inline noise_model noise_preset(const std::string& name) {
  noise_model m;
  m.name = name;
  if (name == "ideal") return m;
  if (name == "superconducting") {
    m.depolarizing_1q = 1e-4;
    m.depolarizing_2q = 1e-3;
    m.t1 = m.t2 = 100e-6;
    m.time_1q = 50e-9;
    m.time_2q = 300e-9;
    m.readout = 1e-2;
    return m;
  }
  if (name == "ion") {
    m.depolarizing_1q = 1e-5;
    m.depolarizing_2q = 1e-4;
    m.t1 = 1000.0;
    m.t2 = 1.0;
    m.time_1q = 10e-6;
    m.time_2q = 100e-6;
    m.readout = 1e-3;
    return m;
  }
  throw std::invalid_argument("unknown noise preset '" + name + "' (superconducting, ion, ideal)");
}

// validate(model): throws std::invalid_argument naming the first bad field and its value.
template <int = 0>
inline void validate(const noise_model& m) {
  auto probability = [](double p, const char* what) {
    if (!(p >= 0.0 && p <= 1.0))
      throw std::invalid_argument(std::string(what) + " must be a probability in [0, 1], got " + std::to_string(p));
  };
  probability(m.depolarizing_1q, "single-qubit depolarizing rate");
  probability(m.depolarizing_2q, "two-qubit depolarizing rate");
  probability(m.readout, "readout error");
  auto time = [](double t, const char* what, bool infinite_ok) {
    if (!(t >= 0.0) || (!infinite_ok && !std::isfinite(t)))
      throw std::invalid_argument(std::string(what) + " must be " + (infinite_ok ? "positive" : "finite and >= 0") +
                                  " (seconds), got " + std::to_string(t));
  };
  time(m.time_1q, "single-qubit gate time", false);
  time(m.time_2q, "two-qubit gate time", false);
  time(m.t1, "T1", true);
  time(m.t2, "T2", true);
  if (m.t1 == 0 || m.t2 == 0) throw std::invalid_argument("T1 and T2 must be positive (seconds), got 0");
  if (m.t2 > 2 * m.t1)
    throw std::invalid_argument("T2 (" + std::to_string(m.t2) + " s) cannot exceed 2 T1 (" + std::to_string(2 * m.t1) +
                                " s)");
  if (m.has_relaxation() && m.time_1q == 0 && m.time_2q == 0)
    throw std::invalid_argument("T1/T2 relaxation needs gate times (both are 0, so no time passes)");
}

}  // namespace qrm
