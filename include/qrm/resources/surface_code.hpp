// qrm/resources/surface_code.hpp: physical qubits and wall time of a Clifford+T computation on
// a surface-code machine, under a small model whose every assumption is stated here.
//
// Hardware: a physical error rate p (per gate and measurement) and the time of one syndrome-
// extraction cycle. Presets: superconducting (p = 1e-3, 1 us per cycle), ion (p = 1e-4, 100 us),
// or any values given.
//
// Model (after Beverland et al. 2022, arXiv:2211.07629, and Litinski 2019, "A Game of Surface
// Codes", arXiv:1808.02892):
//   - error budget eps: split equally between logical errors, T-state distillation and rotation
//     synthesis (in halves between the first two when the circuit has no rotations);
//   - a distance-d logical qubit fails per logical cycle (d syndrome cycles) with probability
//     P_L(d) = 0.03 (p / 0.01)^((d+1)/2) (the fit of Fowler et al. 2012 used by Beverland et al.);
//   - layout: Q logical qubits need Q_layout = 2 Q + ceil(sqrt(8 Q)) + 1 patches with routing
//     space (Beverland et al.), each of 2 d^2 physical qubits;
//   - time: Pauli-based computation (Litinski): Clifford gates are absorbed, every T state is
//     consumed in one logical cycle, one after another, so a run takes T-count logical cycles
//     (a conservative bound: no two T gates in the same cycle);
//   - code distance: the smallest odd d >= 3 with Q_layout * cycles * P_L(d) <= eps_logical;
//   - T states: 15-to-1 distillation (Bravyi and Kitaev 2005), output error 35 p_in^3 from input
//     error p_in, starting from p (injection); levels are added until the output error is at most
//     eps_distillation / T-count. A 15-to-1 unit occupies 11 patches for 11 logical cycles
//     (Litinski 2019); to supply one T state per logical cycle, level k of L has 11 * 15^(L-k)
//     units, all at the data's distance d (real factories use smaller distances at low levels:
//     this overcounts them).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace qrm {

// hardware: a physical error rate and a syndrome-cycle time.
struct hardware {
  std::string name = "superconducting";
  double physical_error = 1e-3;
  double cycle_seconds = 1e-6;
};

// hardware_preset(name): "superconducting" or "ion".
template <int = 0>
inline hardware hardware_preset(const std::string& name) {
  if (name == "superconducting") return {name, 1e-3, 1e-6};
  if (name == "ion") return {name, 1e-4, 100e-6};
  throw std::invalid_argument("unknown hardware preset '" + name + "' (superconducting, ion)");
}

// The error budget and what one run of a circuit needs.
struct surface_code_plan {
  double eps_logical = 0, eps_distillation = 0, eps_synthesis = 0;
  unsigned code_distance = 0;
  std::uint64_t layout_qubits = 0;     // logical patches with routing
  std::uint64_t logical_cycles = 0;    // = T-count (one T state per cycle)
  unsigned distillation_levels = 0;    // 15-to-1 levels (0: no T gates)
  double t_state_error = 0;            // output error of the last level
  std::uint64_t factory_units = 0;     // 15-to-1 units in all levels
  std::uint64_t data_physical_qubits = 0;
  std::uint64_t factory_physical_qubits = 0;
  std::uint64_t physical_qubits = 0;
  double seconds_per_logical_cycle = 0;
  double seconds = 0;                  // one run: logical_cycles * d * cycle time
};

// P_L(d) for physical error p.
template <int = 0>
inline double logical_error_per_cycle(double p, unsigned d) {
  return 0.03 * std::pow(p / 0.01, (static_cast<double>(d) + 1) / 2);
}

// error_split(eps, has_rotations): {logical, distillation, synthesis}.
struct error_split {
  double logical, distillation, synthesis;
};
template <int = 0>
inline error_split split_error_budget(double eps, bool has_rotations) {
  if (!(eps > 0 && eps < 1)) throw std::invalid_argument("error budget must be in (0, 1), got " + std::to_string(eps));
  return has_rotations ? error_split{eps / 3, eps / 3, eps / 3} : error_split{eps / 2, eps / 2, 0};
}

// plan_surface_code(hw, logical_qubits, t_count, split): the plan for one run of a circuit.
template <int = 0>
inline surface_code_plan plan_surface_code(const hardware& hw, std::uint64_t logical_qubits, std::uint64_t t_count,
                                           const error_split& split) {
  if (!(hw.physical_error > 0 && hw.physical_error < 0.01))
    throw std::invalid_argument("physical error rate must be in (0, 0.01) (below the surface code's threshold), got " +
                                std::to_string(hw.physical_error));
  if (!(hw.cycle_seconds > 0 && std::isfinite(hw.cycle_seconds)))
    throw std::invalid_argument("cycle time must be positive, got " + std::to_string(hw.cycle_seconds));
  surface_code_plan s;
  s.eps_logical = split.logical;
  s.eps_distillation = split.distillation;
  s.eps_synthesis = split.synthesis;
  const auto q = static_cast<double>(logical_qubits);
  s.layout_qubits = 2 * logical_qubits + static_cast<std::uint64_t>(std::ceil(std::sqrt(8 * q))) + 1;
  s.logical_cycles = std::max<std::uint64_t>(t_count, 1);  // a circuit without T gates still takes a cycle
  const double volume = static_cast<double>(s.layout_qubits) * static_cast<double>(s.logical_cycles);
  for (s.code_distance = 3; volume * logical_error_per_cycle(hw.physical_error, s.code_distance) > split.logical;
       s.code_distance += 2)
    if (s.code_distance > 999) throw std::invalid_argument("no code distance below 1000 meets the error budget");
  const std::uint64_t d = s.code_distance, patch = 2 * d * d;
  s.data_physical_qubits = s.layout_qubits * patch;
  if (t_count > 0) {
    const double target = split.distillation / static_cast<double>(t_count);
    s.t_state_error = hw.physical_error;
    while (s.t_state_error > target) {
      s.t_state_error = 35 * s.t_state_error * s.t_state_error * s.t_state_error;
      if (++s.distillation_levels > 10) throw std::invalid_argument("T-state distillation does not converge");
    }
    // A T count so small that injected states already meet the budget still gets one level: an
    // injected state is not fault tolerant.
    if (s.distillation_levels == 0) {
      s.distillation_levels = 1;
      s.t_state_error = 35 * std::pow(hw.physical_error, 3);
    }
    std::uint64_t units_at_level = 11;  // the last level: 11 units give one state per cycle
    for (unsigned k = 0; k < s.distillation_levels; ++k, units_at_level *= 15) s.factory_units += units_at_level;
    s.factory_physical_qubits = s.factory_units * 11 * patch;
  }
  s.physical_qubits = s.data_physical_qubits + s.factory_physical_qubits;
  s.seconds_per_logical_cycle = static_cast<double>(d) * hw.cycle_seconds;
  s.seconds = static_cast<double>(s.logical_cycles) * s.seconds_per_logical_cycle;
  return s;
}

}  // namespace qrm
