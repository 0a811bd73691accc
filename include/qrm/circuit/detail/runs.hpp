// qrm/circuit/detail/runs.hpp: a program cut into runs of ops whose moving qubits fit a set of m.
//
// Ops whose moving qubits (targets, added bits, select qubits; not controls) all lie in a set L
// never mix amplitudes whose bits outside L differ, so a run of them can be applied to a
// cache-sized chunk of the state at a time (backends/detail/dense_blocked.hpp), and a fused block
// kept inside one run adds no trip to memory (circuit/fuse.hpp, fusion_options::chunk_qubits).
// Both take their runs from group_runs, so fusion and the backend agree on where runs end.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "../program.hpp"

namespace qrm::detail {

// Moving qubits of an op as a mask (targets, added bits, select qubits: the qubits a chunk must hold).
template <int = 0>
std::uint64_t moving_mask(const op::any& o) {
  std::uint64_t m = 0;
  auto add = [&m](std::span<const qubit_index> qs) {
    for (qubit_index q : qs) m |= q < 64 ? std::uint64_t{1} << q : 0;
  };
  visit_op(o, [&](const auto& x) {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, op::gate1_op>) {
      add(std::span<const qubit_index>(&x.target, 1));
    } else if constexpr (std::is_same_v<T, op::add_op>) {
      add(x.bits);
    } else if constexpr (std::is_same_v<T, op::mux1_op>) {
      add(std::span<const qubit_index>(&x.target, 1));
      add(x.select);
    } else if constexpr (std::is_same_v<T, op::mux_unitary_op>) {
      add(x.targets);
      add(x.select);
    } else {
      add(x.targets);
    }
  });
  return m;
}

// Control qubits of an op as a mask.
template <int = 0>
std::uint64_t control_mask(const op::any& o) {
  std::uint64_t m = 0;
  visit_op(o, [&m](const auto& x) {
    for (const control& c : x.controls) m |= c.qubit < 64 ? std::uint64_t{1} << c.qubit : 0;
  });
  return m;
}

// Ops order[first, last) form a run over the qubits `local` (a mask: the run's moving qubits and
// the reserved ones; a backend may pad it), or one op too wide for any run when local == 0.
struct op_run {
  std::size_t first = 0, last = 0;
  std::uint64_t local = 0;
};

// The runs of a program, and the order its ops are applied in (indices into the program).
struct run_plan {
  std::vector<std::size_t> order;
  std::vector<op_run> runs;
};

// How many ops a run looks past (ops it cannot take) for further ops that commute with them.
inline constexpr std::size_t run_lookahead = 256;

// group_runs(ops, m, reserved): the runs of `ops` over sets of at most m qubits that always hold
// the qubits of `reserved` (a mask). A run takes the first op left and then every later op that
// fits its m qubits and commutes with each op passed over so far: two ops commute when neither
// moves a qubit the other touches (a qubit that is only a control of both is diagonal in both).
// So the ops are applied in another order, which gives the same state to rounding. On the
// 24-qubit random suite (300 gates, chunks of 2^17 amplitudes) in program order: 12 runs unfused
// and 13 fused; with the look-ahead 9 and 11.
template <int = 0>
run_plan group_runs(std::span<const op::any> ops, unsigned m, std::uint64_t reserved) {
  run_plan plan;
  plan.order.reserve(ops.size());
  std::vector<std::uint64_t> moving(ops.size()), touched(ops.size());
  for (std::size_t i = 0; i < ops.size(); ++i) {
    moving[i] = moving_mask(ops[i]);
    touched[i] = moving[i] | control_mask(ops[i]);
  }
  const auto fits = [&](std::uint64_t qubits) { return std::popcount(qubits) <= static_cast<int>(m); };
  std::vector<std::size_t> left(ops.size()), passed;  // left[head, end): ops not yet in a run, in program order
  for (std::size_t i = 0; i < ops.size(); ++i) left[i] = i;
  std::size_t head = 0;
  while (head < left.size()) {
    const std::size_t first = plan.order.size();
    if (!fits(moving[left[head]] | reserved)) {  // too wide for any run: alone
      plan.runs.push_back({first, first + 1, 0});
      plan.order.push_back(left[head++]);
      continue;
    }
    std::uint64_t cur = reserved, passed_moving = 0, passed_touched = 0;
    passed.clear();
    std::size_t k = head;
    for (; k < left.size() && passed.size() < run_lookahead; ++k) {
      const std::size_t i = left[k];
      if (fits(cur | moving[i]) && (moving[i] & passed_touched) == 0 && (touched[i] & passed_moving) == 0) {
        cur |= moving[i];
        plan.order.push_back(i);
      } else {
        passed_moving |= moving[i];
        passed_touched |= touched[i];
        passed.push_back(i);
      }
    }
    // The passed ops, in program order, go back just before the ops not scanned.
    head = k - passed.size();
    std::copy(passed.begin(), passed.end(), left.begin() + static_cast<std::ptrdiff_t>(head));
    plan.runs.push_back({first, plan.order.size(), cur});
  }
  return plan;
}

}  // namespace qrm::detail
