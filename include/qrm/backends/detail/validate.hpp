// qrm/backends/detail/validate.hpp: checks every backend applies to the operands of a primitive op, with
// the same messages (so a user sees the same error whichever backend runs the circuit).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "../../circuit/ops.hpp"

namespace qrm::detail {

// A 2^k x 2^k matrix for k targets.
inline void check_matrix_dim(const dense_matrix& m, std::size_t k, const char* what) {
  if (k > 16 || m.dim != (std::size_t{1} << k) || m.data.size() != m.dim * m.dim)
    throw std::invalid_argument(std::string(what) + ": a " + std::to_string(m.dim) + "x" + std::to_string(m.dim) +
                                " matrix cannot act on " + std::to_string(k) + " qubits");
}

// Select values must fit the select register and appear at most once.
template <class E>
void check_select_entries(std::span<const E> entries, std::size_t m, const char* what) {
  if (m > 30) throw std::invalid_argument(std::string(what) + ": at most 30 select qubits");
  std::vector<std::uint64_t> values;
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

}  // namespace qrm::detail
