// tests/support/density_matrix.hpp: an exact density-matrix simulator for small noisy circuits,
// written from the channel definitions (rho -> sum_i K_i rho K_i^dagger), sharing no code with
// qrm's trajectories. The trajectory averages of qrm::noisy_oracle are checked against it.
#pragma once

#include <cmath>
#include <complex>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include <qrm/circuit/program.hpp>
#include <qrm/noise/channels.hpp>

namespace qrm_test {

class density_matrix {
 public:
  using cx = std::complex<double>;
  explicit density_matrix(unsigned n) : d_(std::uint64_t{1} << n), rho_(d_ * d_) { rho_[0] = 1; }

  cx& at(std::uint64_t r, std::uint64_t c) { return rho_[r * d_ + c]; }
  cx at(std::uint64_t r, std::uint64_t c) const { return rho_[r * d_ + c]; }

  // rho -> U rho U^dagger for the full 2^n x 2^n matrix U of a single-qubit gate with controls.
  void apply_gate(const qrm::gate1& g, qrm::qubit_index t, std::span<const qrm::control> cs) {
    apply_kraus({full(g, t, cs)});
  }

  // The Pauli channel on qubits qs: (1 - p) rho + p / (4^k - 1) sum over non-identity strings.
  void pauli_channel(const std::vector<qrm::qubit_index>& qs, double p) {
    const std::uint64_t strings = std::uint64_t{1} << (2 * qs.size());
    std::vector<cx> out(rho_.size());
    for (std::uint64_t s = 0; s < strings; ++s) {
      std::vector<cx> m = identity();
      for (std::size_t i = 0; i < qs.size(); ++i) {
        const unsigned kind = (s >> (2 * i)) & 3u;
        if (kind) m = multiply(full(kind == 1 ? qrm::gate::x() : kind == 2 ? qrm::gate::y() : qrm::gate::z(), qs[i], {}), m);
      }
      const double w = s == 0 ? 1 - p : p / static_cast<double>(strings - 1);
      const std::vector<cx> term = sandwich(m);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] += w * term[i];
    }
    rho_ = out;
  }

  // Amplitude damping: K0 = diag(1, sqrt(1 - gamma)), K1 = sqrt(gamma) |0><1|.
  void damping(qrm::qubit_index q, double gamma) {
    apply_kraus({full(qrm::gate::u(1, 0, 0, std::sqrt(1 - gamma)), q, {}), full(qrm::gate::u(0, std::sqrt(gamma), 0, 0), q, {})});
  }
  // Dephasing: Z with probability p.
  void dephasing(qrm::qubit_index q, double p) {
    apply_kraus({full(qrm::gate::u(std::sqrt(1 - p), 0, 0, std::sqrt(1 - p)), q, {}),
                 full(qrm::gate::u(std::sqrt(p), 0, 0, -std::sqrt(p)), q, {})});
  }

  // Every event of a noisy circuit whose ops are single-qubit gates with at most one control.
  void run(const qrm::noisy_circuit& c) {
    for (const qrm::noise_event& e : c.events) switch (e.kind) {
        case qrm::noise_event_kind::gate: {
          const auto& g = std::get<qrm::op::gate1_op>(c.circuit.ops()[e.op]);
          apply_gate(g.gate, g.target, g.controls);
          break;
        }
        case qrm::noise_event_kind::pauli: pauli_channel(e.qubits, e.probability); break;
        case qrm::noise_event_kind::damping: damping(e.qubits[0], e.probability); break;
        case qrm::noise_event_kind::dephasing: dephasing(e.qubits[0], e.probability); break;
      }
  }

  // P(measuring the condition's qubits reads their values), each bit misread with probability e.
  double measured(std::span<const qrm::control> cond, double e) const {
    double p = 0;
    for (std::uint64_t i = 0; i < d_; ++i) {
      double w = at(i, i).real();
      for (const auto& c : cond) w *= (((i >> c.qubit) & 1u) != 0) == c.value ? 1 - e : e;
      p += w;
    }
    return p;
  }
  double trace() const {
    double t = 0;
    for (std::uint64_t i = 0; i < d_; ++i) t += at(i, i).real();
    return t;
  }

 private:
  std::vector<cx> identity() const {
    std::vector<cx> m(d_ * d_);
    for (std::uint64_t i = 0; i < d_; ++i) m[i * d_ + i] = 1;
    return m;
  }
  // The 2^n x 2^n matrix of g on t where the controls hold, identity elsewhere.
  std::vector<cx> full(const qrm::gate1& g, qrm::qubit_index t, std::span<const qrm::control> cs) const {
    std::vector<cx> m(d_ * d_);
    for (std::uint64_t col = 0; col < d_; ++col) {
      bool on = true;
      for (const auto& c : cs) on = on && ((((col >> c.qubit) & 1u) != 0) == c.value);
      if (!on) {
        m[col * d_ + col] = 1;
        continue;
      }
      const unsigned b = (col >> t) & 1u;
      for (unsigned r = 0; r < 2; ++r) {
        const std::uint64_t row = (col & ~(std::uint64_t{1} << t)) | (std::uint64_t{r} << t);
        m[row * d_ + col] += g.m[r][b];
      }
    }
    return m;
  }
  std::vector<cx> multiply(const std::vector<cx>& a, const std::vector<cx>& b) const {
    std::vector<cx> m(d_ * d_);
    for (std::uint64_t i = 0; i < d_; ++i)
      for (std::uint64_t k = 0; k < d_; ++k)
        if (a[i * d_ + k] != cx{})
          for (std::uint64_t j = 0; j < d_; ++j) m[i * d_ + j] += a[i * d_ + k] * b[k * d_ + j];
    return m;
  }
  std::vector<cx> sandwich(const std::vector<cx>& k) const {  // K rho K^dagger
    std::vector<cx> kd(d_ * d_);
    for (std::uint64_t i = 0; i < d_; ++i)
      for (std::uint64_t j = 0; j < d_; ++j) kd[i * d_ + j] = std::conj(k[j * d_ + i]);
    return multiply(multiply(k, rho_), kd);
  }
  void apply_kraus(const std::vector<std::vector<cx>>& ks) {
    std::vector<cx> out(rho_.size());
    for (const auto& k : ks) {
      const std::vector<cx> term = sandwich(k);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] += term[i];
    }
    rho_ = out;
  }

  std::uint64_t d_;
  std::vector<cx> rho_;
};

}  // namespace qrm_test
