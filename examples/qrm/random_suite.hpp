// examples/qrm/random_suite.hpp: the random gate suite qrm simulate --random runs and
// bench_fusion times: H, Ry, CX, CCX and C^4 X on distinct random qubits, uniformly mixed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <qrm/circuit/program.hpp>
#include <qrm/support/random.hpp>
#include <utility>
#include <vector>

namespace qrm_cli {

inline qrm::program random_gate_suite(std::size_t n, std::size_t gates, std::uint64_t seed) {
  qrm::rng g(seed);
  qrm::program p(n);
  std::vector<qrm::qubit_index> q(n);
  for (std::size_t i = 0; i < gates; ++i) {
    for (std::size_t j = 0; j < n; ++j) q[j] = static_cast<qrm::qubit_index>(j);
    for (std::size_t j = 0; j < 5 && j < n; ++j) std::swap(q[j], q[j + g.below(n - j)]);
    const std::uint64_t kind = g.below(5);
    const std::size_t controls = kind == 2 ? 1 : kind == 3 ? 2 : kind == 4 ? 4 : 0;
    if (controls + 1 > n) continue;
    std::vector<qrm::control> cs;
    for (std::size_t c = 0; c < controls; ++c) cs.push_back({q[1 + c], true});
    const qrm::gate1 gate = kind == 0 ? qrm::gate::h() : kind == 1 ? qrm::gate::ry(6.283185307179586 * g.uniform())
                                                                   : qrm::gate::x();
    p.apply_gate1(gate, q[0], cs);
  }
  return p;
}

}  // namespace qrm_cli
