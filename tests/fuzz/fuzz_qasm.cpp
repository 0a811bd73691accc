// libFuzzer target for the OpenQASM 3 importer and exporter (qrm/circuit/qasm.hpp). The first byte picks
// the mode:
//  - even: text mode. The whole input is OpenQASM text. from_qasm must return a program or throw
//    qrm::qasm_error (never crash, hang, or throw anything else). A program it accepts must
//    export (to_qasm), import again to the same width, and -- up to 12 qubits -- simulate on the
//    dense backend to the same state as the first import.
//  - odd: structured mode. The bytes are decoded into a small program of the five primitive ops
//    (every op kind, random placements, positive and negative controls, named, general and
//    exactly special gates, extreme add constants); it is exported in the logical and the
//    decomposed form, imported, and simulated against the original from a fixed state.
// Any mismatch or unexpected exception aborts with a message. Seeds: tests/fuzz/corpus/qasm
// (text seeds begin with a newline, which is even; structured seeds with an odd byte).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <qrm/backends/dense.hpp>
#include <qrm/circuit/qasm.hpp>
#include <qrm/support/random.hpp>

#include "support/random_ops.hpp"
#include "support/random_programs.hpp"

namespace {

using cvec = std::vector<std::complex<double>>;

// Simulations of a program and of its round trip agree to this: the exporter writes angles with
// 17 digits (exact), so differences are rounding in re-derived U angles and in the two-level
// bodies of dense matrices, ~1e-13 for the sizes decoded here; a lost control, phase or qubit
// is O(1).
constexpr double tolerance = 1e-9;
constexpr std::size_t max_simulated_width = 12;
constexpr std::size_t max_decomposed_gates = 3000;

[[noreturn]] void fail(const std::string& what, const std::string& text) {
  std::fprintf(stderr, "fuzz_qasm: %s\n--- exported text ---\n%s\n", what.c_str(), text.c_str());
  std::abort();
}

// A fixed normalised state of n qubits (the same for every input, so a mismatch reproduces).
const cvec& fixed_state(std::size_t n) {
  static std::vector<cvec> cache(max_simulated_width + 1);
  cvec& s = cache.at(n);
  if (s.empty()) {
    qrm::rng g(1234 + n);
    s = qrm_test::random_unit_state(n, g);
  }
  return s;
}

// p run on the dense backend from fixed_state(n), n <= p's width (extra qubits start in |0>).
cvec simulate(const qrm::program& p, std::size_t n) {
  return qrm_test::run_from(p, fixed_state(n));
}

double max_diff(const cvec& a, const cvec& b, std::size_t count) {
  double d = 0;
  for (std::size_t i = 0; i < count; ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// Exports p (logical and decomposed), imports both, and compares the simulations with `want`
// (p simulated from fixed_state(p.width())). `options` picks comments and decomposition options.
void check_round_trips(const qrm::program& p, const cvec& want, std::uint8_t options, bool decomposed_too) {
  const std::size_t n = p.width();
  qrm::qasm_options logical;
  logical.comments = (options & 1u) != 0;
  const std::string text = qrm::to_qasm(p, logical);
  const qrm::program back = qrm::from_qasm(text);
  if (back.width() != n)
    fail("logical round trip changed the width from " + std::to_string(n) + " to " + std::to_string(back.width()), text);
  if (n <= max_simulated_width) {
    const double d = max_diff(want, simulate(back, n), want.size());
    if (!(d < tolerance)) fail("logical round trip differs by " + std::to_string(d), text);
  }
  if (!decomposed_too) return;
  qrm::qasm_options dec = logical;
  dec.decomposed = true;
  dec.decomposition.keep_toffoli = (options & 2u) != 0;
  dec.decomposition.relative_phase_toffoli = (options & 4u) != 0;
  dec.decomposition.optimize = (options & 8u) == 0;
  // Large decompositions (a controlled 3-qubit unitary is thousands of gates) are parsed and
  // simulated at a few ms each under the sanitizers; the unit tests round-trip those. Here the
  // decomposed form is checked where it stays small, which keeps the fuzzer fast.
  const qrm::decomposition_result lowered = qrm::decompose(p, dec.decomposition);
  if (lowered.circuit.size() > max_decomposed_gates) return;
  const std::string dtext = qrm::to_qasm(p, dec);
  const qrm::program dback = qrm::from_qasm(dtext);
  if (dback.width() < n) fail("decomposed round trip lost qubits", dtext);
  if (dback.width() > max_simulated_width + 2) return;  // too many ancillas to simulate densely (rare)
  const cvec got = simulate(dback, n);
  const double d = max_diff(want, got, want.size());
  if (!(d < tolerance)) fail("decomposed round trip differs by " + std::to_string(d), dtext);
  double ancilla = 0;
  for (std::size_t i = want.size(); i < got.size(); ++i) ancilla += std::norm(got[i]);
  // Clean ancillas end in |0>: what is left is rounding (~1e-30); one left in |1> is O(1).
  if (!(ancilla < tolerance * tolerance)) fail("decomposed round trip leaves ancillas with norm^2 " + std::to_string(ancilla), dtext);
}

// ---- text mode --------------------------------------------------------------------------------

void text_mode(std::string_view text) {
  qrm::program p;
  try {
    p = qrm::from_qasm(text);
  } catch (const qrm::qasm_error&) {
    return;  // rejected with a located message: fine
  }
  // Accepted: everything from here on must work.
  const bool simulate_it = p.width() <= max_simulated_width;
  const cvec want = simulate_it ? simulate(p, p.width()) : cvec{};
  check_round_trips(p, want, 1, false);
}

// ---- structured mode --------------------------------------------------------------------------

class byte_reader {
 public:
  byte_reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t next() { return pos_ < size_ ? data_[pos_++] : 0; }
  bool empty() const { return pos_ >= size_; }
  std::uint64_t below(std::uint64_t n) { return next() % n; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | next();
    return v;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

double decode_angle(byte_reader& r) {
  const double pi = std::acos(-1.0);
  static const double special[] = {0.0, pi, -pi, pi / 2, 2 * pi, 4 * pi, -4 * pi, 1e-300, 1e-17, 5e-324, 1e6, -1e6, 3e15};
  const std::uint8_t c = r.next();
  if (c < std::size(special)) return special[c];
  const std::uint16_t v = static_cast<std::uint16_t>(r.next() << 8 | r.next());
  return (static_cast<double>(v) / 65535.0 - 0.5) * 8 * pi;
}

// e^{i gamma} [[cos t/2, -e^{i l} sin t/2], [e^{i p} sin t/2, e^{i (p + l)} cos t/2]] (kind u).
// e^{i (p + l)} is formed as e^{i p} e^{i l}: for huge angles p + l rounds (the ulp of 3e15 is
// 0.5) and the matrix would not be unitary.
qrm::gate1 general_gate(double theta, double phi, double lambda, double gamma) {
  const double c = std::cos(theta / 2), s = std::sin(theta / 2);
  const std::complex<double> g = std::polar(1.0, gamma), ep = std::polar(1.0, phi), el = std::polar(1.0, lambda);
  return qrm::gate::u(g * c, -g * el * s, g * ep * s, g * ep * el * c);
}

qrm::gate1 decode_gate(byte_reader& r, bool ry_only) {
  if (ry_only) return qrm::gate::ry(decode_angle(r));
  const std::complex<double> i(0, 1);
  const double h = 1 / std::sqrt(2.0);
  switch (r.below(10)) {
    case 0: return qrm::gate::x();
    case 1: return qrm::gate::y();
    case 2: return qrm::gate::z();
    case 3: return qrm::gate::h();
    case 4: return qrm::gate::ry(decode_angle(r));
    case 5: return qrm::gate::rz(decode_angle(r));
    case 6: return qrm::gate::phase(decode_angle(r));
    case 7: {
      const double t = decode_angle(r), p = decode_angle(r), l = decode_angle(r);
      return general_gate(t, p, l, decode_angle(r));
    }
    case 8: {  // kind u but exactly a special matrix (the exporter must still get it right)
      switch (r.below(7)) {
        case 0: return qrm::gate::u(0.0, 1.0, 1.0, 0.0);    // X
        case 1: return qrm::gate::u(1.0, 0.0, 0.0, 1.0);    // identity
        case 2: return qrm::gate::u(-1.0, 0.0, 0.0, -1.0);  // -I: a pure global phase
        case 3: return qrm::gate::u(0.0, i, i, 0.0);        // i X
        case 4: return qrm::gate::u(i, 0.0, 0.0, -i);       // diag(i, -i)
        case 5: return qrm::gate::u(h * i, h * i, h * i, -h * i);  // i H
        default: return qrm::gate::u(0.0, -1.0, 1.0, 0.0);  // -i Y
      }
    }
    default: {  // a named kind whose angle is a multiple of 2 pi or huge
      const double pi = std::acos(-1.0);
      const double a = r.below(2) ? 2 * pi * static_cast<double>(r.below(5)) : 1e12 + decode_angle(r);
      switch (r.below(3)) {
        case 0: return qrm::gate::ry(a);
        case 1: return qrm::gate::rz(a);
        default: return qrm::gate::phase(a);
      }
    }
  }
}

qrm::dense_matrix decode_matrix(byte_reader& r, std::size_t k) {
  const std::size_t d = std::size_t{1} << k;
  qrm::rng g(r.u32());
  switch (r.below(6)) {
    case 0: return qrm_test::random_unitary(k, g, true);
    case 1: return qrm_test::random_unitary(k, g, false);
    case 2: return k >= 2 ? qrm_test::sparse_coin(k, g) : qrm_test::random_unitary(k, g, false);
    case 3: {  // an exact permutation
      qrm::dense_matrix m(d);
      const auto perm = qrm_test::shuffled_qubits(d, g);
      for (std::size_t c = 0; c < d; ++c) m(perm[c], c) = 1.0;
      return m;
    }
    case 4: {  // exact diagonal phases (some exactly 1)
      qrm::dense_matrix m(d);
      for (std::size_t c = 0; c < d; ++c) m(c, c) = g.below(3) == 0 ? std::complex<double>(1.0) : std::polar(1.0, 6.3 * g.uniform());
      return m;
    }
    default: return qrm::dense_matrix::identity(d);
  }
}

std::vector<qrm::control> decode_controls(byte_reader& r, std::vector<qrm::qubit_index>& pool, std::size_t max) {
  const std::uint8_t b = r.next();
  const std::size_t count = std::min<std::size_t>({static_cast<std::size_t>(b & 7u), max, pool.size()});
  std::vector<qrm::control> cs;
  for (std::size_t i = 0; i < count; ++i) {
    cs.push_back({pool.back(), ((b >> (3 + i)) & 1u) == 0});
    pool.pop_back();
  }
  return cs;
}

std::int64_t decode_constant(byte_reader& r, std::size_t k) {
  const std::int64_t dim = std::int64_t{1} << k;
  switch (r.below(8)) {
    case 0: return std::numeric_limits<std::int64_t>::min();
    case 1: return std::numeric_limits<std::int64_t>::max();
    case 2: return 0;
    case 3: return dim * (static_cast<std::int64_t>(r.below(5)) - 2);  // a multiple of 2^k: identity
    default: return static_cast<std::int8_t>(r.next());
  }
}

// One op on n qubits, all operands distinct.
qrm::op::any decode_op(byte_reader& r, std::size_t n) {
  qrm::rng g(r.next());
  std::vector<qrm::qubit_index> pool = qrm_test::shuffled_qubits(n, g);
  auto take = [&](std::size_t count) { return qrm_test::take(pool, count); };
  std::size_t kind = r.below(5);
  if ((kind == 3 && n < 2) || (kind == 4 && n < 2)) kind = 0;
  switch (kind) {
    case 1: {
      const std::size_t k = 1 + r.below(std::min<std::size_t>(3, n));
      auto ts = take(k);
      auto m = decode_matrix(r, k);
      return qrm::op::unitary_op{std::move(m), std::move(ts), decode_controls(r, pool, 3)};
    }
    case 2: {
      const std::size_t k = 1 + r.below(std::min<std::size_t>(4, n));
      auto bits = take(k);
      const std::int64_t c = decode_constant(r, k);
      return qrm::op::add_op{c, std::move(bits), decode_controls(r, pool, 3)};
    }
    case 3: {
      const qrm::qubit_index t = take(1)[0];
      const std::size_t m = 1 + r.below(std::min<std::size_t>(3, pool.size()));
      auto sel = take(m);
      const bool ry_only = r.below(2) == 0;  // all-Ry multiplexers take the Mottonen path
      const std::uint8_t mask = r.next();
      std::vector<qrm::mux1_entry> es;
      for (std::uint64_t s = 0; s < (std::uint64_t{1} << m); ++s)
        if ((mask >> s) & 1u) es.push_back({s, decode_gate(r, ry_only)});
      return qrm::op::mux1_op{std::move(es), t, std::move(sel), decode_controls(r, pool, 2)};
    }
    case 4: {
      const std::size_t k = 1 + r.below(std::min<std::size_t>(2, n - 1));
      auto ts = take(k);
      const std::size_t m = 1 + r.below(std::min<std::size_t>(2, pool.size()));
      auto sel = take(m);
      const std::size_t count = 1 + r.below(3);
      std::vector<qrm::dense_matrix> ms;
      for (std::size_t i = 0; i < count; ++i) ms.push_back(decode_matrix(r, k));
      const std::uint8_t mask = r.next();
      std::vector<qrm::mux_unitary_entry> es;
      for (std::uint64_t s = 0; s < (std::uint64_t{1} << m); ++s)
        if ((mask >> s) & 1u) es.push_back({s, static_cast<std::uint32_t>(r.below(count))});
      return qrm::op::mux_unitary_op{std::move(ms), std::move(es), std::move(ts), std::move(sel),
                                     decode_controls(r, pool, 1)};
    }
    default: {
      const qrm::qubit_index t = take(1)[0];
      qrm::gate1 gate = decode_gate(r, false);
      return qrm::op::gate1_op{gate, t, decode_controls(r, pool, 4)};
    }
  }
}

void structured_mode(const std::uint8_t* data, std::size_t size) {
  byte_reader r(data, size);
  const std::uint8_t options = static_cast<std::uint8_t>(r.next() >> 1);  // the mode bit is bit 0
  const std::size_t n = 1 + r.below(6);
  qrm::program p(n);
  for (int i = 0; i < 8 && !r.empty(); ++i) p.push(decode_op(r, n));
  check_round_trips(p, simulate(p, n), options, true);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    if (data[0] % 2 == 0)
      text_mode(std::string_view(reinterpret_cast<const char*>(data), size));
    else
      structured_mode(data, size);
  } catch (const std::exception& e) {
    // qasm_error is handled in text mode; anything else escaping is a bug.
    std::fprintf(stderr, "fuzz_qasm: unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
