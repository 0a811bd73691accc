// qrm/resources/clifford_t.hpp: the logical cost of a program on a fault-tolerant machine whose
// native gates are Clifford+T.
//
// The program is lowered by qrm::decompose with Toffolis kept (circuit/decompose.hpp: single-qubit
// gates, CNOTs, Toffolis and the clean ancillas the lowering needs), and then costed:
//   - a single-qubit gate U = e^{ia} Rz(b) Ry(c) Rz(d) (ZYZ angles; when c is 0 or pi only b + d
//     or b - d matters) is Clifford when every angle that matters is a multiple of pi/2, one
//     T gate per angle that is an odd multiple of pi/4, and one arbitrary rotation per other
//     angle (angles compared to 1e-9 rad);
//   - a Toffoli costs `toffoli_t` T gates in `toffoli_t_depth` T layers: 7 in 3 (Amy, Maslov,
//     Mosca, Roetteler 2013, arXiv:1206.0758, the default) or 4 in 1 (Jones 2013,
//     arXiv:1212.5069, completing Selinger's T-depth-one construction with an extra ancilla and a
//     measurement; the ancilla is counted). Measurement-based uncomputation (an AND undone with
//     no T gate, Gidney 2018) is not exploited: every Toffoli of the lowering is charged;
//   - an arbitrary rotation to error eps costs ceil(a log2(1/eps) + b) T gates in sequence:
//       mixed_fallback (default): a = 0.53, b = 5.3 (Kliuchnikov et al. 2022, arXiv:2203.10064,
//         the rule of the Azure Quantum Resource Estimator, Beverland et al. 2022, arXiv:2211.07629);
//       ross_selinger: a = 3, b = 0 (Ross and Selinger 2016, arXiv:1403.2975: typical T-count
//         3 log2(1/eps) + O(log log(1/eps)); the O(log log) term is left out, so this undercounts
//         slightly);
//     where eps = the rotation-synthesis budget divided by the number of rotations (the errors
//     of R rotations add up to at most R eps);
//   - T-depth is the ASAP layering of the T layers above, Clifford gates taking no T layer.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "../circuit/decompose.hpp"
#include "../circuit/program.hpp"

namespace qrm {

enum class rotation_synthesis : unsigned char { mixed_fallback, ross_selinger };
enum class toffoli_costing : unsigned char { seven_t, four_t };

// clifford_t_rules: how T gates are counted (see the header comment for the sources).
struct clifford_t_rules {
  toffoli_costing toffoli = toffoli_costing::seven_t;
  rotation_synthesis synthesis = rotation_synthesis::mixed_fallback;
};

// The Clifford+T content of one program.
struct clifford_t_counts {
  std::size_t logical_qubits = 0;   // program qubits + decomposition ancillas (+1 for 4-T Toffolis)
  std::size_t cnot_count = 0;
  std::size_t cnot_depth = 0;       // ASAP layers counting CNOTs and Toffolis only
  std::size_t toffoli_count = 0;
  std::size_t clifford_1q_count = 0;  // single-qubit Clifford gates (H, S, X, ...), identities dropped
  std::size_t t_gates = 0;            // T or T^dagger appearing as such (odd multiples of pi/4)
  std::size_t rotation_count = 0;     // arbitrary rotations needing synthesis
};

// t_per_rotation(rules, eps): T gates for one arbitrary rotation to error eps in (0, 1).
template <int = 0>
inline std::uint64_t t_per_rotation(rotation_synthesis s, double eps) {
  if (!(eps > 0 && eps < 1)) throw std::invalid_argument("t_per_rotation: eps must be in (0, 1), got " + std::to_string(eps));
  const double bits = std::log2(1.0 / eps);
  const double t = s == rotation_synthesis::mixed_fallback ? 0.53 * bits + 5.3 : 3.0 * bits;
  return static_cast<std::uint64_t>(std::ceil(t));
}

// The T-count and T-depth once the rotation error is fixed.
struct t_cost {
  std::uint64_t t_per_rotation = 0;
  std::uint64_t t_count = 0;  // t_gates + toffoli_t * toffolis + t_per_rotation * rotations
  std::uint64_t t_depth = 0;
};

namespace detail {

// How many of pi/4: the integer k with |angle - k pi/4| < 1e-9, if there is one.
template <int = 0>
inline std::optional<long> quarter_pi_multiple(double angle) {
  const double q = angle / (std::numbers::pi / 4);
  const double k = std::round(q);
  if (std::abs(q - k) * (std::numbers::pi / 4) >= 1e-9) return std::nullopt;
  return static_cast<long>(k);
}

// T gates and rotations of one uncontrolled single-qubit gate (see the header comment).
struct single_qubit_cost {
  unsigned t_gates = 0, rotations = 0;
  bool clifford() const { return t_gates == 0 && rotations == 0; }
};
template <int = 0>
inline single_qubit_cost cost_of_single_qubit(const gate1& g) {
  const zyz_angles z = zyz(g);
  std::vector<double> angles;
  if (std::abs(std::sin(z.gamma / 2)) < 1e-12) {
    angles = {z.beta + z.delta};  // Rz(b) Rz(d) up to a phase
  } else if (std::abs(std::cos(z.gamma / 2)) < 1e-12) {
    angles = {z.beta - z.delta};  // Rz(b) Ry(pi) Rz(d) = Rz(b - d) Ry(pi) up to a phase
  } else {
    angles = {z.beta, z.gamma, z.delta};
  }
  single_qubit_cost c;
  for (const double a : angles) {
    const std::optional<long> k = quarter_pi_multiple(a);
    if (!k) ++c.rotations;
    else if (*k % 2 != 0) ++c.t_gates;
  }
  return c;
}

// The T layers a gate of the costed circuit occupies.
template <int = 0>
inline std::uint64_t t_layers(const op::gate1_op& g, const single_qubit_cost& one, std::uint64_t t_rotation,
                              toffoli_costing toffoli) {
  if (g.controls.size() >= 2) return toffoli == toffoli_costing::seven_t ? 3 : 1;
  if (g.controls.size() == 1) return 0;
  return one.t_gates + one.rotations * t_rotation;
}

}  // namespace detail

// clifford_t_lowering(p): p lowered to single-qubit gates, CNOTs and Toffolis.
template <int = 0>
inline program clifford_t_lowering(const program& p) {
  decompose_options o;
  o.keep_toffoli = true;
  return decompose(p, o).circuit;
}

// clifford_t_counts_of(lowered, rules): the counts of a program already lowered by clifford_t_lowering.
template <int = 0>
inline clifford_t_counts clifford_t_counts_of(const program& lowered, const clifford_t_rules& rules = {}) {
  clifford_t_counts c;
  c.logical_qubits = lowered.width();
  std::vector<std::size_t> level(lowered.width(), 0);
  for (const op::any& o : lowered.ops()) {
    const auto* g = std::get_if<op::gate1_op>(&o);
    if (g == nullptr) throw std::invalid_argument("clifford_t_counts_of: the program is not lowered (use clifford_t_lowering)");
    if (g->controls.empty()) {
      const detail::single_qubit_cost one = detail::cost_of_single_qubit(g->gate);
      c.t_gates += one.t_gates;
      c.rotation_count += one.rotations;
      if (one.clifford() && !detail::is_scalar(g->gate)) ++c.clifford_1q_count;
      continue;
    }
    (g->controls.size() == 1 ? c.cnot_count : c.toffoli_count) += 1;
    std::size_t start = level[g->target];
    for (const control& k : g->controls) start = std::max(start, level[k.qubit]);
    level[g->target] = start + 1;
    for (const control& k : g->controls) level[k.qubit] = start + 1;
  }
  c.cnot_depth = level.empty() ? 0 : *std::max_element(level.begin(), level.end());
  if (rules.toffoli == toffoli_costing::four_t && c.toffoli_count > 0) ++c.logical_qubits;
  return c;
}

// t_cost_of(lowered, counts, rules, rotation_eps): T-count and T-depth with each rotation
// synthesised to rotation_eps (ignored when there are no rotations).
template <int = 0>
inline t_cost t_cost_of(const program& lowered, const clifford_t_counts& counts, const clifford_t_rules& rules,
                        double rotation_eps) {
  t_cost t;
  t.t_per_rotation = counts.rotation_count > 0 ? t_per_rotation(rules.synthesis, rotation_eps) : 0;
  const std::uint64_t toffoli_t = rules.toffoli == toffoli_costing::seven_t ? 7 : 4;
  t.t_count = counts.t_gates + toffoli_t * counts.toffoli_count + t.t_per_rotation * counts.rotation_count;
  std::vector<std::uint64_t> level(lowered.width(), 0);
  for (const op::any& o : lowered.ops()) {
    const auto& g = std::get<op::gate1_op>(o);
    const detail::single_qubit_cost one =
        g.controls.empty() ? detail::cost_of_single_qubit(g.gate) : detail::single_qubit_cost{};
    const std::uint64_t layers = detail::t_layers(g, one, t.t_per_rotation, rules.toffoli);
    std::uint64_t start = level[g.target];
    for (const control& k : g.controls) start = std::max(start, level[k.qubit]);
    level[g.target] = start + layers;
    for (const control& k : g.controls) level[k.qubit] = start + layers;
  }
  t.t_depth = level.empty() ? 0 : *std::max_element(level.begin(), level.end());
  return t;
}

}  // namespace qrm
