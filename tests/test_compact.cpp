// The compact backend against the dense backend and the naive reference simulator: random
// circuits of every op kind, the whole unitary of each op kind (through maximal entanglement with
// ancillas), pruning, labels wider than 64 qubits, determinism, memory accounting, the layout
// API (run, probability, distribution, sample_counts) and bad input.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <qrm/qrm.hpp>
#include <string>
#include <vector>

#include "support/errors.hpp"
#include "support/backends.hpp"
#include "support/random_ops.hpp"
#include "support/reference.hpp"

using namespace qrm_test;
using qrm::control;
using qrm::qubit_index;
using cd = std::complex<double>;

namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// The compact invariants: labels strictly increasing and inside the register, no zero stored.
template <class B>
bool well_formed(const B& b) {
  using T = qrm::detail::label_traits<typename B::label_type>;
  const auto es = b.entries();
  const auto outside = ~T::low_mask(b.num_qubits());
  for (std::size_t i = 0; i < es.size(); ++i) {
    if (es[i].amp == typename B::scalar_type{}) return false;
    if (!T::is_zero(es[i].label & outside)) return false;
    if (i > 0 && !(es[i - 1].label < es[i].label)) return false;
  }
  return true;
}

// Maps every qubit of an op through `to` (op qubit i -> to[i]).
qrm::op::any remap(qrm::op::any o, const std::vector<qubit_index>& to) {
  std::visit(
      [&](auto& x) {
        using O = std::decay_t<decltype(x)>;
        for (control& c : x.controls) c.qubit = to[c.qubit];
        if constexpr (std::is_same_v<O, qrm::op::gate1_op>) {
          x.target = to[x.target];
        } else if constexpr (std::is_same_v<O, qrm::op::unitary_op>) {
          for (auto& q : x.targets) q = to[q];
        } else if constexpr (std::is_same_v<O, qrm::op::add_op>) {
          for (auto& q : x.bits) q = to[q];
        } else if constexpr (std::is_same_v<O, qrm::op::mux1_op>) {
          x.target = to[x.target];
          for (auto& q : x.select) q = to[q];
        } else {
          for (auto& q : x.targets) q = to[q];
          for (auto& q : x.select) q = to[q];
        }
      },
      o);
  return o;
}

// Picks qubits for one op out of 0..m-1: operands first (half the time a run of consecutive
// qubits, so both the merging and the sorting paths of the backend are used), then the rest.
struct picker {
  qrm::rng& g;
  std::vector<qubit_index> free;
  picker(qrm::rng& gen, std::size_t m) : g(gen), free(m) { std::iota(free.begin(), free.end(), 0u); }
  std::vector<qubit_index> operands(std::size_t k) {
    std::vector<qubit_index> r;
    if (g.below(2) == 0) {
      const auto start = static_cast<qubit_index>(g.below(free.size() - k + 1));
      for (std::size_t i = 0; i < k; ++i) r.push_back(start + static_cast<qubit_index>(i));
      if (g.below(3) == 0) std::reverse(r.begin(), r.end());  // a contiguous set, not in increasing order
      for (qubit_index q : r) free.erase(std::find(free.begin(), free.end(), q));
      return r;
    }
    return any(k);
  }
  std::vector<qubit_index> any(std::size_t k) {
    std::vector<qubit_index> r;
    for (std::size_t i = 0; i < k && !free.empty(); ++i) {
      const std::size_t j = g.below(free.size());
      r.push_back(free[j]);
      free.erase(free.begin() + static_cast<std::ptrdiff_t>(j));
    }
    return r;
  }
  std::vector<control> controls(std::size_t most) {
    std::vector<control> cs;
    for (qubit_index q : any(std::min<std::size_t>(g.below(most + 1), free.size()))) cs.push_back({q, g.below(2) == 1});
    return cs;
  }
};

// A random diagonal unitary on k qubits (random signs, or phases when complex).
qrm::dense_matrix random_diagonal(std::size_t k, qrm::rng& g, bool complex_values) {
  qrm::dense_matrix m(std::size_t{1} << k);
  for (std::size_t i = 0; i < m.dim; ++i)
    m(i, i) = complex_values ? std::polar(1.0, 6.283185307179586 * g.uniform()) : cd(g.below(2) ? 1.0 : -1.0);
  return m;
}

// One random unitary op of any kind on qubits 0..m-1 (m >= 2).
qrm::op::any random_op(qrm::rng& g, std::size_t m, bool complex_values) {
  picker pk(g, m);
  auto gate = [&]() -> qrm::gate1 {
    switch (g.below(complex_values ? 7 : 4)) {
      case 0:
        return qrm::gate::h();
      case 1:
        return qrm::gate::ry(6.283185307179586 * g.uniform());
      case 2:
        return qrm::gate::z();
      case 3:
        return random_gate1_unitary(g, false);
      case 4:
        return qrm::gate::y();
      case 5:
        return qrm::gate::phase(g.uniform());
      default:
        return random_gate1_unitary(g, true);
    }
  };
  switch (g.below(8)) {
    case 0: {  // named or random 2x2 gate, up to 2 controls
      const qubit_index t = pk.operands(1)[0];
      return qrm::op::gate1_op{gate(), t, pk.controls(2)};
    }
    case 1: {  // multi-controlled X
      const qubit_index t = pk.operands(1)[0];
      return qrm::op::gate1_op{qrm::gate::x(), t, pk.controls(3)};
    }
    case 2: {  // k-qubit unitary
      const std::size_t k = 1 + g.below(std::min<std::size_t>(3, m - 1));
      const auto ts = pk.operands(k);
      return qrm::op::unitary_op{random_unitary(k, g, complex_values), ts, pk.controls(1)};
    }
    case 3: {  // add a constant
      const std::size_t k = 1 + g.below(std::min<std::size_t>(4, m - 1));
      const auto bits = pk.operands(k);
      const auto lim = std::int64_t{1} << k;
      const std::int64_t c = static_cast<std::int64_t>(g.below(static_cast<std::uint64_t>(4 * lim))) - 2 * lim;
      return qrm::op::add_op{c, bits, pk.controls(2)};
    }
    case 4: {  // multiplexed 2x2
      const qubit_index t = pk.operands(1)[0];
      const auto sel = pk.any(1 + g.below(std::min<std::size_t>(3, m - 1)));
      std::vector<qrm::mux1_entry> es;
      for (std::uint64_t v = 0; v < (std::uint64_t{1} << sel.size()); ++v)
        if (g.uniform() < 0.7) es.push_back({v, gate()});
      return qrm::op::mux1_op{es, t, sel, pk.controls(1)};
    }
    case 5: {  // multiplexed k-qubit matrices
      const std::size_t k = 1 + g.below(std::min<std::size_t>(3, m - 1));
      const auto ts = pk.operands(k);
      const auto sel = pk.any(std::min<std::size_t>(1 + g.below(2), m - k));
      std::vector<qrm::dense_matrix> ms = {random_unitary(k, g, complex_values), random_unitary(k, g, false)};
      std::vector<qrm::mux_unitary_entry> es;
      for (std::uint64_t v = 0; v < (std::uint64_t{1} << sel.size()); ++v)
        if (g.uniform() < 0.7) es.push_back({v, static_cast<std::uint32_t>(g.below(2))});
      return qrm::op::mux_unitary_op{ms, es, ts, sel, pk.controls(1)};
    }
    case 6: {  // diagonal matrix (scaled in place by the backend)
      const std::size_t k = 1 + g.below(std::min<std::size_t>(2, m - 1));
      const auto ts = pk.operands(k);
      return qrm::op::unitary_op{random_diagonal(k, g, complex_values), ts, pk.controls(2)};
    }
    default: {  // a plain Hadamard: keeps states sparse for a while
      const qubit_index t = pk.operands(1)[0];
      return qrm::op::gate1_op{qrm::gate::h(), t, {}};
    }
  }
}

qrm::program random_program(qrm::rng& g, std::size_t m, std::size_t ops, bool complex_values) {
  qrm::program p(m);
  for (std::size_t i = 0; i < ops; ++i) p.push(random_op(g, m, complex_values));
  return p;
}

template <class B>
std::vector<cd> dump(const B& b) {
  return backend_traits<B>::dump(b);
}

// The amplitudes of the qubits `pos` (op qubit i at pos[i]) of a wide compact state, as a dense
// vector over those qubits; fails the check if any other qubit is set.
template <class B>
std::vector<cd> gather_dense(const B& b, const std::vector<qubit_index>& pos) {
  using T = qrm::detail::label_traits<typename B::label_type>;
  std::vector<cd> d(std::size_t{1} << pos.size());
  typename B::label_type used{};
  for (qubit_index q : pos) used = used | T::bit(q);
  for (const auto& e : b.entries()) {
    CHECK(T::is_zero(e.label & ~used));
    std::size_t idx = 0;
    for (std::size_t i = 0; i < pos.size(); ++i) idx |= std::size_t{T::test(e.label, pos[i])} << i;
    d[idx] = cd(e.amp);
  }
  return d;
}

}  // namespace

// ---- building blocks ------------------------------------------------------------------------------

TEST_CASE("next_match finds the smallest label >= x with the given bits, by brute force on 8 bits") {
  // Every x on 8 bits against masks and values on those bits; the same numbers shifted across the
  // word boundary of a wide label. Bits above 8 are free, so when nothing in [x, 2^8) fits, the
  // answer is 2^8 | value.
  using W = qrm::wide_label<2>;
  using TW = qrm::detail::label_traits<W>;
  std::size_t cases = 0;
  for (std::uint64_t mask = 0; mask < 256; mask += 7)
    for (std::uint64_t value = mask;; value = (value - 1) & mask) {
      for (std::uint64_t x = 0; x < 256; ++x) {
        std::uint64_t expect = 256 | value;
        for (std::uint64_t y = x; y < 256; ++y)
          if ((y & mask) == value) {
            expect = y;
            break;
          }
        std::uint64_t got = 0;
        CHECK(qrm::detail::next_match<std::uint64_t>(x, mask, value, got));
        CHECK(got == expect);
        W wgot;
        CHECK(qrm::detail::next_match<W>(TW::place(x, 60), TW::place(mask, 60), TW::place(value, 60), wgot));
        CHECK(wgot == TW::place(expect, 60));
        ++cases;
      }
      if (value == 0) break;
    }
  CHECK(cases > 100000);
  // At the top of the label type nothing may be left.
  std::uint64_t out = 0;
  CHECK_FALSE(qrm::detail::next_match<std::uint64_t>(std::uint64_t{1} << 63, std::uint64_t{1} << 63, 0, out));
  CHECK(qrm::detail::next_match<std::uint64_t>(0, std::uint64_t{1} << 63, std::uint64_t{1} << 63, out));
  CHECK(out == std::uint64_t{1} << 63);
}

// ---- (a) random circuits: compact and dense agree ------------------------------------------------

TEST_CASE_TEMPLATE("random circuits of every op kind give the dense backend's state, 2..16 qubits", S, double, cd) {
  constexpr bool complex_values = qrm::detail::scalar_traits<S>::is_complex;
  qrm::rng g(101);
  for (std::size_t n = 2; n <= 16; ++n)
    for (int round = 0; round < 3; ++round) {
      const qrm::program p = random_program(g, n, 40, complex_values);
      qrm::state_vector<S> dense(n, qrm::dense_options{1});
      qrm::compact_state<S> compact(n);
      // Compare after every op, so an error is caught where it happens.
      double worst = 0;
      for (const auto& o : p.ops()) {
        qrm::emit_op(o, dense);
        qrm::emit_op(o, compact);
        worst = std::max(worst, max_diff(dump(dense), dump(compact)));
      }
      INFO("n " << n << " round " << round << " nonzeros " << compact.nonzeros());
      // Amplitudes are at most 1 and each op rounds each of them a few times (~1e-16); 40 ops
      // stay far below 1e-12 unless an amplitude is wrong.
      CHECK(worst <= 1e-12);
      CHECK(well_formed(compact));
      CHECK(std::abs(compact.norm_squared() - dense.norm_squared()) <= 1e-12);
    }
}

// ---- (b) the whole unitary of each op kind --------------------------------------------------------

namespace {

// Op qubit i is entangled with ancilla i (H on the ancilla, CNOT onto the op qubit), so the input
// is maximally entangled and every column of the op's unitary matters. The compact backend applies
// the op; the reference simulator applies its adjoint and undoes the entangling; the result must
// be |0...0> again. `contiguous`: op qubits at 0..m-1 (runs of qubits), else interleaved.
template <class S>
double roundtrip_error(const qrm::op::any& o, std::size_t m, bool contiguous) {
  const std::size_t n = 2 * m;
  std::vector<qubit_index> pos(m), anc(m);
  for (std::size_t i = 0; i < m; ++i) {
    pos[i] = static_cast<qubit_index>(contiguous ? i : 2 * i + 1);
    anc[i] = static_cast<qubit_index>(contiguous ? m + i : 2 * i);
  }
  qrm::compact_state<S> c(n);
  for (std::size_t i = 0; i < m; ++i) {
    c.apply_gate1(qrm::gate::h(), anc[i], {});
    const control ctl{anc[i], true};
    c.apply_gate1(qrm::gate::x(), pos[i], std::span<const control>(&ctl, 1));
  }
  CHECK(c.nonzeros() == (std::size_t{1} << m));
  qrm::emit_op(remap(o, pos), c);
  CHECK(well_formed(c));
  reference_state ref(n);
  ref.amp = dump(c);
  qrm::emit_op(remap(qrm::op_adjoint(o), pos), ref);
  for (std::size_t i = m; i-- > 0;) {
    const control ctl{anc[i], true};
    ref.apply_gate1(qrm::gate::x(), pos[i], std::span<const control>(&ctl, 1));
    ref.apply_gate1(qrm::gate::h(), anc[i], {});
  }
  return std::abs(ref.amp[0] - 1.0);
}

struct named_op {
  std::string name;
  qrm::op::any op;
  std::size_t qubits;
};

std::vector<named_op> every_op_kind(bool complex_values) {
  qrm::rng g(202);
  std::vector<named_op> r;
  std::vector<std::pair<std::string, qrm::gate1>> gates = {{"x", qrm::gate::x()},
                                                           {"z", qrm::gate::z()},
                                                           {"h", qrm::gate::h()},
                                                           {"ry", qrm::gate::ry(0.7)},
                                                           {"u real", random_gate1_unitary(g, false)}};
  if (complex_values) {
    gates.push_back({"y", qrm::gate::y()});
    gates.push_back({"rz", qrm::gate::rz(1.1)});
    gates.push_back({"phase", qrm::gate::phase(0.4)});
    gates.push_back({"u complex", random_gate1_unitary(g, true)});
  }
  for (const auto& [name, gt] : gates) {
    r.push_back({name, qrm::op::gate1_op{gt, 1, {}}, 2});
    // Controls below and above the target, on 1 and on 0.
    r.push_back({name + " controlled", qrm::op::gate1_op{gt, 1, {{0, true}, {2, false}}}, 3});
  }
  for (std::size_t k = 1; k <= 4; ++k) {
    std::vector<qubit_index> ts(k);
    std::iota(ts.begin(), ts.end(), 1u);
    r.push_back({"unitary k=" + std::to_string(k),
                 qrm::op::unitary_op{random_unitary(k, g, complex_values), ts, {{0, true}}}, k + 1});
    std::reverse(ts.begin(), ts.end());
    r.push_back({"unitary reversed targets k=" + std::to_string(k),
                 qrm::op::unitary_op{random_unitary(k, g, complex_values), ts, {{0, false}}}, k + 1});
    std::vector<qubit_index> bits(k);
    std::iota(bits.begin(), bits.end(), 1u);
    for (std::int64_t c : {std::int64_t{1}, std::int64_t{-1}, std::int64_t{3}}) {
      r.push_back({"add " + std::to_string(c) + " k=" + std::to_string(k), qrm::op::add_op{c, bits, {}}, k + 1});
      // One control below the register, one above.
      r.push_back({"add " + std::to_string(c) + " k=" + std::to_string(k) + " controlled",
                   qrm::op::add_op{c, bits, {{0, true}, {static_cast<qubit_index>(k + 1), false}}}, k + 2});
      // Only above: the in-place rotation.
      r.push_back({"add " + std::to_string(c) + " k=" + std::to_string(k) + " controlled above",
                   qrm::op::add_op{c, bits, {{static_cast<qubit_index>(k + 1), true}}}, k + 2});
    }
  }
  r.push_back({"diagonal k=2", qrm::op::unitary_op{random_diagonal(2, g, complex_values), {1, 2}, {{0, true}}}, 3});
  {
    std::vector<qrm::mux1_entry> es = {{0, random_gate1_unitary(g, complex_values)},
                                       {1, qrm::gate::ry(0.3)},
                                       {3, random_gate1_unitary(g, complex_values)}};
    r.push_back({"mux1 target below select", qrm::op::mux1_op{es, 0, {1, 2}, {{3, true}}}, 4});
    r.push_back({"mux1 target above select", qrm::op::mux1_op{es, 3, {0, 2}, {{1, false}}}, 4});
    std::vector<qrm::mux1_entry> diag = {{0, qrm::gate::z()}, {2, qrm::gate::u(-1.0, 0, 0, 1.0)}};
    r.push_back({"mux1 diagonal", qrm::op::mux1_op{diag, 2, {0, 1}, {}}, 3});
  }
  for (std::size_t k = 1; k <= 3; ++k) {
    std::vector<qrm::dense_matrix> ms = {random_unitary(k, g, complex_values), random_unitary(k, g, complex_values)};
    std::vector<qubit_index> ts(k);
    std::iota(ts.begin(), ts.end(), 0u);
    const auto s0 = static_cast<qubit_index>(k), s1 = static_cast<qubit_index>(k + 1);
    std::vector<qrm::mux_unitary_entry> es = {{0, 1}, {1, 0}, {3, 1}};
    r.push_back({"mux unitary k=" + std::to_string(k),
                 qrm::op::mux_unitary_op{ms, es, ts, {s0, s1}, {{static_cast<qubit_index>(k + 2), true}}}, k + 3});
  }
  return r;
}

}  // namespace

TEST_CASE_TEMPLATE("each op kind is the whole intended unitary (maximally entangled input, reference inverse)", S,
                   double, cd) {
  constexpr bool complex_values = qrm::detail::scalar_traits<S>::is_complex;
  const auto ops = every_op_kind(complex_values);
  for (const auto& o : ops)
    for (bool contiguous : {true, false}) {
      INFO(o.name << (contiguous ? " (contiguous)" : " (interleaved)"));
      // The state has 2^m amplitudes of size 2^(-m/2); a few dozen roundings of ~1e-16 each.
      CHECK(roundtrip_error<S>(o.op, o.qubits, contiguous) <= 1e-10);
    }
}

TEST_CASE("the unitary check fails for a wrong op (it can fail)") {
  // Applying ry(0.7) but inverting ry(0.71) must leave a visible error.
  const qrm::op::any applied = qrm::op::gate1_op{qrm::gate::ry(0.7), 0, {}};
  qrm::compact_state<double> c(2);
  c.apply_gate1(qrm::gate::h(), 1, {});
  const control ctl{1, true};
  c.apply_gate1(qrm::gate::x(), 0, std::span<const control>(&ctl, 1));
  qrm::emit_op(applied, c);
  reference_state ref(2);
  ref.amp = dump(c);
  ref.apply_gate1(qrm::gate::ry(-0.71), 0, {});
  ref.apply_gate1(qrm::gate::x(), 0, std::span<const control>(&ctl, 1));
  ref.apply_gate1(qrm::gate::h(), 1, {});
  CHECK(std::abs(ref.amp[0] - 1.0) > 1e-6);
}

// ---- (c) pruning -----------------------------------------------------------------------------------

TEST_CASE("exact zeros are never stored") {
  qrm::compact_state<cd> s(12);
  for (qubit_index q = 0; q < 12; ++q) s.apply_gate1(qrm::gate::h(), q, {});
  CHECK(s.nonzeros() == 4096);
  // H H = I: the |1> amplitudes cancel exactly (products of 1/sqrt(2) are equal in floating point).
  for (qubit_index q = 0; q < 12; ++q) s.apply_gate1(qrm::gate::h(), q, {});
  CHECK(s.nonzeros() == 1);
  CHECK(std::abs(s.amplitude(0) - 1.0) <= 1e-14);  // 24 layers of H, each rounding once (~1e-16)
  // A projector zeroes half of a superposition; those amplitudes go too.
  s.apply_gate1(qrm::gate::h(), 3, {});
  s.apply_gate1(qrm::gate::u(1.0, 0.0, 0.0, 0.0), 3, {});
  CHECK(s.nonzeros() == 1);
  CHECK(well_formed(s));
  CHECK(s.pruned().count == 0);  // exact zeros are not "pruned"
}

TEST_CASE("relative pruning never deletes a uniform superposition (2^k states, k <= 20, 40 qubits)") {
  // An absolute cut |a|^2 < 1e-12 would delete all of a uniform superposition over 40 qubits;
  // the relative cut compares with the mean probability, which every amplitude here equals.
  qrm::compact_options opt;
  opt.prune_threshold = 0.5;
  qrm::compact_state<double> s(40, opt);
  for (std::size_t k = 1; k <= 20; ++k) {
    s.apply_gate1(qrm::gate::h(), static_cast<qubit_index>(2 * k - 1), {});  // spread over the register
    CHECK(s.nonzeros() == (std::size_t{1} << k));
  }
  CHECK(s.pruned().count == 0);
  CHECK(s.norm_squared() == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("pruning reports what it removed, and that is exactly the change of the norm") {
  // A product state with probabilities spread over many orders of magnitude.
  qrm::compact_state<cd> s(10);
  for (qubit_index q = 0; q < 10; ++q) s.apply_gate1(qrm::gate::ry(0.02 + 0.25 * q), q, {});
  s.apply_gate1(qrm::gate::phase(0.3), 4, {});
  const auto before = dump(s);
  const double norm_before = s.norm_squared();
  const std::size_t n_before = s.nonzeros();
  const double eps = 0.01;
  // Independent count from the dense copy, by the documented rule.
  const double cut = eps * norm_before / static_cast<double>(n_before);
  std::uint64_t expect_count = 0;
  double expect_mass = 0;
  for (const cd& a : before)
    if (a != cd{} && std::norm(a) < cut) {
      ++expect_count;
      expect_mass += std::norm(a);
    }
  REQUIRE(expect_count > 0);
  const qrm::prune_stats removed = s.prune(eps);
  CHECK(removed.count == expect_count);
  CHECK(s.nonzeros() == n_before - expect_count);
  // Sums of ~1000 terms of size <= 1: agreement to ~1e-15; 1e-13 leaves room.
  CHECK(std::abs(removed.probability - expect_mass) <= 1e-13);
  CHECK(std::abs((norm_before - s.norm_squared()) - removed.probability) <= 1e-13);
  CHECK(removed.probability < eps * norm_before);  // the bound the rule guarantees
  // The survivors are untouched.
  const auto after = dump(s);
  for (std::size_t i = 0; i < before.size(); ++i)
    if (std::norm(before[i]) >= cut) CHECK(after[i] == before[i]);
  CHECK(s.pruned().count == expect_count);
}

TEST_CASE("automatic pruning after each op accumulates its report") {
  qrm::compact_options opt;
  opt.prune_threshold = 1e-3;
  qrm::compact_state<double> pruned(8, opt), exact(8);
  double lost = 0;
  for (qubit_index q = 0; q < 8; ++q) {
    const qrm::gate1 g = qrm::gate::ry(0.01 + 0.1 * q);
    const double before = pruned.norm_squared();
    const double mass_before = pruned.pruned().probability;
    pruned.apply_gate1(g, q, {});
    exact.apply_gate1(g, q, {});
    // Unitary op, then pruning: the norm drops by exactly the reported mass (up to rounding).
    CHECK(std::abs((before - pruned.norm_squared()) - (pruned.pruned().probability - mass_before)) <= 1e-14);
    lost = pruned.pruned().probability;
  }
  CHECK(pruned.pruned().count > 0);
  CHECK(pruned.nonzeros() < exact.nonzeros());
  CHECK(std::abs((1.0 - pruned.norm_squared()) - lost) <= 1e-14);
}

// ---- (d) wide labels --------------------------------------------------------------------------------

TEST_CASE("circuits on 100 qubits (wide labels) equal the same circuit on 20 qubits, dense and compact") {
  // Active qubit i sits at pos[i]: runs across the 64-bit word boundary, at the very top, at the
  // bottom, and out of order, so both the merging and the sorting paths see wide labels.
  const std::vector<qubit_index> pos = {61, 62, 63, 64, 65, 66, 0, 1, 2, 97, 98, 99, 30, 31, 32, 33, 45, 80, 81, 10};
  qrm::rng g(303);
  for (int round = 0; round < 4; ++round) {
    const qrm::program p = random_program(g, pos.size(), 60, true);
    qrm::compact_state<cd, qrm::wide_label<2>> wide(100);
    qrm::compact_state<cd> narrow(pos.size());
    qrm::state_vector<cd> dense(pos.size(), qrm::dense_options{1});
    for (const auto& o : p.ops()) qrm::emit_op(remap(o, pos), wide);
    qrm::run(narrow, p);
    qrm::run(dense, p);
    INFO("round " << round << " nonzeros " << wide.nonzeros());
    CHECK(well_formed(wide));
    // Same bar as (a): 60 ops of a few roundings each on amplitudes <= 1.
    CHECK(max_diff(gather_dense(wide, pos), dump(dense)) <= 1e-12);
    // Each output amplitude is computed by the same arithmetic wherever its qubits sit.
    CHECK(max_diff(gather_dense(wide, pos), dump(narrow)) == 0.0);
  }
}

TEST_CASE("uint64 labels use all 64 qubits; wide_label<3> reaches past 128") {
  qrm::rng g(304);
  {
    const std::vector<qubit_index> pos = {60, 61, 62, 63, 0, 1, 2, 3, 31, 32, 33, 50};
    const qrm::program p = random_program(g, pos.size(), 50, false);
    qrm::compact_state<double> wide(64);
    qrm::state_vector<double> dense(pos.size(), qrm::dense_options{1});
    for (const auto& o : p.ops()) qrm::emit_op(remap(o, pos), wide);
    qrm::run(dense, p);
    CHECK(well_formed(wide));
    CHECK(max_diff(gather_dense(wide, pos), dump(dense)) <= 1e-12);
  }
  {
    const std::vector<qubit_index> pos = {126, 127, 128, 129, 130, 5, 6, 63, 64, 191};
    const qrm::program p = random_program(g, pos.size(), 50, true);
    qrm::compact_state<cd, qrm::wide_label<3>> wide(192);
    qrm::state_vector<cd> dense(pos.size(), qrm::dense_options{1});
    for (const auto& o : p.ops()) qrm::emit_op(remap(o, pos), wide);
    qrm::run(dense, p);
    CHECK(well_formed(wide));
    CHECK(max_diff(gather_dense(wide, pos), dump(dense)) <= 1e-12);
  }
}

TEST_CASE("a 3-qubit register straddling the word boundary counts like a number") {
  qrm::compact_state<double, qrm::wide_label<2>> s(128);
  const std::vector<qubit_index> reg = {63, 64, 65};
  for (int i = 0; i < 5; ++i) s.apply_add(1, reg, {});
  qrm::wide_label<2> five;
  five.set(63).set(65);  // 5 = 0b101 on qubits 63 (low), 64, 65
  CHECK(s.amplitude(five) == 1.0);
  s.apply_add(4, reg, {});  // 9 mod 8 = 1
  CHECK(s.amplitude(qrm::wide_label<2>().set(63)) == 1.0);
  CHECK(s.nonzeros() == 1);
}

// ---- determinism, measurement, memory --------------------------------------------------------------

TEST_CASE("same ops, same bits: a round trip through a dense vector midway changes nothing") {
  qrm::rng g(405);
  const qrm::program p = random_program(g, 10, 80, true);
  qrm::compact_state<cd> a(10), b(10);
  for (std::size_t i = 0; i < p.size(); ++i) {
    qrm::emit_op(p.ops()[i], a);
    qrm::emit_op(p.ops()[i], b);
    if (i == 40) {
      const auto d = b.to_dense();
      b = qrm::compact_state<cd>(10);
      b.set_amplitudes(d);
    }
  }
  REQUIRE(a.nonzeros() == b.nonzeros());
  bool identical = true;
  for (std::size_t i = 0; i < a.nonzeros(); ++i)
    identical = identical && a.entries()[i].label == b.entries()[i].label && a.entries()[i].amp == b.entries()[i].amp;
  CHECK(identical);
  CHECK(a.norm_squared() == b.norm_squared());
}

namespace {
using x_reg = qrm::position<"x", 3>;
using dir_reg = qrm::direction<3>;
using le_reg = qrm::emission<3>;
using out_reg = qrm::output<>;
using walk_layout = qrm::layout<x_reg, dir_reg, le_reg, out_reg>;
}  // namespace

TEST_CASE("static circuits run and measure through the layout API like on the dense backend") {
  const auto c = qrm::make_circuit<walk_layout>(qrm::h<dir_reg>{}, qrm::increment<x_reg, qrm::when<dir_reg, 3>>{},
                                                qrm::add<x_reg, -3, qrm::when<dir_reg, 5>>{},
                                                qrm::mux_ry<qrm::bit<le_reg, 1>, x_reg>{{1, 0.3}, {6, 1.2}, {0, 0.5}},
                                                qrm::ry<out_reg, qrm::on<qrm::bit<le_reg, 1>>>{0.8});
  using C = decltype(c);
  static_assert(qrm::can_run<C, qrm::compact_state<double>>);
  static_assert(
      !qrm::can_run<decltype(qrm::make_circuit<walk_layout>(qrm::phase<out_reg>{0.5})), qrm::compact_state<double>>);
  qrm::compact_state<double> compact(walk_layout::width);
  qrm::state_vector<double> dense(walk_layout::width);
  qrm::run(compact, c);
  qrm::run(dense, c);
  // Sums of a handful of probabilities: a few roundings.
  CHECK(qrm::probability<walk_layout, qrm::on<out_reg>>(compact) ==
        doctest::Approx(qrm::probability<walk_layout, qrm::on<out_reg>>(dense)).epsilon(1e-13));
  const auto pc = qrm::distribution<walk_layout, x_reg>(compact), pd = qrm::distribution<walk_layout, x_reg>(dense);
  REQUIRE(pc.size() == pd.size());
  for (std::size_t v = 0; v < pc.size(); ++v) CHECK(pc[v] == doctest::Approx(pd[v]).epsilon(1e-13));
  qrm::rng g(7);
  const auto counts = qrm::sample_counts<walk_layout, x_reg>(compact, 1000, g);
  CHECK(std::accumulate(counts.begin(), counts.end(), std::uint64_t{0}) == 1000);
  CHECK(compact.nonzeros() < (std::size_t{1} << walk_layout::width));
}

TEST_CASE("memory follows the nonzeros, and the peak covers every allocation") {
  qrm::compact_state<cd> s(32);
  const std::size_t entry_bytes = sizeof(qrm::compact_state<cd>::entry);
  for (qubit_index q = 0; q < 16; ++q) s.apply_gate1(qrm::gate::h(), 2 * q, {});
  CHECK(s.nonzeros() == 65536);
  CHECK(s.memory_bytes() >= 65536 * entry_bytes);
  CHECK(s.peak_memory_bytes() >= s.memory_bytes());
  // Three buffers of (at most twice) the state at once is the design's bound.
  CHECK(s.peak_memory_bytes() <= 8 * 65536 * entry_bytes);
  for (qubit_index q = 0; q < 16; ++q) s.apply_gate1(qrm::gate::h(), 2 * q, {});
  CHECK(s.nonzeros() == 1);
  CHECK(s.peak_memory_bytes() <= 8 * 65536 * entry_bytes);
  // After the state collapsed, buffers much larger than it were released (4096 spare entries kept).
  CHECK(s.memory_bytes() <= 3 * 4096 * entry_bytes);
  s.shrink_to_fit();
  CHECK(s.memory_bytes() <= 64 * entry_bytes);
}

// ---- (e) bad input ------------------------------------------------------------------------------------

TEST_CASE("bad input is refused with an error naming the problem and the value") {
  CHECK(contains(error_of([] { qrm::compact_state<double> s(65); }), "65 qubits do not fit a 64-qubit label"));
  CHECK(contains(error_of([] { qrm::compact_state<double, qrm::wide_label<2>> s(129); }),
                 "129 qubits do not fit a 128-qubit"));
  CHECK(contains(error_of([] { qrm::compact_state<double> s(65); }), "wide_label<2>"));
  CHECK(error_of([] { qrm::compact_state<double, qrm::wide_label<2>> s(128); }) == "(no error)");

  qrm::compact_state<double> s(4);
  qrm::compact_state<cd, qrm::wide_label<2>> w(100);
  const std::vector<control> twice = {{1, true}, {1, false}};
  const std::vector<control> far = {{7, true}};
  CHECK(contains(error_of([&] { s.apply_gate1(qrm::gate::h(), 4, {}); }), "qubit 4 is outside the 4-qubit state"));
  CHECK(
      contains(error_of([&] { w.apply_gate1(qrm::gate::h(), 100, {}); }), "qubit 100 is outside the 100-qubit state"));
  CHECK(contains(error_of([&] { s.apply_gate1(qrm::gate::h(), 0, twice); }), "qubit 1 is controlled twice"));
  CHECK(contains(error_of([&] { s.apply_gate1(qrm::gate::h(), 0, far); }), "control qubit 7 is outside"));
  const std::vector<control> on_target = {{0, true}};
  CHECK(contains(error_of([&] { s.apply_gate1(qrm::gate::h(), 0, on_target); }), "qubits_must_be_disjoint"));
  const std::vector<qubit_index> dup = {1, 1};
  CHECK(contains(error_of([&] { s.apply_add(1, dup, {}); }), "qubit 1 is used twice"));
  const std::vector<qubit_index> two = {0, 1};
  CHECK(contains(error_of([&] { s.apply_unitary(qrm::dense_matrix::identity(2), two, {}); }),
                 "a 2x2 matrix cannot act on 2 qubits"));
  const std::vector<qubit_index> sel = {1, 2};
  const std::vector<qrm::mux1_entry> big = {{4, qrm::gate::x()}};
  CHECK(contains(error_of([&] { s.apply_mux1(big, 0, sel, {}); }), "select value 4 does not fit 2 select qubits"));
  const std::vector<qrm::mux1_entry> again = {{2, qrm::gate::x()}, {2, qrm::gate::h()}};
  CHECK(contains(error_of([&] { s.apply_mux1(again, 0, sel, {}); }), "select value 2 has two entries"));
  const std::vector<qrm::dense_matrix> ms = {qrm::dense_matrix::identity(2)};
  const std::vector<qrm::mux_unitary_entry> bad_matrix = {{0, 1}};
  const std::vector<qubit_index> t0 = {0};
  CHECK(contains(error_of([&] { s.apply_mux_unitary(ms, bad_matrix, t0, sel, {}); }), "names matrix 1 of 1"));
  CHECK(contains(error_of([&] { s.apply_mux1(big, 1, sel, {}); }), "qubit 1 is used twice"));

  // A complex gate on a real backend: the same rule as the dense backend, directly and through run().
  CHECK(contains(error_of([&] { s.apply_gate1(qrm::gate::phase(0.3), 0, {}); }), "complex_gate_needs_complex_backend"));
  qrm::program complex_program(4);
  complex_program.apply_gate1(qrm::gate::y(), 2, {});
  CHECK(contains(error_of([&] { qrm::run(s, complex_program); }), "complex matrix"));
  qrm::program wide_program(9);
  CHECK(contains(error_of([&] { qrm::run(s, wide_program); }), "needs 9 qubits but the backend has 4"));

  CHECK(contains(error_of([&] { (void)s.amplitude(16); }), "label 16 does not fit 4 qubits"));
  CHECK(contains(error_of([&] { s.set_basis_state(17); }), "label 17 does not fit 4 qubits"));
  qrm::wide_label<2> high;
  high.set(100);
  CHECK(contains(error_of([&] { (void)w.amplitude(high); }), "does not fit 100 qubits"));
  CHECK(contains(error_of([&] { s.set_amplitudes(std::vector<double>(15)); }), "got 15 amplitudes, need 2^4"));
  CHECK(contains(error_of([&] { (void)w.to_dense(); }), "100 qubits are too many"));
  CHECK(contains(error_of([&] { s.prune(1.0); }), "must be in [0, 1), got 1"));
  CHECK(contains(error_of([&] { s.set_prune_threshold(-0.1); }), "got -0.1"));
  CHECK(contains(error_of([&] { s.prune(std::nan("")); }), "must be in [0, 1)"));
  std::vector<qubit_index> reg65(65);
  std::iota(reg65.begin(), reg65.end(), 0u);
  CHECK(contains(error_of([&] { w.apply_add(1, reg65, {}); }), "register of 65 qubits"));
  // Nothing above changed the state.
  CHECK(s.nonzeros() == 1);
  CHECK(s.amplitude(0) == 1.0);
}

TEST_CASE("every argument check gives the dense backend's message, word for word") {
  // One list of bad calls, run on both backends; only the class name in the real-amplitude rule
  // differs.
  auto messages = [](auto& b) {
    const std::vector<control> twice = {{1, true}, {1, false}}, far = {{7, true}}, on_target = {{0, true}};
    const std::vector<qubit_index> dup = {1, 1}, two = {0, 1}, sel = {1, 2}, t0 = {0};
    const std::vector<qrm::mux1_entry> big = {{4, qrm::gate::x()}}, again = {{2, qrm::gate::x()}, {2, qrm::gate::h()}};
    const std::vector<qrm::mux1_entry> complex_entry = {{1, qrm::gate::phase(0.2)}};
    const std::vector<qrm::dense_matrix> ms = {qrm::dense_matrix::identity(2)}, ms4 = {qrm::dense_matrix::identity(4)};
    const std::vector<qrm::mux_unitary_entry> bad_matrix = {{0, 1}}, ok = {{0, 0}};
    std::vector<qrm::dense_matrix> phase = {qrm::dense_matrix::identity(2)};
    phase[0](1, 1) = cd(0, 1);
    return std::vector<std::string>{
        error_of([&] { b.apply_gate1(qrm::gate::h(), 4, {}); }),
        error_of([&] { b.apply_gate1(qrm::gate::h(), 0, twice); }),
        error_of([&] { b.apply_gate1(qrm::gate::h(), 0, far); }),
        error_of([&] { b.apply_gate1(qrm::gate::h(), 0, on_target); }),
        error_of([&] { b.apply_gate1(qrm::gate::phase(0.3), 0, {}); }),
        error_of([&] { b.apply_unitary(qrm::dense_matrix::identity(2), two, {}); }),
        error_of([&] { b.apply_unitary(qrm::dense_matrix::identity(4), dup, {}); }),
        error_of([&] { b.apply_add(1, dup, {}); }),
        error_of([&] { b.apply_add(1, t0, on_target); }),
        error_of([&] { b.apply_mux1(big, 0, sel, {}); }),
        error_of([&] { b.apply_mux1(again, 0, sel, {}); }),
        error_of([&] { b.apply_mux1(big, 1, sel, {}); }),
        error_of([&] { b.apply_mux1(complex_entry, 0, sel, {}); }),
        error_of([&] { b.apply_mux_unitary(ms, bad_matrix, t0, sel, {}); }),
        error_of([&] { b.apply_mux_unitary(ms4, ok, t0, sel, {}); }),
        error_of([&] { b.apply_mux_unitary(ms, ok, t0, sel, far); }),
        error_of([&] { b.apply_mux_unitary(phase, ok, t0, sel, {}); }),
        error_of([&] { (void)b.probability(twice); }),
        error_of([&] { (void)b.distribution(dup); }),
    };
  };
  qrm::state_vector<double> d(4);
  qrm::compact_state<double> c(4);
  const auto from_dense = messages(d), from_compact = messages(c);
  REQUIRE(from_dense.size() == from_compact.size());
  for (std::size_t i = 0; i < from_dense.size(); ++i) {
    INFO("call " << i << ": " << from_dense[i]);
    CHECK(from_dense[i] != "(no error)");
    std::string expected = from_dense[i];
    const auto at = expected.find("state_vector<");
    if (at != std::string::npos) expected.replace(at, 12, "compact_state");
    CHECK(from_compact[i] == expected);
  }
}
