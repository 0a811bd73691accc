// qrm/backends/detail/validate.hpp: checks every backend applies to the operands of a primitive op, with
// the same messages (so a user sees the same error whichever backend runs the circuit). They work on
// basis labels of any width (labels.hpp): the dense backend's are std::uint64_t.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "../../circuit/ops.hpp"
#include "../../support/detail/meta.hpp"
#include "labels.hpp"
#include "scalar.hpp"

namespace qrm::detail {

// A 2^k x 2^k matrix for k targets.
template <int = 0>
inline void check_matrix_dim(const dense_matrix& m, std::size_t k, const char* what) {
  if (k > 16 || m.dim != (std::size_t{1} << k) || m.data.size() != m.dim * m.dim)
    throw std::invalid_argument(std::string(what) + ": a " + std::to_string(m.dim) + "x" + std::to_string(m.dim) +
                                " matrix cannot act on " + std::to_string(k) + " qubits");
}

// Select values must fit the select register and appear at most once.
template <class E>
void check_select_entries(std::span<const E> entries, std::size_t m, const char* what) {
  if (m > 30) throw std::invalid_argument(std::string(what) + ": at most 30 select qubits");
  deferred_by<std::vector<std::uint64_t>, E> values;
  values.reserve(entries.size());
  for (const auto& e : entries) {
    if (e.select >= (std::uint64_t{1} << m))
      throw std::invalid_argument(std::string(what) + ": select value " + std::to_string(e.select) + " does not fit " +
                                  std::to_string(m) + " select qubits");
    values.push_back(e.select);
  }
  std::sort(values.begin(), values.end());
  const auto dup = std::adjacent_find(values.begin(), values.end());
  if (dup != values.end())
    throw std::invalid_argument(std::string(what) + ": select value " + std::to_string(*dup) + " has two entries");
}

// Controls as a label mask and value.
template <class Label>
struct label_condition {
  Label mask{}, value{};
};

// The controls' mask and value; throws if a control is out of range or repeated.
template <class Label>
label_condition<Label> make_label_condition(std::span<const control> cs, std::size_t n, const char* what) {
  using T = label_traits<Label>;
  label_condition<Label> c;
  for (const control& k : cs) {
    if (k.qubit >= n)
      throw std::invalid_argument(std::string(what) + ": control qubit " + std::to_string(k.qubit) +
                                  " is outside the " + std::to_string(n) + "-qubit state");
    if (T::test(c.mask, k.qubit))
      throw std::invalid_argument(std::string(what) + ": qubit " + std::to_string(k.qubit) + " is controlled twice");
    c.mask = c.mask | T::bit(k.qubit);
    if (k.value) c.value = c.value | T::bit(k.qubit);
  }
  return c;
}

// Mask of operand qubits; throws if one is out of range, repeated, or already in `taken`.
template <class Label>
Label make_label_operands(std::span<const qubit_index> qs, std::size_t n, const Label& taken, const char* what) {
  using T = label_traits<Label>;
  Label mask{};
  for (qubit_index q : qs) {
    if (q >= n)
      throw std::invalid_argument(std::string(what) + ": qubit " + std::to_string(q) + " is outside the " +
                                  std::to_string(n) + "-qubit state");
    if (T::test(mask | taken, q))
      throw std::invalid_argument(std::string(what) + ": qubit " + std::to_string(q) +
                                  " is used twice (qubits_must_be_disjoint)");
    mask = mask | T::bit(q);
  }
  return mask;
}

// What an op's checks hand its kernel: the controls, and the masks of the targets (or the added
// register) and of the select register.
template <class Label>
struct checked_op {
  label_condition<Label> cond;
  Label targets{}, select{};
};

// op_checks<Label, Scalar>{n, name}: every check of the gate_sink ops and the state reads, in one
// order, for an n-qubit backend called `name` (e.g. "state_vector") storing Scalar.
template <class Label, class Scalar>
struct op_checks {
  std::size_t n;
  const char* name;

  // A backend of real amplitudes refuses complex gates.
  void real(bool is_real, const char* what) const {
    if constexpr (!scalar_traits<Scalar>::is_complex) {
      if (!is_real)
        throw std::invalid_argument(std::string(what) + ": complex_gate_needs_complex_backend: this " + name + "<" +
                                    scalar_name<Scalar>() + "> stores real amplitudes");
    }
  }
  checked_op<Label> gate1(const qrm::gate1& g, qubit_index target, std::span<const control> cs) const {
    checked_op<Label> r{make_label_condition<Label>(cs, n, "apply_gate1")};
    r.targets = make_label_operands<Label>(std::span<const qubit_index>(&target, 1), n, r.cond.mask, "apply_gate1");
    real(g.is_real(), "apply_gate1");
    return r;
  }
  checked_op<Label> unitary(const dense_matrix& m, std::span<const qubit_index> targets,
                            std::span<const control> cs) const {
    checked_op<Label> r{make_label_condition<Label>(cs, n, "apply_unitary")};
    r.targets = make_label_operands<Label>(targets, n, r.cond.mask, "apply_unitary");
    check_matrix_dim(m, targets.size(), "apply_unitary");
    real(m.is_real(), "apply_unitary");
    return r;
  }
  checked_op<Label> add(std::span<const qubit_index> bits, std::span<const control> cs) const {
    checked_op<Label> r{make_label_condition<Label>(cs, n, "apply_add")};
    r.targets = make_label_operands<Label>(bits, n, r.cond.mask, "apply_add");
    return r;
  }
  checked_op<Label> mux1(std::span<const mux1_entry> entries, qubit_index target, std::span<const qubit_index> select,
                         std::span<const control> cs) const {
    checked_op<Label> r{make_label_condition<Label>(cs, n, "apply_mux1")};
    r.select = make_label_operands<Label>(select, n, r.cond.mask, "apply_mux1");
    r.targets =
        make_label_operands<Label>(std::span<const qubit_index>(&target, 1), n, r.cond.mask | r.select, "apply_mux1");
    check_select_entries(entries, select.size(), "apply_mux1");
    for (const auto& e : entries) real(e.gate.is_real(), "apply_mux1");
    return r;
  }
  checked_op<Label> mux_unitary(std::span<const dense_matrix> matrices, std::span<const mux_unitary_entry> entries,
                                std::span<const qubit_index> targets, std::span<const qubit_index> select,
                                std::span<const control> cs) const {
    checked_op<Label> r{make_label_condition<Label>(cs, n, "apply_mux_unitary")};
    r.select = make_label_operands<Label>(select, n, r.cond.mask, "apply_mux_unitary");
    r.targets = make_label_operands<Label>(targets, n, r.cond.mask | r.select, "apply_mux_unitary");
    check_select_entries(entries, select.size(), "apply_mux_unitary");
    for (const auto& m : matrices) {
      check_matrix_dim(m, targets.size(), "apply_mux_unitary");
      real(m.is_real(), "apply_mux_unitary");
    }
    for (const auto& e : entries)
      if (e.matrix >= matrices.size())
        throw std::invalid_argument("apply_mux_unitary: entry names matrix " + std::to_string(e.matrix) + " of " +
                                    std::to_string(matrices.size()));
    return r;
  }
  label_condition<Label> probability(std::span<const control> condition) const {
    return make_label_condition<Label>(condition, n, "probability");
  }
  // A register whose 2^k probabilities are asked for.
  void distribution(std::span<const qubit_index> bits) const {
    make_label_operands<Label>(bits, n, Label{}, "distribution");
    if (bits.size() > 26) throw std::invalid_argument("distribution: at most 26 qubits per register");
  }
};

}  // namespace qrm::detail
