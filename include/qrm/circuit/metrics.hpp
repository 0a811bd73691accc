// qrm/circuit/metrics.hpp: run-time metrics of a program: width, qubits touched, logical depth and gate
// counts by kind.
//
// Conventions (the paper's logical circuit, Section 6): a multi-controlled gate is one gate; a
// multiplexed gate is one gate per entry (one per voxel), all on the same qubits, so each entry
// is one layer; a dense k-qubit matrix is one gate; add-a-constant is one gate. Depth is the
// ASAP layering: a gate starts after the last gate on any of its qubits.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "program.hpp"

namespace qrm {

struct circuit_metrics {
  std::size_t width = 0;           // qubits of the program
  std::size_t qubits_touched = 0;  // qubits some op uses
  std::size_t logical_depth = 0;   // ASAP layers, conventions above
  std::size_t gate_count = 0;      // logical gates, conventions above
  std::size_t ops = 0;             // primitive ops (a multiplexed op counts once)
  std::size_t max_controls = 0;    // largest number of control (and select) qubits of one gate
  std::map<std::string, std::size_t> by_kind;  // e.g. "x", "cx", "mcx", "ry", "mux_ry", "unitary", "mux_unitary", "add"
};

namespace detail {
// Name of a single-qubit gate with c controls: "x", "cx", "mcx", "ry", "c-ry", "mc-ry", ...
template <int = 0>
inline std::string controlled_name(const std::string& base, std::size_t controls) {
  if (controls == 0) return base;
  if (base == "x") return controls == 1 ? "cx" : "mcx";
  if (base == "z") return controls == 1 ? "cz" : "mcz";
  return (controls == 1 ? "c-" : "mc-") + base;
}
}  // namespace detail

// circuit_metrics_of(p): the metrics of program p.
template <int = 0>
inline circuit_metrics circuit_metrics_of(const program& p) {
  circuit_metrics m;
  m.width = p.width();
  std::vector<std::size_t> level(p.width(), 0);
  std::vector<bool> used(p.width(), false);
  for (const op::any& o : p.ops()) {
    const std::vector<qubit_index> qs = op_qubits(o);
    std::size_t layers = 1, controls = 0;
    std::string kind;
    visit_op(o, [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          controls = x.controls.size();
          if constexpr (std::is_same_v<T, op::gate1_op>) {
            kind = detail::controlled_name(std::string(gate1_name(x.gate.kind)), controls);
          } else if constexpr (std::is_same_v<T, op::unitary_op>) {
            kind = detail::controlled_name("unitary", controls);
          } else if constexpr (std::is_same_v<T, op::add_op>) {
            kind = detail::controlled_name("add", controls);
          } else if constexpr (std::is_same_v<T, op::mux1_op>) {
            const bool all_ry = std::all_of(x.entries.begin(), x.entries.end(),
                                            [](const mux1_entry& e) { return e.gate.kind == gate1_kind::ry; });
            kind = all_ry ? "mux_ry" : "mux_u";
            layers = x.entries.size();
            controls += x.select.size();
          } else {
            kind = "mux_unitary";
            layers = x.entries.size();
            controls += x.select.size();
          }
        });
    if (layers == 0) continue;
    ++m.ops;
    m.gate_count += layers;
    m.by_kind[kind] += layers;
    m.max_controls = std::max(m.max_controls, controls);
    std::size_t start = 0;
    for (qubit_index q : qs) start = std::max(start, level[q]);
    for (qubit_index q : qs) {
      level[q] = start + layers;
      used[q] = true;
    }
  }
  m.logical_depth = level.empty() ? 0 : *std::max_element(level.begin(), level.end());
  m.qubits_touched = static_cast<std::size_t>(std::count(used.begin(), used.end(), true));
  return m;
}

}  // namespace qrm
