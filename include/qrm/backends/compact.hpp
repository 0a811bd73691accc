// qrm/backends/compact.hpp: the compact backend: only the nonzero amplitudes, as (label, amplitude)
// pairs, so a walk started from one point runs on registers far wider than a dense vector holds.
//
// compact_state<S, L> implements the same gate_sink as state_vector<S> with the same semantics,
// checks and messages. S is float, double, std::complex<float> or std::complex<double>; L is
// std::uint64_t (up to 64 qubits) or qrm::wide_label<Words> (64 * Words qubits); compact_backend
// is the family (backend.hpp) that picks among them.
//
// Storage: one vector of entries sorted by label, plus a second vector the next state is written
// into. Why sorted vectors rather than a hash map: every operation here is a function of groups
// of labels that differ only in the target qubits, and in label order such a group lies inside
// one block of entries sharing the bits above the targets, where the entries of each target
// value form a sorted run. One sequential merge of those runs per block finds every partner and
// writes the output already sorted; nothing is hashed or probed, exact zeros are simply not
// written, and the sorted order makes every sum (norm, probabilities) canonical. Permutations
// (X, multi-controlled X, add-a-constant on a register) rotate each block in place. Measured
// before choosing (one H on a 2^20-entry complex<double> state, uint64 labels, the 2-core VM,
// steady state): the block merge takes 16 ns per entry when the target qubit is fresh (every
// entry gains a partner) and 7 ns when it is occupied (pairs merge, zeros vanish); an
// open-addressing hash map (linear probing, zero removal) 185 and 212 ns, std::unordered_map 420
// and 290 ns; even a leaner single-probe hash update without zero removal took 58-73 ns. No
// operations are queued or fused: each is one pass.
//
// Groups whose targets are not a contiguous run of qubits, or more than 3 targets, go through a
// general path that sorts by (group, target value) and back: O(N log N) instead of O(N).
//
// Determinism: each output amplitude is the sum over the matrix's nonzero columns in increasing
// order of M[r][c] * x_c over the nonzero inputs, computed in double as the dense backend does,
// and reductions sum in label order; the result depends only on the operations, not on any
// iteration order. The backend is single-threaded.
//
// Memory: the state, the buffer the next state is written into, and per-target-value scratch
// during an operation: at most about 4 entries per nonzero at the peak (peak_memory_bytes()).
// It pays on sparse states: on a completely full state one operation costs 1.4 (controlled add)
// to 26 (Ry on an occupied qubit) times the dense kernel's time (bench_backends, full_state_op).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "backend.hpp"
#include "detail/compact_kernels.hpp"
#include "detail/labels.hpp"
#include "detail/scalar.hpp"
#include "detail/validate.hpp"
#include "../circuit/ops.hpp"
#include "../support/detail/meta.hpp"

namespace qrm {

struct compact_options {
  // Relative pruning after every operation: drop amplitudes with |a|^2 < prune_threshold *
  // (norm^2 / nonzeros), i.e. below that fraction of the mean probability; each pruning removes
  // less than prune_threshold of the norm^2 and never touches a uniform superposition. Must be
  // in [0, 1); 0 (default) drops exact zeros only.
  double prune_threshold = 0.0;
};

// What pruning removed: how many amplitudes and their total probability (sum of |a|^2).
struct prune_stats {
  std::uint64_t count = 0;
  double probability = 0.0;
};

// compact_state<S, L>: the nonzero amplitudes of an n-qubit state, starting in |0...0>.
template <class Scalar = std::complex<double>, class Label = std::uint64_t>
class compact_state {
  // Vectors of element types that do not depend on Scalar (see detail::deferred).
  template <class T>
  using list = detail::deferred<std::vector<T>, sizeof(Scalar)>;

  static constexpr bool scalar_must_be_float_double_or_complex = detail::is_backend_scalar<Scalar>;
  static_assert(scalar_must_be_float_double_or_complex,
                "scalar_must_be_float_double_or_complex: compact_state<S, L> needs S = float, double, "
                "std::complex<float> or std::complex<double>");
  static constexpr bool label_must_be_uint64_or_wide_label = detail::label_traits<Label>::supported;
  static_assert(label_must_be_uint64_or_wide_label,
                "label_must_be_uint64_or_wide_label: compact_state<S, L> needs L = std::uint64_t or "
                "qrm::wide_label<Words>");

  using T = detail::label_traits<Label>;

 public:
  using scalar_type = Scalar;
  using label_type = Label;
  using real_type = typename detail::scalar_traits<Scalar>::real;
  using entry = detail::compact_entry<Label, Scalar>;
  static constexpr bool is_complex = detail::scalar_traits<Scalar>::is_complex;
  // Qubits a label holds.
  static constexpr std::size_t max_qubits = T::bits;

  explicit compact_state(std::size_t num_qubits, compact_options opt = {}) : n_(num_qubits) {
    if (num_qubits > max_qubits)
      throw std::length_error("compact_state: " + std::to_string(num_qubits) + " qubits do not fit a " +
                              std::to_string(max_qubits) + "-qubit label (" + T::name +
                              "); use compact_state<S, qrm::wide_label<" + std::to_string((num_qubits + 63) / 64) +
                              ">>");
    set_prune_threshold(opt.prune_threshold);
    valid_ = T::low_mask(n_);
    cur_.push_back(entry{Label{}, Scalar{1}});
    note_peak(memory_bytes());
  }

  std::size_t num_qubits() const { return n_; }
  // Stored (nonzero) amplitudes.
  std::size_t nonzeros() const { return cur_.size(); }
  // The stored amplitudes, sorted by label.
  std::span<const entry> entries() const { return cur_; }

  Scalar amplitude(const Label& label) const {
    check_label(label, "compact_state::amplitude");
    const auto it =
        std::lower_bound(cur_.begin(), cur_.end(), label, [](const entry& e, const Label& l) { return e.label < l; });
    return it != cur_.end() && it->label == label ? it->amp : Scalar{};
  }
  // |label>
  void set_basis_state(const Label& label) {
    check_label(label, "compact_state::set_basis_state");
    cur_.assign(1, entry{label, Scalar{1}});
    note_peak(memory_bytes());
  }

  // The state as 2^n dense amplitudes (n <= 32).
  std::vector<Scalar> to_dense() const {
    if (n_ > 32)
      throw std::length_error("compact_state::to_dense: " + std::to_string(n_) +
                              " qubits are too many for a dense vector here (at most 32)");
    std::vector<Scalar> d(std::size_t{1} << n_, Scalar{});
    for (const entry& e : cur_) d[static_cast<std::size_t>(T::low_u64(e.label))] = e.amp;
    return d;
  }
  // Loads 2^n dense amplitudes (zeros are not stored).
  void set_amplitudes(std::span<const Scalar> amplitudes) {
    if (n_ > 62 || amplitudes.size() != (std::size_t{1} << n_))
      throw std::invalid_argument("compact_state::set_amplitudes: got " + std::to_string(amplitudes.size()) +
                                  " amplitudes, need 2^" + std::to_string(n_));
    std::vector<entry> v;
    std::size_t count = 0;
    for (const Scalar& a : amplitudes) count += a != Scalar{} ? 1 : 0;
    v.reserve(count);
    for (std::size_t i = 0; i < amplitudes.size(); ++i)
      if (amplitudes[i] != Scalar{}) v.push_back(entry{T::from_u64(i), amplitudes[i]});
    cur_.swap(v);
    note_peak(memory_bytes() + v.capacity() * sizeof(entry));
  }

  // Bytes held now for amplitudes and labels (the state, the buffer the next state is written
  // into, and scratch), and the most ever held at once, transient growth included.
  std::size_t memory_bytes() const {
    std::size_t entries = cur_.capacity() + next_.capacity();
    for (const auto& s : streams_) entries += s.capacity();
    return entries * sizeof(entry) + items_.capacity() * sizeof(item) +
           (acc_re_.capacity() + acc_im_.capacity()) * sizeof(double) + touched_.capacity() * sizeof(std::uint32_t);
  }
  std::size_t peak_memory_bytes() const { return peak_bytes_; }
  // Frees the spare buffers (they are reallocated by the next operation).
  void shrink_to_fit() {
    release(next_);
    release(streams_);
    release(items_);
    cur_.shrink_to_fit();
  }

  // ---- pruning ----------------------------------------------------------------------------------

  // Threshold applied after every operation (see compact_options::prune_threshold).
  void set_prune_threshold(double eps) {
    check_prune_threshold(eps, "compact_state::set_prune_threshold");
    prune_threshold_ = eps;
  }
  double prune_threshold() const { return prune_threshold_; }
  // Drops amplitudes with |a|^2 < eps * norm^2 / nonzeros now; returns what was removed.
  prune_stats prune(double eps) {
    check_prune_threshold(eps, "compact_state::prune");
    prune_stats removed;
    if (cur_.empty() || eps == 0) return removed;
    const double cut = eps * (norm_squared() / static_cast<double>(cur_.size()));
    std::size_t w = 0;
    for (std::size_t i = 0; i < cur_.size(); ++i) {
      const double p = prob(cur_[i].amp);
      if (p < cut) {
        ++removed.count;
        removed.probability += p;
      } else {
        cur_[w++] = cur_[i];
      }
    }
    cur_.resize(w);
    pruned_.count += removed.count;
    pruned_.probability += removed.probability;
    return removed;
  }
  // Everything pruning has removed so far (automatic and explicit).
  prune_stats pruned() const { return pruned_; }

  // ---- gate_sink --------------------------------------------------------------------------------

  void apply_gate1(const gate1& g, qubit_index target, std::span<const control> controls) {
    const auto cond = checks().gate1(g, target, controls).cond;
    if (g.is_identity()) return;
    const bool is_x =
        g.m[0][0] == complex{} && g.m[1][1] == complex{} && g.m[0][1] == complex{1.0} && g.m[1][0] == complex{1.0};
    const list<qubit_index> ts = {target};
    if (is_x) {
      guarded([&] { permute_add(1, ts, cond); });
      return;
    }
    const detail::select_lookup lookup({}, {{0, 0}});
    if (g.is_diagonal()) {
      const list<detail::compiled_matrix> ms = {detail::compiled_matrix(g)};
      guarded([&] { scale_diagonal(ts, cond, lookup, ms); });
      return;
    }
    const list<detail::compiled_gate1> gs = {detail::compiled_gate1(g)};
    guarded([&] { branch_one(target, cond, lookup, gs); });
  }

  void apply_unitary(const dense_matrix& m, std::span<const qubit_index> targets, std::span<const control> controls) {
    const auto cond = checks().unitary(m, targets, controls).cond;
    const list<detail::compiled_matrix> ms = {detail::compiled_matrix(m)};
    const detail::select_lookup lookup({}, {{0, 0}});
    guarded([&] { apply_matrices(targets, cond, lookup, ms); });
  }

  void apply_add(std::int64_t constant, std::span<const qubit_index> bits, std::span<const control> controls) {
    const auto cond = checks().add(bits, controls).cond;
    if (bits.empty()) return;
    if (bits.size() > 64)
      throw std::invalid_argument("apply_add: a register of " + std::to_string(bits.size()) +
                                  " qubits is wider than the 64 this backend adds on");
    const std::uint64_t wrap = bits.size() >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits.size()) - 1;
    const std::uint64_t shift = static_cast<std::uint64_t>(constant) & wrap;
    if (shift == 0) return;
    guarded([&] { permute_add(shift, bits, cond); });
  }

  void apply_mux1(std::span<const mux1_entry> entries, qubit_index target, std::span<const qubit_index> select,
                  std::span<const control> controls) {
    const auto cond = checks().mux1(entries, target, select, controls).cond;
    // Identity entries act like missing ones.
    list<std::pair<std::uint64_t, std::int32_t>> ids;
    bool all_diagonal = true;
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (entries[i].gate.is_identity()) continue;
      ids.push_back({entries[i].select, static_cast<std::int32_t>(i)});
      all_diagonal = all_diagonal && entries[i].gate.is_diagonal();
    }
    if (ids.empty()) return;
    const detail::select_lookup lookup(select, ids);
    const list<qubit_index> ts = {target};
    if (all_diagonal) {
      list<detail::compiled_matrix> ms;
      for (const auto& e : entries) ms.emplace_back(e.gate);
      guarded([&] { scale_diagonal(ts, cond, lookup, ms); });
      return;
    }
    list<detail::compiled_gate1> gs;
    for (const auto& e : entries) gs.emplace_back(e.gate);
    guarded([&] { branch_one(target, cond, lookup, gs); });
  }

  void apply_mux_unitary(std::span<const dense_matrix> matrices, std::span<const mux_unitary_entry> entries,
                         std::span<const qubit_index> targets, std::span<const qubit_index> select,
                         std::span<const control> controls) {
    const auto cond = checks().mux_unitary(matrices, entries, targets, select, controls).cond;
    list<detail::compiled_matrix> ms;
    for (const auto& m : matrices) ms.emplace_back(m);
    list<std::pair<std::uint64_t, std::int32_t>> ids;
    for (const auto& e : entries) ids.push_back({e.select, static_cast<std::int32_t>(e.matrix)});
    if (ids.empty()) return;
    const detail::select_lookup lookup(select, ids);
    guarded([&] { apply_matrices(targets, cond, lookup, ms); });
  }

  // ---- reading the state ------------------------------------------------------------------------

  // Sum of |a|^2, in label order.
  double norm_squared() const {
    double acc = 0;
    for (const entry& e : cur_) add_prob(acc, e.amp);
    return acc;
  }
  // Probability that every control holds.
  double probability(std::span<const control> condition) const {
    const auto cond = checks().probability(condition);
    double acc = 0;
    for (const entry& e : cur_)
      if ((e.label & cond.mask) == cond.value) add_prob(acc, e.amp);
    return acc;
  }
  // Probabilities of every value of the register `bits` (2^k numbers).
  std::vector<double> distribution(std::span<const qubit_index> bits) const {
    checks().distribution(bits);
    list<double> p(std::size_t{1} << bits.size(), 0.0);
    for (const entry& e : cur_) {
      std::size_t v = 0;
      for (std::size_t i = 0; i < bits.size(); ++i) v |= std::size_t{T::test(e.label, bits[i])} << i;
      add_prob(p[v], e.amp);
    }
    return p;
  }

 private:
  // A group's entry in the general (sorting) path: group label (targets cleared), matrix index,
  // position of the amplitude in the state.
  struct item {
    Label group;
    std::uint32_t column;
    std::size_t index;
  };

  // ---- arithmetic ---------------------------------------------------------------------------------

  static double re_of(const Scalar& x) {
    if constexpr (is_complex)
      return static_cast<double>(x.real());
    else
      return static_cast<double>(x);
  }
  static double im_of(const Scalar& x) {
    if constexpr (is_complex)
      return static_cast<double>(x.imag());
    else
      return 0.0;
  }
  static Scalar make_scalar(double re, double im) {
    if constexpr (is_complex)
      return Scalar(static_cast<real_type>(re), static_cast<real_type>(im));
    else {
      (void)im;
      return static_cast<Scalar>(re);
    }
  }
  // |a|^2 added as the dense backend does (real part squared, then imaginary part squared).
  static void add_prob(double& acc, const Scalar& a) {
    const double r = re_of(a);
    acc += r * r;
    if constexpr (is_complex) {
      const double i = im_of(a);
      acc += i * i;
    }
  }
  static double prob(const Scalar& a) {
    double p = 0;
    add_prob(p, a);
    return p;
  }

  // (b0, b1) = m (x0, x1), with an absent input passed as zero.
  static void mul2(const detail::compiled_gate1& g, const Scalar& x0, const Scalar& x1, Scalar& b0, Scalar& b1) {
    const double* m = g.m;
    if constexpr (is_complex) {
      const double xr = x0.real(), xi = x0.imag(), yr = x1.real(), yi = x1.imag();
      b0 = make_scalar(((m[0] * xr - m[1] * xi) + m[2] * yr) - m[3] * yi,
                       ((m[0] * xi + m[1] * xr) + m[2] * yi) + m[3] * yr);
      b1 = make_scalar(((m[4] * xr - m[5] * xi) + m[6] * yr) - m[7] * yi,
                       ((m[4] * xi + m[5] * xr) + m[6] * yi) + m[7] * yr);
    } else {
      const double x = x0, y = x1;
      b0 = static_cast<Scalar>(m[0] * x + m[2] * y);
      b1 = static_cast<Scalar>(m[4] * x + m[6] * y);
    }
  }

  // Calls emit(row, value) for every row of M * x with a nonzero value, where x is zero except at
  // columns cols[0..count) (increasing) holding xs[]. Each row sums its columns in increasing order.
  template <class Emit>
  void multiply(const detail::compiled_matrix& m, const std::uint32_t* cols, const Scalar* xs, std::size_t count,
                Emit&& emit) {
    if (acc_re_.size() < m.dim) {
      grow(acc_re_, m.dim);
      grow(acc_im_, m.dim);
      acc_re_.resize(m.dim, 0.0);
      acc_im_.resize(m.dim, 0.0);
      seen_.resize(m.dim, 0);
    }
    touched_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t c = cols[i];
      const double xr = re_of(xs[i]), xi = im_of(xs[i]);
      for (std::uint32_t e = m.col_start[c]; e < m.col_start[c + 1]; ++e) {
        const std::uint32_t r = m.row[e];
        if (!seen_[r]) {
          seen_[r] = 1;
          acc_re_[r] = 0;
          acc_im_[r] = 0;
          touched_.push_back(r);
        }
        if constexpr (is_complex) {
          acc_re_[r] += m.re[e] * xr - m.im[e] * xi;
          acc_im_[r] += m.re[e] * xi + m.im[e] * xr;
        } else {
          acc_re_[r] += m.re[e] * xr;
        }
      }
    }
    for (const std::uint32_t r : touched_) {
      seen_[r] = 0;
      const Scalar v = make_scalar(acc_re_[r], acc_im_[r]);
      if (v != Scalar{}) emit(r, v);
    }
  }

  // ---- storage ------------------------------------------------------------------------------------

  template <class V>
  void grow(V& v, std::size_t need) {
    if (need <= v.capacity()) return;
    const std::size_t cap = std::max<std::size_t>({need, 2 * v.capacity(), 16});
    // Old and new buffers coexist while the vector moves.
    note_peak(memory_bytes() + cap * sizeof(typename V::value_type));
    v.reserve(cap);
  }
  void push(std::vector<entry>& v, const Label& label, const Scalar& amp) {
    if (v.size() == v.capacity()) grow(v, v.size() + 1);
    v.push_back(entry{label, amp});
  }
  void append(std::vector<entry>& v, const entry* first, std::size_t count) {
    grow(v, v.size() + count);
    v.insert(v.end(), first, first + count);
  }
  void note_peak(std::size_t bytes) { peak_bytes_ = std::max(peak_bytes_, bytes); }

  // Runs one operation: converts running out of memory into a clear error, then prunes, trims
  // spare buffers and records the memory high-water mark.
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const std::bad_alloc&) {
      throw_out_of_memory();
    }
    after_operation();
  }
  // Apart from guarded so that each operation's instantiation holds only the call and the catch.
  [[noreturn]] void throw_out_of_memory() const {
    throw std::length_error("compact_state: out of memory at " + std::to_string(cur_.size()) +
                            " nonzero amplitudes (" + std::to_string(memory_bytes()) + " bytes held)");
  }
  void after_operation() {
    note_peak(memory_bytes());
    if (prune_threshold_ > 0) prune(prune_threshold_);
    // Buffers much larger than the state are released, so memory follows the nonzeros; the slack
    // (8x) keeps buffers across the usual ups and downs of a circuit, since freeing and refaulting
    // large buffers measured slower than the operations themselves.
    const std::size_t keep = 8 * cur_.size() + 4096;
    if (cur_.capacity() > keep) cur_.shrink_to_fit();
    if (next_.capacity() > keep) release(next_);
    for (auto& s : streams_)
      if (s.capacity() > keep) release(s);
    if (items_.capacity() > keep) release(items_);
  }
  // Frees v's storage (assigning {} would keep the capacity).
  template <class V>
  static void release(V& v) {
    V().swap(v);
  }

  // ---- checks -------------------------------------------------------------------------------------

  detail::op_checks<Label, Scalar> checks() const { return {n_, "compact_state"}; }
  void check_label(const Label& label, const char* what) const {
    if (!T::is_zero(label & ~valid_))
      throw std::out_of_range(std::string(what) + ": label " + T::to_string(label) + " does not fit " +
                              std::to_string(n_) + " qubits");
  }
  static void check_prune_threshold(double eps, const char* what) {
    if (!(eps >= 0.0 && eps < 1.0))
      throw std::invalid_argument(std::string(what) + ": the relative threshold must be in [0, 1), got " +
                                  std::to_string(eps));
  }

  // ---- traversal ----------------------------------------------------------------------------------

  // Splits the entries into blocks sharing the bits under hi_mask. Controls among those bits are
  // constant per block: failing stretches go to skip(i, j) (found by seeking, not by walking),
  // the other blocks to block(i, j).
  template <class Skip, class Block>
  void for_each_block(const Label& hi_mask, const detail::label_condition<Label>& cond, Skip&& skip, Block&& block) {
    const Label cm = cond.mask & hi_mask, cv = cond.value & hi_mask;
    const entry* a = cur_.data();
    const std::size_t n = cur_.size();
    std::size_t i = 0;
    while (i < n) {
      const Label first = a[i].label;
      if ((first & cm) != cv) {
        Label next{};
        std::size_t j = n;
        if (detail::next_match(first, cm, cv, next))
          j = detail::gallop(a, i, n, [&](const entry& e) { return e.label < next; });
        skip(i, j);
        i = j;
        continue;
      }
      const Label hi = first & hi_mask;
      const std::size_t e = detail::gallop(a, i + 1, n, [&](const entry& x) { return (x.label & hi_mask) == hi; });
      block(i, e);
      i = e;
    }
  }

  // ---- diagonal operations: scale in place ---------------------------------------------------------

  void scale_diagonal(const list<qubit_index>& targets, detail::label_condition<Label> cond,
                      const detail::select_lookup& lookup, const list<detail::compiled_matrix>& ms) {
    // One target whose |0> (or |1>) entry is 1 in every matrix (Z, phase, controlled-Z): the
    // other value is one more control, so untouched entries are skipped by seeking.
    if (targets.size() == 1) {
      const auto leaves = [&](std::size_t r) {
        return std::all_of(ms.begin(), ms.end(),
                           [&](const auto& m) { return m.diag_re[r] == 1.0 && m.diag_im[r] == 0.0; });
      };
      const Label t = T::bit(targets[0]);
      if (leaves(0) || leaves(1)) {
        cond.mask = cond.mask | t;
        if (leaves(0)) cond.value = cond.value | t;
      }
    }
    // Controls on qubit 6 and up are checked per block of entries sharing the bits from the
    // lowest of them up (failing stretches are skipped by seeking); lower ones per entry, since
    // seeking across blocks of a few labels costs more than looking at each entry.
    const Label seek_mask = cond.mask & ~T::low_mask(6);
    const Label hi_mask = T::is_zero(seek_mask) ? Label{} : ~T::low_mask(T::lowest(seek_mask));
    const Label lo_cm = cond.mask & ~hi_mask, lo_cv = cond.value & ~hi_mask;
    bool zero_made = false;
    entry* a = cur_.data();
    for_each_block(
        hi_mask, cond, [](std::size_t, std::size_t) {},
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) {
            if ((a[i].label & lo_cm) != lo_cv) continue;
            const std::int32_t id = lookup(a[i].label);
            if (id < 0) continue;
            const auto& m = ms[static_cast<std::size_t>(id)];
            std::size_t r = 0;
            for (std::size_t j = 0; j < targets.size(); ++j) r |= std::size_t{T::test(a[i].label, targets[j])} << j;
            const double dr = m.diag_re[r], di = m.diag_im[r];
            if (dr == 1.0 && di == 0.0) continue;
            const double xr = re_of(a[i].amp), xi = im_of(a[i].amp);
            a[i].amp = make_scalar(dr * xr - di * xi, dr * xi + di * xr);
            zero_made = zero_made || a[i].amp == Scalar{};
          }
        });
    if (zero_made) std::erase_if(cur_, [](const entry& e) { return e.amp == Scalar{}; });
  }

  // ---- permutations: add a constant to a register --------------------------------------------------

  void permute_add(std::uint64_t shift, std::span<const qubit_index> bits, const detail::label_condition<Label>& cond) {
    const std::size_t k = bits.size();
    bool contiguous = true;
    for (std::size_t i = 1; i < k; ++i)
      if (bits[i] != bits[0] + i) contiguous = false;
    const std::uint64_t wrap = k >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << k) - 1;
    if (!contiguous) {
      // Scattered register: relabel, then sort (no two entries can collide: a permutation).
      for (entry& e : cur_) {
        if ((e.label & cond.mask) != cond.value) continue;
        std::uint64_t v = 0;
        for (std::size_t i = 0; i < k; ++i) v |= std::uint64_t{T::test(e.label, bits[i])} << i;
        v = (v + shift) & wrap;
        for (std::size_t i = 0; i < k; ++i) {
          const Label b = T::bit(bits[i]);
          e.label = ((v >> i) & 1u) ? (e.label | b) : (e.label & ~b);
        }
      }
      std::sort(cur_.begin(), cur_.end(), [](const entry& x, const entry& y) { return x.label < y.label; });
      return;
    }
    const std::size_t p = bits[0];
    const Label field = T::low_mask(p + k) & ~T::low_mask(p);
    const Label hi_mask = ~T::low_mask(p + k);
    const Label lo_cm = cond.mask & T::low_mask(p), lo_cv = cond.value & T::low_mask(p);
    // In a block (fixed bits above the register) entries are sorted by (register value, low
    // bits); adding `shift` moves the values >= 2^k - shift to the front: a rotation.
    const std::uint64_t wrap_from = (wrap - shift) + 1;
    entry* a = cur_.data();
    auto below_wrap = [&](const entry& e) { return T::extract(e.label, p, k) < wrap_from; };
    auto relabel = [&](const Label& l) { return T::add_field(l, field, p, k, shift); };
    if (T::is_zero(lo_cm)) {
      for_each_block(
          hi_mask, cond, [](std::size_t, std::size_t) {},
          [&](std::size_t b, std::size_t e) {
            const std::size_t q = detail::gallop(a, b, e, below_wrap);
            std::rotate(a + b, a + q, a + e);
            for (std::size_t i = b; i < e; ++i) a[i].label = relabel(a[i].label);
          });
      return;
    }
    // Controls below the register: per block, the moving entries (rotated) merge with the
    // staying ones into the next buffer.
    next_.clear();
    grow(next_, cur_.size());
    for_each_block(
        hi_mask, cond, [&](std::size_t i, std::size_t j) { append(next_, a + i, j - i); },
        [&](std::size_t b, std::size_t e) {
          const std::size_t q = detail::gallop(a, b, e, below_wrap);
          auto moves = [&](std::size_t i) { return (a[i].label & lo_cm) == lo_cv; };
          // Movers in rotated order: [q, e) then [b, q).
          std::size_t mi = q, si = b;
          bool second_half = false;
          auto next_mover = [&] {
            for (;;) {
              while (mi < (second_half ? q : e) && !moves(mi)) ++mi;
              if (mi < (second_half ? q : e) || second_half) return;
              second_half = true;
              mi = b;
            }
          };
          auto next_stayer = [&] {
            while (si < e && moves(si)) ++si;
          };
          next_mover();
          next_stayer();
          for (;;) {
            const bool have_m = mi < (second_half ? q : e), have_s = si < e;
            if (!have_m && !have_s) break;
            if (have_m) {
              const Label ml = relabel(a[mi].label);
              if (!have_s || ml < a[si].label) {
                next_.push_back(entry{ml, a[mi].amp});
                ++mi;
                next_mover();
                continue;
              }
            }
            next_.push_back(a[si]);
            ++si;
            next_stayer();
          }
        });
    cur_.swap(next_);
  }

  // ---- branching operations ------------------------------------------------------------------------

  // One target qubit: per block, the run with the target 0 merges with the run with the target 1.
  void branch_one(qubit_index t, const detail::label_condition<Label>& cond, const detail::select_lookup& lookup,
                  const list<detail::compiled_gate1>& gates) {
    const Label bit = T::bit(t);
    const Label hi_mask = ~T::low_mask(t + 1);
    if (streams_.empty()) streams_.resize(1);
    std::vector<entry>& out = next_;
    std::vector<entry>& ones = streams_[0];
    out.clear();
    ones.clear();
    grow(out, cur_.size());
    const entry* a = cur_.data();
    auto group = [&](const Label& g, const Scalar& x0, const Scalar& x1) {
      const detail::compiled_gate1* m = nullptr;
      if ((g & cond.mask) == cond.value) {
        const std::int32_t id = lookup(g);
        if (id >= 0) m = &gates[static_cast<std::size_t>(id)];
      }
      Scalar b0 = x0, b1 = x1;
      if (m) mul2(*m, x0, x1, b0, b1);
      if (b0 != Scalar{}) push(out, g, b0);
      if (b1 != Scalar{}) push(ones, g | bit, b1);
    };
    for_each_block(
        hi_mask, cond, [&](std::size_t i, std::size_t j) { append(out, a + i, j - i); },
        [&](std::size_t b, std::size_t e) {
          const std::size_t s = detail::gallop(a, b, e, [&](const entry& x) { return !T::test(x.label, t); });
          std::size_t i = b, j = s;
          while (i < s && j < e) {
            const Label li = a[i].label, lj = a[j].label ^ bit;
            if (li < lj) {
              group(li, a[i].amp, Scalar{});
              ++i;
            } else if (lj < li) {
              group(lj, Scalar{}, a[j].amp);
              ++j;
            } else {
              group(li, a[i].amp, a[j].amp);
              ++i;
              ++j;
            }
          }
          for (; i < s; ++i) group(a[i].label, a[i].amp, Scalar{});
          for (; j < e; ++j) group(a[j].label ^ bit, Scalar{}, a[j].amp);
          append(out, ones.data(), ones.size());
          ones.clear();
        });
    cur_.swap(out);
  }

  // k-qubit matrices (possibly multiplexed): diagonal ones scale in place; targets that are a
  // contiguous run of at most 3 qubits merge per block; anything else sorts.
  void apply_matrices(std::span<const qubit_index> targets, const detail::label_condition<Label>& cond,
                      const detail::select_lookup& lookup, const list<detail::compiled_matrix>& ms) {
    const list<qubit_index> ts(targets.begin(), targets.end());
    if (std::all_of(ms.begin(), ms.end(), [](const detail::compiled_matrix& m) { return m.diagonal; })) {
      scale_diagonal(ts, cond, lookup, ms);
      return;
    }
    const std::size_t k = ts.size();
    const qubit_index lo = *std::min_element(ts.begin(), ts.end());
    const qubit_index hi = *std::max_element(ts.begin(), ts.end());
    if (k <= 3 && hi - lo + 1 == k)
      branch_runs(ts, lo, cond, lookup, ms);
    else
      branch_sorted(ts, cond, lookup, ms);
  }

  // Targets occupy bits [p, p + k) in some order. In a block the entries of each target value
  // (run index = bits [p, p+k)) form a sorted run; a k-way merge on the other bits finds groups.
  void branch_runs(const list<qubit_index>& ts, qubit_index p, const detail::label_condition<Label>& cond,
                   const detail::select_lookup& lookup, const list<detail::compiled_matrix>& ms) {
    const std::size_t k = ts.size(), runs = std::size_t{1} << k;
    // Matrix index c has target j = bit j; run index has qubit p + i = bit i.
    std::uint32_t run_of[8] = {}, column_of[8] = {};
    for (std::uint32_t c = 0; c < runs; ++c) {
      std::uint32_t r = 0;
      for (std::size_t j = 0; j < k; ++j) r |= ((c >> j) & 1u) << (ts[j] - p);
      run_of[c] = r;
      column_of[r] = c;
    }
    Label run_label[8];  // the target bits of each run
    for (std::uint32_t r = 0; r < runs; ++r) run_label[r] = T::place(r, p);
    const Label tmask = T::low_mask(p + k) & ~T::low_mask(p);
    const Label keep = ~tmask;
    const Label hi_mask = ~T::low_mask(p + k);
    if (streams_.size() < runs) streams_.resize(runs);
    std::vector<entry>& out = next_;
    out.clear();
    for (std::size_t r = 1; r < runs; ++r) streams_[r].clear();
    grow(out, cur_.size());
    const entry* a = cur_.data();
    auto stream = [&](std::uint32_t run) -> std::vector<entry>& { return run == 0 ? out : streams_[run]; };
    for_each_block(
        hi_mask, cond, [&](std::size_t i, std::size_t j) { append(out, a + i, j - i); },
        [&](std::size_t b, std::size_t e) {
          std::size_t head[9], end[9];
          head[0] = b;
          for (std::size_t r = 0; r < runs; ++r) {
            end[r] = detail::gallop(a, head[r], e, [&](const entry& x) { return T::extract(x.label, p, k) <= r; });
            head[r + 1] = end[r];
          }
          std::uint32_t cols[8];
          Scalar xs[8];
          for (;;) {
            bool any = false;
            Label g{};
            for (std::size_t r = 0; r < runs; ++r) {
              if (head[r] == end[r]) continue;
              const Label key = a[head[r]].label & keep;
              if (!any || key < g) g = key;
              any = true;
            }
            if (!any) break;
            std::size_t count = 0;
            for (std::size_t r = 0; r < runs; ++r) {
              if (head[r] == end[r] || (a[head[r]].label & keep) != g) continue;
              // Insert by column so each output sums its columns in increasing order.
              std::size_t at = count++;
              const std::uint32_t c = column_of[r];
              for (; at > 0 && cols[at - 1] > c; --at) {
                cols[at] = cols[at - 1];
                xs[at] = xs[at - 1];
              }
              cols[at] = c;
              xs[at] = a[head[r]].amp;
              ++head[r];
            }
            const detail::compiled_matrix* m = nullptr;
            if ((g & cond.mask) == cond.value) {
              const std::int32_t id = lookup(g);
              if (id >= 0) m = &ms[static_cast<std::size_t>(id)];
            }
            if (!m) {
              for (std::size_t i = 0; i < count; ++i)
                push(stream(run_of[cols[i]]), g | run_label[run_of[cols[i]]], xs[i]);
              continue;
            }
            // multiply() with the accumulators on the stack (dim <= 8): same sums, same order.
            double acc_re[8], acc_im[8];
            std::uint32_t touched = 0;
            for (std::size_t i = 0; i < count; ++i) {
              const std::uint32_t c = cols[i];
              const double xr = re_of(xs[i]), xi = im_of(xs[i]);
              for (std::uint32_t e = m->col_start[c]; e < m->col_start[c + 1]; ++e) {
                const std::uint32_t r = m->row[e];
                if (!((touched >> r) & 1u)) {
                  touched |= 1u << r;
                  acc_re[r] = 0;
                  acc_im[r] = 0;
                }
                if constexpr (is_complex) {
                  acc_re[r] += m->re[e] * xr - m->im[e] * xi;
                  acc_im[r] += m->re[e] * xi + m->im[e] * xr;
                } else {
                  acc_re[r] += m->re[e] * xr;
                }
              }
            }
            for (; touched != 0; touched &= touched - 1) {
              const auto r = static_cast<std::uint32_t>(std::countr_zero(touched));
              const Scalar v = make_scalar(acc_re[r], acc_im[r]);
              if (v != Scalar{}) push(stream(run_of[r]), g | run_label[run_of[r]], v);
            }
          }
          for (std::size_t r = 1; r < runs; ++r) {
            append(out, streams_[r].data(), streams_[r].size());
            streams_[r].clear();
          }
        });
    cur_.swap(out);
  }

  // Any targets: sort by (group, matrix index), apply per group, sort the result by label.
  void branch_sorted(const list<qubit_index>& ts, const detail::label_condition<Label>& cond,
                     const detail::select_lookup& lookup, const list<detail::compiled_matrix>& ms) {
    const std::size_t k = ts.size();
    Label tmask{};
    for (qubit_index q : ts) tmask = tmask | T::bit(q);
    const Label keep = ~tmask;
    items_.clear();
    grow(items_, cur_.size());
    for (std::size_t i = 0; i < cur_.size(); ++i) {
      const Label& l = cur_[i].label;
      std::uint32_t c = 0;
      for (std::size_t j = 0; j < k; ++j) c |= std::uint32_t{T::test(l, ts[j])} << j;
      items_.push_back(item{l & keep, c, i});
    }
    std::sort(items_.begin(), items_.end(), [](const item& x, const item& y) {
      return x.group < y.group || (x.group == y.group && x.column < y.column);
    });
    auto label_of = [&](const Label& g, std::uint32_t c) {
      Label l = g;
      for (std::size_t j = 0; j < k; ++j)
        if ((c >> j) & 1u) l = l | T::bit(ts[j]);
      return l;
    };
    std::vector<entry>& out = next_;
    out.clear();
    grow(out, cur_.size());
    list<std::uint32_t> cols;
    std::vector<Scalar> xs;
    for (std::size_t i = 0; i < items_.size();) {
      const Label g = items_[i].group;
      std::size_t j = i;
      cols.clear();
      xs.clear();
      for (; j < items_.size() && items_[j].group == g; ++j) {
        cols.push_back(items_[j].column);
        xs.push_back(cur_[items_[j].index].amp);
      }
      i = j;
      const detail::compiled_matrix* m = nullptr;
      if ((g & cond.mask) == cond.value) {
        const std::int32_t id = lookup(g);
        if (id >= 0) m = &ms[static_cast<std::size_t>(id)];
      }
      if (!m) {
        for (std::size_t c = 0; c < cols.size(); ++c) push(out, label_of(g, cols[c]), xs[c]);
        continue;
      }
      multiply(*m, cols.data(), xs.data(), cols.size(),
               [&](std::uint32_t row, const Scalar& v) { push(out, label_of(g, row), v); });
    }
    std::sort(out.begin(), out.end(), [](const entry& x, const entry& y) { return x.label < y.label; });
    cur_.swap(out);
  }

  std::size_t n_;
  Label valid_{};
  double prune_threshold_ = 0.0;
  prune_stats pruned_;
  std::size_t peak_bytes_ = 0;
  std::vector<entry> cur_, next_;
  std::vector<std::vector<entry>> streams_;  // outputs of runs 1.. of a block, appended after run 0
  list<item> items_;
  list<double> acc_re_, acc_im_;
  list<char> seen_;
  list<std::uint32_t> touched_;
};

// compact_backend: the compact backend as a type (qrm::backend_family): real or complex double
// with 64-bit labels, and complex double with 128-bit labels past 64 qubits.
struct compact_backend {
  static constexpr std::string_view name = "compact";
  template <class S>
  using state = compact_state<S>;
  template <class F>
  static decltype(auto) visit(std::size_t width, bool real, F&& f) {
    if (width > 64) return f(std::type_identity<compact_state<std::complex<double>, wide_label<2>>>{});
    if (real) return f(std::type_identity<compact_state<double>>{});
    return f(std::type_identity<compact_state<std::complex<double>>>{});
  }
  template <class B>
  static B make(std::size_t n) {
    return B(n);
  }
};

}  // namespace qrm

// The compact backend's part of <qrm/backends/compiled_backends.hpp> (QRM_COMPILED_BACKENDS): the
// state classes of compact_backend and of `qrm simulate --scalar`.
#define QRM_DETAIL_COMPACT_INSTANCES(PREFIX)                      \
  PREFIX class compact_state<float>;                              \
  PREFIX class compact_state<double>;                             \
  PREFIX class compact_state<std::complex<float>>;                \
  PREFIX class compact_state<std::complex<double>>;               \
  PREFIX class compact_state<std::complex<double>, wide_label<2>>;

#ifdef QRM_COMPILED_BACKENDS
namespace qrm {
QRM_DETAIL_COMPACT_INSTANCES(extern template)
}  // namespace qrm
#endif
