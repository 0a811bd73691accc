// qrm/backends/detail/compact_kernels.hpp: building blocks of the compact backend (backends/compact.hpp):
// entries, searches in the sorted entry list, matrices compiled for sparse inputs, and the
// select-value lookup of multiplexed gates.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "../../circuit/ops.hpp"
#include "validate.hpp"
#include "labels.hpp"
#include "scalar.hpp"

namespace qrm::detail {

// One nonzero amplitude and its basis label.
template <class Label, class Scalar>
struct compact_entry {
  Label label;
  Scalar amp;
};

// First index in [i, n) where pred fails, given pred holds on a prefix of [i, n). Exponential
// then binary search: O(log distance), so a short step costs a comparison or two and a long
// skip does not walk every entry.
template <class E, class Pred>
std::size_t gallop(const E* a, std::size_t i, std::size_t n, Pred pred) {
  if (i >= n || !pred(a[i])) return i;
  std::size_t lo = i, step = 1, hi = i + 1;  // pred(a[lo]) holds
  while (hi < n && pred(a[hi])) {
    lo = hi;
    step *= 2;
    hi = n - lo > step ? lo + step : n;
  }
  while (hi - lo > 1) {  // pred(a[lo]) holds; hi == n or pred(a[hi]) fails
    const std::size_t mid = lo + (hi - lo) / 2;
    if (pred(a[mid]))
      lo = mid;
    else
      hi = mid;
  }
  return hi;
}

// The smallest label >= x whose bits under `mask` equal `value` (value within mask); false if
// none fits in the label type.
template <class Label>
bool next_match(const Label& x, const Label& mask, const Label& value, Label& out) {
  using T = label_traits<Label>;
  const Label diff = (x ^ value) & mask;
  if (T::is_zero(diff)) {
    out = x;
    return true;
  }
  const std::size_t d = T::highest(diff);
  const Label upto_d = T::low_mask(d + 1);
  if (T::test(value, d)) {  // raise bit d; everything below takes its smallest allowed value
    out = (x & ~upto_d) | (value & upto_d);
    return true;
  }
  // Bit d must drop: add one to the free bits above d (fixed and lower bits set to 1 so the
  // carry runs through them), then impose the fixed bits.
  const Label carry_path = x | mask | upto_d;
  if (T::is_all_ones(carry_path)) return false;
  out = (T::increment(carry_path) & ~mask) | value;
  return true;
}

// A 2x2 matrix as (re, im) of m00, m01, m10, m11.
struct compiled_gate1 {
  double m[8];
  template <int = 0>
  explicit compiled_gate1(const gate1& g) {
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) {
        m[4 * r + 2 * c] = g.m[r][c].real();
        m[4 * r + 2 * c + 1] = g.m[r][c].imag();
      }
  }
};

// A 2^k x 2^k matrix stored by columns of nonzero entries (rows increasing), so a group with
// few nonzero inputs costs only their columns.
struct compiled_matrix {
  std::size_t dim = 0;
  bool diagonal = true;
  std::vector<std::uint32_t> col_start, row;
  std::vector<double> re, im;
  std::vector<double> diag_re, diag_im;  // M[r][r]

  template <int = 0>
  explicit compiled_matrix(const dense_matrix& m) : dim(m.dim), diag_re(m.dim), diag_im(m.dim) {
    col_start.push_back(0);
    for (std::size_t c = 0; c < dim; ++c) {
      for (std::size_t r = 0; r < dim; ++r) {
        const complex v = m(r, c);
        if (r == c) {
          diag_re[r] = v.real();
          diag_im[r] = v.imag();
        }
        if (v == complex{}) continue;
        if (r != c) diagonal = false;
        row.push_back(static_cast<std::uint32_t>(r));
        re.push_back(v.real());
        im.push_back(v.imag());
      }
      col_start.push_back(static_cast<std::uint32_t>(row.size()));
    }
  }
  explicit compiled_matrix(const gate1& g) : compiled_matrix(dense_matrix::of(g)) {}
};

// Select value -> entry id (or -1: identity) for multiplexed gates. A table indexed by the
// select value when it is small, a sorted list searched by halving otherwise.
class select_lookup {
 public:
  select_lookup() = default;
  // ids[i] belongs to select value values[i].
  template <int = 0>
  select_lookup(std::span<const qubit_index> select,
                const std::vector<std::pair<std::uint64_t, std::int32_t>>& value_ids)
      : select_(select.begin(), select.end()) {
    contiguous_ = true;
    for (std::size_t i = 1; i < select_.size(); ++i)
      if (select_[i] != select_[0] + i) contiguous_ = false;
    const std::size_t m = select_.size();
    if (m <= 12 || (std::uint64_t{1} << m) <= 16 * static_cast<std::uint64_t>(value_ids.size())) {
      table_.assign(std::size_t{1} << m, -1);
      for (const auto& [v, id] : value_ids) table_[v] = id;
    } else {
      sorted_ = value_ids;
      std::sort(sorted_.begin(), sorted_.end());
    }
  }

  // Entry id for the group whose non-target bits are g.
  template <class Label>
  std::int32_t operator()(const Label& g) const {
    using T = label_traits<Label>;
    std::uint64_t v = 0;
    if (select_.empty()) {
      v = 0;
    } else if (contiguous_) {
      v = T::extract(g, select_[0], select_.size());
    } else {
      for (std::size_t i = 0; i < select_.size(); ++i) v |= std::uint64_t{T::test(g, select_[i])} << i;
    }
    if (!table_.empty()) return table_[static_cast<std::size_t>(v)];
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::pair<std::uint64_t, std::int32_t>{v, -1});
    return it != sorted_.end() && it->first == v ? it->second : -1;
  }
  template <int = 0>
  std::size_t table_bytes() const {
    return table_.capacity() * sizeof(std::int32_t) +
           sorted_.capacity() * sizeof(std::pair<std::uint64_t, std::int32_t>);
  }

 private:
  std::vector<qubit_index> select_;
  bool contiguous_ = true;
  std::vector<std::int32_t> table_;
  std::vector<std::pair<std::uint64_t, std::int32_t>> sorted_;
};

}  // namespace qrm::detail
