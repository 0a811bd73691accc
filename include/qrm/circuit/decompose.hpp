// qrm/circuit/decompose.hpp: lowering a program to single-qubit gates and CNOTs (what hardware runs).
//
// The paper's circuits use multi-controlled and multiplexed gates as single logical operations
// (Section 6, Limitations). `decompose(p)` returns an equivalent program made only of
//   (a) single-qubit gate1 ops without controls, and
//   (b) CNOT: gate1 X with exactly one control of value 1,
// plus clean ancillas appended after p's qubits (they start and end in |0>; ancillas are
// reused between gates, so the count is the most needed at once). Every rule is exact,
// including global phases (a controlled gate exposes the phase of its target gate).
//
// Rules (N&C = Nielsen & Chuang, "Quantum Computation and Quantum Information", 10th ed.):
//  1. Negative controls: X on the control before and after.
//  2. Controlled single-qubit U (1 control), N&C section 4.3, Corollary 4.2 / Fig. 4.6: ZYZ
//     Euler angles U = e^{ia} Rz(b) Ry(c) Rz(d); A = Rz(b) Ry(c/2), B = Ry(-c/2) Rz(-(d+b)/2),
//     C = Rz((d-b)/2); circuit C, CNOT, B, CNOT, A on the target and phase(a) on the control:
//     2 CNOTs. Cheaper exact special cases: U = X is one CNOT; U = e^{ia} I is phase(a) on the
//     control (0 CNOTs); trace(U) = 0 (U = e^{ia} V X V^dagger: X, Y, Z, H, ...) is
//     V^dagger, CNOT, V and phase(a) on the control (1 CNOT).
//  3. k >= 2 controls (N&C Fig. 4.10): the AND of the controls is computed into k-1 clean
//     ancillas with Toffolis, U is applied controlled by the last ancilla (rule 2), and the
//     Toffolis are undone. X is cheaper: C^2 X is one Toffoli, C^k X computes the AND of the
//     first k-1 controls (k-2 Toffolis), applies Toffoli(ancilla, last control, target) and
//     undoes them. A controlled global phase C^k(e^{ia} I) is C^{k-1}-phase(a) on the last
//     control. Toffoli = 6 CNOTs + 2 H, 7 T or T^dagger and 1 S (N&C Fig. 4.9).
//     CNOT counts (default options): C^k X = 6 (2k-3) for k >= 2 (Toffoli 6, C^3 X 18,
//     C^5 X 42); C^k U = 12 (k-1) + 2 (generic U). With `relative_phase_toffoli`, the
//     compute/uncompute Toffolis into ancillas use the 3-CNOT relative-phase Toffoli
//     (Margolus; Maslov, Phys. Rev. A 93, 022311 (2016)), exact because every gate between the
//     compute and the uncompute uses those qubits only as controls: C^k X = 6k - 6,
//     C^k U = 6 (k-1) + 2.
//  4. Dense k-qubit unitary (N&C section 4.5.1, two-level / Givens decomposition): the
//     below-diagonal entries are eliminated column by column with two-level unitaries acting
//     on basis states |j>, |i>, entries below 1e-14 counting as zero (so sparse matrices, like
//     the paper's coins with entries 0 and +-1/2, give fewer factors; the error this admits is
//     below 1e-14 per skipped entry); a leftover diagonal phase is folded into the column's
//     last factor. Each two-level unitary on |s>, |t> is realised as in N&C Fig. 4.16: a
//     Gray code from s to t, multi-controlled X gates (all other register qubits as controls,
//     with the Gray code's values) move |s> next to |t>, one multi-controlled single-qubit gate
//     acts on the one differing qubit, and the X gates are undone; adjacent identical X gates of
//     consecutive factors cancel. Factors that are the identity are skipped. The op's own
//     controls are ANDed into one ancilla (rule 3) and added only to the middle gates (the
//     permutations cancel when the controls do not hold). Then everything is lowered by rules
//     1-3.
//  5. Add a constant c modulo 2^k: c is written in non-adjacent form (signed binary digits
//     +-1, fewest nonzero digits); digit +1 at j adds 2^j = increments bits j..k-1, digit -1
//     subtracts 2^j = X on bits j..k-1, increment, X again. Increment of r_0..r_{w-1} = for
//     i = w-1 down to 0: X on r_i controlled by r_0..r_{i-1} (the cascade from the most
//     significant bit down). Cost: for each nonzero digit j, sum_{i=0}^{k-j-1} C^i X (plus the
//     op's controls, ANDed into one ancilla), i.e. add 1 on 3 qubits = X + CNOT + Toffoli
//     = 7 CNOTs.
//  6. Multiplexed Ry (every entry a real rotation Ry): the uniformly controlled rotation of
//     Mottonen, Vartiainen, Bergholm, Salomaa, "Quantum circuits for general multiqubit gates",
//     PRL 93, 130502 (2004): 2^m Ry and 2^m CNOTs for m select qubits, CNOT controls in
//     Gray-code order and angles theta_i = 2^-m sum_s (-1)^{popcount(s & gray(i))} alpha_s
//     (a Walsh-Hadamard transform); the op's controls become extra select qubits (entries
//     only where they hold). Used when 2^{m+c} is at most the per-entry cost below.
//     Other multiplexed gates (and multiplexed Ry when cheaper): one multi-controlled gate per
//     entry (select qubits as controls with the entry's values), lowered by rules 1-4.
//
// Special cases (X, e^{ia} I, trace 0, identity factors, Ry entries) are recognised to 1e-14,
// so each admits an error below 1e-14, far under the 1e-12 the tests hold results to.
// Non-unitary matrices are rejected (std::invalid_argument naming the op and the error).
//
// Options: `keep_toffoli` stops at Toffolis (X with two positive controls stays in the output);
// `relative_phase_toffoli` see rule 3; `optimize` (default on) runs a peephole pass that fuses
// runs of single-qubit gates on one qubit into one gate, drops fused gates within 1e-14 of the
// identity and cancels adjacent equal CNOT (and kept Toffoli) pairs.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "metrics.hpp"
#include "program.hpp"
#include "../support/detail/meta.hpp"

namespace qrm {

struct decompose_options {
  bool keep_toffoli = false;            // output may contain Toffolis (X with 2 positive controls)
  bool relative_phase_toffoli = false;  // AND computations into ancillas with 3-CNOT relative-phase Toffolis
  bool optimize = true;                 // peephole: fuse single-qubit runs, cancel adjacent CNOT pairs
};

// The decomposed program (width = original width + ancillas) and its ancilla count.
struct decomposition_result {
  program circuit;
  std::size_t ancillas = 0;
};

namespace detail {

// Entries (and deviations from the identity) below this are treated as zero: far above the
// rounding of O(1) products (1e-16) and far below the 1e-12 that simulations are checked to.
inline constexpr double decompose_tolerance = 1e-14;

template <int = 0>
inline gate1 product(const gate1& a, const gate1& b) {  // a * b: b acts first
  gate1 r = gate::u(0.0, 0.0, 0.0, 0.0);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j];
  return r;
}

template <int = 0>
inline double distance_from_identity(const gate1& g) {
  return std::max({std::abs(g.m[0][0] - 1.0), std::abs(g.m[0][1]), std::abs(g.m[1][0]), std::abs(g.m[1][1] - 1.0)});
}

template <int = 0>
inline bool is_pauli_x(const gate1& g) {
  return g.m[0][0] == complex{} && g.m[1][1] == complex{} && g.m[0][1] == complex{1.0} && g.m[1][0] == complex{1.0};
}

// e^{ia} I within the tolerance (a controlled version is a phase on the control).
template <int = 0>
inline bool is_scalar(const gate1& g) {
  return std::abs(g.m[0][1]) <= decompose_tolerance && std::abs(g.m[1][0]) <= decompose_tolerance &&
         std::abs(g.m[0][0] - g.m[1][1]) <= decompose_tolerance;
}

// Largest |(g^dagger g - I)_ij|.
template <int = 0>
inline double unitarity_error(const gate1& g) {
  double worst = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const complex s = std::conj(g.m[0][i]) * g.m[0][j] + std::conj(g.m[1][i]) * g.m[1][j];
      worst = std::max(worst, std::abs(s - complex(i == j ? 1.0 : 0.0)));
    }
  return worst;
}

// A real rotation [[c, -s], [s, c]] = Ry(2 atan2(s, c)) (within the tolerance).
template <int = 0>
inline std::optional<double> ry_angle(const gate1& g) {
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      if (std::abs(g.m[i][j].imag()) > decompose_tolerance) return std::nullopt;
  const double c = g.m[0][0].real(), s = g.m[1][0].real();
  if (std::abs(c - g.m[1][1].real()) > decompose_tolerance || std::abs(s + g.m[0][1].real()) > decompose_tolerance)
    return std::nullopt;
  return 2.0 * std::atan2(s, c);
}

// Why a multiplexed op's entries are invalid (a select value too large or listed twice), if so.
template <class Entry>
std::optional<std::string> select_problem(std::span<const Entry> entries, std::size_t m) {
  if (m > 30) return "more than 30 select qubits";
  std::vector<std::uint64_t> values;
  values.reserve(entries.size());
  for (const Entry& e : entries) {
    if (e.select >> m)
      return "select value " + std::to_string(e.select) + " does not fit " + std::to_string(m) + " select qubits";
    values.push_back(e.select);
  }
  std::sort(values.begin(), values.end());
  const auto dup = std::adjacent_find(values.begin(), values.end());
  if (dup != values.end()) return "select value " + std::to_string(*dup) + " has two entries";
  return std::nullopt;
}

// ZYZ Euler angles: u = e^{i alpha} Rz(beta) Ry(gamma) Rz(delta) (N&C Theorem 4.1).
struct zyz_angles {
  double alpha, beta, gamma, delta;
};
template <int = 0>
inline zyz_angles zyz(const gate1& u) {
  const complex det = u.m[0][0] * u.m[1][1] - u.m[0][1] * u.m[1][0];
  const double alpha = std::arg(det) / 2;
  const complex ph = std::polar(1.0, -alpha);
  // v = e^{-i alpha} u is in SU(2): v = [[e^{-i(b+d)/2} cos, -e^{-i(b-d)/2} sin], [e^{i(b-d)/2} sin, e^{i(b+d)/2} cos]].
  // The first column fixes everything (the second follows from v in SU(2)); half angles are
  // read directly (arg differences would lose a sign: b + d is needed modulo 4 pi).
  const complex v00 = ph * u.m[0][0], v10 = ph * u.m[1][0];
  const double gamma = 2.0 * std::atan2(std::abs(v10), std::abs(v00));
  // A noisy arg of a vanishing entry only multiplies that vanishing entry: no special cases.
  const double sum = -2.0 * std::arg(v00), diff = 2.0 * std::arg(v10);
  return {alpha, (sum + diff) / 2, gamma, (sum - diff) / 2};
}

// A single-qubit gate acting on the Gray-code qubit of a two-level unitary, together with the
// values the other qubits must hold. `conditional`: the gate needs the op's own controls (the
// permutations around it do not: they cancel when the controls fail).
struct local_gate {
  gate1 gate;
  qubit_index target;
  std::vector<control> controls;
  bool conditional = true;
};

// A two-level unitary: g acts on span{|s>, |t>} (g.m[0][0] = <s|G|s>, g.m[0][1] = <s|G|t>, ...).
struct two_level {
  std::uint64_t s, t;
  gate1 g;
};

// U = F_m ... F_1 (F_1 acts first), each F a two-level unitary (N&C section 4.5.1).
template <int = 0>
inline std::vector<two_level> two_level_factors(const dense_matrix& u) {
  dense_matrix m = u;
  const std::size_t d = m.dim;
  std::vector<two_level> elim;  // G_1, G_2, ... with ... G_2 G_1 U = I
  auto apply_rows = [&](std::uint64_t s, std::uint64_t t, const gate1& g) {
    for (std::size_t c = 0; c < d; ++c) {
      const complex a = m(s, c), b = m(t, c);
      m(s, c) = g.m[0][0] * a + g.m[0][1] * b;
      m(t, c) = g.m[1][0] * a + g.m[1][1] * b;
    }
  };
  for (std::size_t j = 0; j < d; ++j) {
    std::optional<std::size_t> last;
    for (std::size_t i = j + 1; i < d; ++i) {
      const complex b = m(i, j);
      if (std::abs(b) <= decompose_tolerance) continue;
      const complex a = m(j, j);
      const double n = std::sqrt(std::norm(a) + std::norm(b));
      const gate1 g = gate::u(std::conj(a) / n, std::conj(b) / n, -b / n, a / n);
      apply_rows(j, i, g);
      m(i, j) = 0.0;
      elim.push_back({j, i, g});
      last = elim.size() - 1;
    }
    const complex ph = m(j, j);
    if (std::abs(ph - 1.0) <= decompose_tolerance) continue;
    const complex fix = std::conj(ph) / std::abs(ph);
    for (std::size_t c = 0; c < d; ++c) m(j, c) *= fix;
    if (last) {
      elim[*last].g.m[0][0] *= fix;
      elim[*last].g.m[0][1] *= fix;
    } else {
      elim.push_back({j, j ^ 1u, gate::u(fix, 0.0, 0.0, 1.0)});  // a phase on |j> alone
    }
  }
  std::vector<two_level> factors;
  factors.reserve(elim.size());
  for (std::size_t i = elim.size(); i-- > 0;) factors.push_back({elim[i].s, elim[i].t, adjoint(elim[i].g)});
  return factors;
}

// Pushes g unless it undoes the previous gate (equal multi-controlled X gates cancel).
template <int = 0>
inline void push_local(std::vector<local_gate>& out, local_gate g) {
  if (!out.empty() && !g.conditional && !out.back().conditional && is_pauli_x(g.gate) && is_pauli_x(out.back().gate) &&
      out.back().target == g.target && out.back().controls == g.controls) {
    out.pop_back();
    return;
  }
  out.push_back(std::move(g));
}

// The two-level decomposition of a 2^k x 2^k unitary as multi-controlled single-qubit gates
// on local qubits 0..k-1 (time order): N&C Fig. 4.16.
template <int = 0>
inline std::vector<local_gate> two_level_gates(const dense_matrix& u, std::size_t k) {
  std::vector<local_gate> out;
  auto others = [&](qubit_index skip, std::uint64_t state) {
    std::vector<control> cs;
    for (qubit_index l = 0; l < k; ++l)
      if (l != skip) cs.push_back({l, ((state >> l) & 1u) != 0});
    return cs;
  };
  for (const two_level& f : two_level_factors(u)) {
    if (distance_from_identity(f.g) <= decompose_tolerance) continue;
    const std::uint64_t diff = f.s ^ f.t;
    const auto p = static_cast<qubit_index>(std::bit_width(diff) - 1);  // the qubit the middle gate acts on
    std::vector<local_gate> perms;
    std::uint64_t cur = f.s;
    for (qubit_index b = 0; b < p; ++b)
      if ((diff >> b) & 1u) {
        perms.push_back({gate::x(), b, others(b, cur), false});
        cur ^= std::uint64_t{1} << b;
      }
    for (const local_gate& g : perms) push_local(out, g);
    const gate1 mid = ((cur >> p) & 1u) == 0 ? f.g : gate::u(f.g.m[1][1], f.g.m[1][0], f.g.m[0][1], f.g.m[0][0]);
    push_local(out, {mid, p, others(p, cur), true});
    for (std::size_t i = perms.size(); i-- > 0;) push_local(out, perms[i]);
  }
  return out;
}

// Add c (mod 2^k) on local qubits 0..k-1 (least significant first) as X cascades: rule 5.
template <int = 0>
inline std::vector<local_gate> add_gates(std::int64_t constant, std::size_t k) {
  if (k == 0 || k > 62) throw std::invalid_argument("decompose: add needs 1..62 qubits, got " + std::to_string(k));
  const std::uint64_t mask = (std::uint64_t{1} << k) - 1;
  std::uint64_t v = static_cast<std::uint64_t>(constant) & mask;
  std::vector<local_gate> out;
  auto flip_all = [&](std::size_t j) {
    for (std::size_t b = j; b < k; ++b) out.push_back({gate::x(), static_cast<qubit_index>(b), {}, false});
  };
  for (std::size_t j = 0; v != 0 && j < k; ++j, v >>= 1) {
    if ((v & 1u) == 0) continue;
    const bool minus = (v & 3u) == 3u;  // non-adjacent form: ...11 -> -1 and carry
    if (minus) {
      v += 1;  // v < 2^62, no overflow
      flip_all(j);
    }
    for (std::size_t i = k; i-- > j;) {
      local_gate g{gate::x(), static_cast<qubit_index>(i), {}, true};
      for (std::size_t c = j; c < i; ++c) g.controls.push_back({static_cast<qubit_index>(c), true});
      out.push_back(std::move(g));
    }
    if (minus) flip_all(j);
  }
  return out;
}

// Walsh-Hadamard-type transform of the uniformly controlled Ry (rule 6): the Ry angles
// theta_i to interleave with CNOTs controlled by select bit cnot_bit(i), for entry angles alpha.
template <int = 0>
inline std::vector<double> mottonen_angles(std::vector<double> alpha) {
  const std::size_t n = alpha.size();
  for (std::size_t h = 1; h < n; h <<= 1)  // in-place fast Walsh-Hadamard: w[x] = sum_s (-1)^{s.x} alpha[s]
    for (std::size_t i = 0; i < n; i += 2 * h)
      for (std::size_t j = i; j < i + h; ++j) {
        const double a = alpha[j], b = alpha[j + h];
        alpha[j] = a + b;
        alpha[j + h] = a - b;
      }
  std::vector<double> theta(n);
  for (std::size_t i = 0; i < n; ++i) theta[i] = alpha[i ^ (i >> 1)] / static_cast<double>(n);
  return theta;
}
// The select bit whose CNOT follows rotation i: the bit where gray(i) and gray(i+1) differ
// (the top bit after the last rotation, closing the cycle).
template <int = 0>
inline unsigned mottonen_cnot_bit(std::size_t i, std::size_t n, unsigned m) {
  return i + 1 == n ? m - 1 : static_cast<unsigned>(std::countr_zero(i + 1));
}

// One output gate: a single-qubit gate, a CNOT (controls 1) or a kept Toffoli (controls 2).
struct lowered_gate {
  gate1 gate;
  qubit_index target;
  qubit_index c0 = 0, c1 = 0;
  unsigned char controls = 0;
  bool alive = true;
};

// Collects output gates; with `optimize`, fuses single-qubit runs and cancels equal pairs.
template <int Deferred = 0>
class peephole_sink {
  template <class T>
  using list = deferred<std::vector<T>, Deferred>;

 public:
  explicit peephole_sink(bool optimize) : optimize_(optimize) {}

  void single(const gate1& g, qubit_index q) {
    if (g.is_identity()) return;
    if (optimize_) {
      auto& st = stack(q);
      if (!st.empty() && gates_[st.back()].controls == 0) {
        lowered_gate& prev = gates_[st.back()];
        prev.gate = product(g, prev.gate);
        if (distance_from_identity(prev.gate) <= decompose_tolerance) {
          prev.alive = false;
          st.pop_back();
        }
        return;
      }
      if (distance_from_identity(g) <= decompose_tolerance) return;
    }
    push({g, q, 0, 0, 0, true});
  }
  void cnot(qubit_index c, qubit_index t) {
    if (optimize_ && cancels({c, t}, [&](const lowered_gate& o) { return o.controls == 1 && o.c0 == c && o.target == t; }))
      return;
    push({gate::x(), t, c, 0, 1, true});
  }
  void toffoli(qubit_index a, qubit_index b, qubit_index t) {
    if (optimize_ && cancels({a, b, t}, [&](const lowered_gate& o) {
          return o.controls == 2 && o.target == t && ((o.c0 == a && o.c1 == b) || (o.c0 == b && o.c1 == a));
        }))
      return;
    push({gate::x(), t, a, b, 2, true});
  }

  const list<lowered_gate>& gates() const { return gates_; }

 private:
  list<std::uint32_t>& stack(qubit_index q) {
    if (q >= last_.size()) last_.resize(q + 1);
    return last_[q];
  }
  template <class Same>
  bool cancels(std::initializer_list<qubit_index> qs, Same same) {
    std::optional<std::uint32_t> top;
    for (qubit_index q : qs) {
      auto& st = stack(q);
      if (st.empty() || (top && st.back() != *top)) return false;
      top = st.back();
    }
    if (!same(gates_[*top])) return false;
    gates_[*top].alive = false;
    for (qubit_index q : qs) stack(q).pop_back();
    return true;
  }
  void push(const lowered_gate& g) {
    const auto index = static_cast<std::uint32_t>(gates_.size());
    gates_.push_back(g);
    if (!optimize_) return;
    stack(g.target).push_back(index);
    if (g.controls >= 1) stack(g.c0).push_back(index);
    if (g.controls >= 2) stack(g.c1).push_back(index);
  }

  bool optimize_;
  list<lowered_gate> gates_;
  list<list<std::uint32_t>> last_;  // per qubit: live gates touching it, latest last
};

// The lowering rules of the header comment, applied op by op.
template <int Deferred = 0>
class lowerer {
  template <class T>
  using list = deferred<std::vector<T>, Deferred>;

 public:
  lowerer(std::size_t width, decompose_options o) : n_(width), opt_(o), out_(o.optimize) {}

  void lower(const op::any& o, std::size_t index) {
    index_ = index;
    visit_op(o, [&](const auto& x) { lower_op(x); });
  }

  decomposition_result finish(const list<register_info>& registers) const {
    decomposition_result r{program(n_ + ancillas_), ancillas_};
    r.circuit.set_registers(registers);
    for (const lowered_gate& g : out_.gates()) {
      if (!g.alive) continue;
      list<control> cs;
      if (g.controls >= 1) cs.push_back({g.c0, true});
      if (g.controls >= 2) cs.push_back({g.c1, true});
      r.circuit.push(op::gate1_op{g.gate, g.target, std::move(cs)});
    }
    return r;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("decompose: op " + std::to_string(index_) + ": " + what);
  }
  void check_unitary(const gate1& g) const {
    const double e = unitarity_error(g);
    if (!(e <= 1e-9)) fail("the 2x2 matrix is not unitary (|U^dagger U - I| = " + std::to_string(e) + ")");
  }

  // ---- ancillas ----------------------------------------------------------------------------
  qubit_index allocate() {
    if (!free_.empty()) {
      const qubit_index q = free_.back();
      free_.pop_back();
      return q;
    }
    return static_cast<qubit_index>(n_ + ancillas_++);
  }
  void release(qubit_index q) { free_.push_back(q); }

  // ---- Toffolis ----------------------------------------------------------------------------
  void x(qubit_index q) { out_.single(gate::x(), q); }
  // Exact Toffoli (N&C Fig. 4.9): 6 CNOTs, 2 H, 7 T/T^dagger, 1 S.
  void toffoli(qubit_index a, qubit_index b, qubit_index t) {
    if (opt_.keep_toffoli) {
      out_.toffoli(a, b, t);
      return;
    }
    const double q = std::acos(-1.0) / 4;
    out_.single(gate::h(), t);
    out_.cnot(b, t);
    out_.single(gate::phase(-q), t);
    out_.cnot(a, t);
    out_.single(gate::phase(q), t);
    out_.cnot(b, t);
    out_.single(gate::phase(-q), t);
    out_.cnot(a, t);
    out_.single(gate::phase(-q), b);
    out_.single(gate::phase(q), t);
    out_.single(gate::h(), t);
    out_.cnot(a, b);
    out_.single(gate::phase(-q), b);
    out_.cnot(a, b);
    out_.single(gate::phase(q), a);
    out_.single(gate::phase(2 * q), b);
  }
  // t ^= a AND b for a clean t, possibly up to a diagonal phase; the same call undoes it.
  void and_into(qubit_index a, qubit_index b, qubit_index t) {
    if (opt_.keep_toffoli || !opt_.relative_phase_toffoli) {
      toffoli(a, b, t);
      return;
    }
    // Margolus: Toffoli times diag(-1 on |a=1, b=0, t=1>, +1 elsewhere); it is its own
    // inverse (the Toffoli leaves |101> alone, so the sign squares away).
    const double q = std::acos(-1.0) / 4;
    out_.single(gate::ry(q), t);
    out_.cnot(b, t);
    out_.single(gate::ry(q), t);
    out_.cnot(a, t);
    out_.single(gate::ry(-q), t);
    out_.cnot(b, t);
    out_.single(gate::ry(-q), t);
  }
  struct and_step {
    qubit_index a, b, t;
  };
  // The AND of positive controls qs (2 or more) into fresh ancillas; returns the last one.
  qubit_index compute_and(std::span<const qubit_index> qs, list<and_step>& steps) {
    qubit_index acc = qs[0];
    for (std::size_t i = 1; i < qs.size(); ++i) {
      const qubit_index t = allocate();
      and_into(acc, qs[i], t);
      steps.push_back({acc, qs[i], t});
      acc = t;
    }
    return acc;
  }
  void uncompute_and(const list<and_step>& steps) {
    for (std::size_t i = steps.size(); i-- > 0;) {
      and_into(steps[i].a, steps[i].b, steps[i].t);
      release(steps[i].t);
    }
  }

  // ---- controlled single-qubit gates ---------------------------------------------------------
  // Rule 2: U controlled by one positive control.
  void controlled_1(const gate1& u, qubit_index c, qubit_index t) {
    if (is_pauli_x(u)) {
      out_.cnot(c, t);
      return;
    }
    if (is_scalar(u)) {
      out_.single(gate::phase(std::arg(u.m[0][0])), c);
      return;
    }
    const complex tr = u.m[0][0] + u.m[1][1];
    if (std::abs(tr) <= decompose_tolerance) {
      // u = lambda W with W Hermitian, W^2 = I, trace 0: W = E Z E^dagger = V X V^dagger, V = E H.
      const complex det = u.m[0][0] * u.m[1][1] - u.m[0][1] * u.m[1][0];
      const complex lambda = std::sqrt(-det);
      const complex w00 = u.m[0][0] / lambda, w01 = u.m[0][1] / lambda, w10 = u.m[1][0] / lambda,
                    w11 = u.m[1][1] / lambda;
      // +1 eigenvector: the larger column of the projector (I + W) / 2.
      complex v0 = (1.0 + w00) / 2.0, v1 = w10 / 2.0;
      const complex u0 = w01 / 2.0, u1 = (1.0 + w11) / 2.0;
      if (std::norm(u0) + std::norm(u1) > std::norm(v0) + std::norm(v1)) {
        v0 = u0;
        v1 = u1;
      }
      const double nv = std::sqrt(std::norm(v0) + std::norm(v1));
      v0 /= nv;
      v1 /= nv;
      const gate1 e = gate::u(v0, -std::conj(v1), v1, std::conj(v0));
      const gate1 v = product(e, gate::h());
      out_.single(adjoint(v), t);
      out_.cnot(c, t);
      out_.single(v, t);
      out_.single(gate::phase(std::arg(lambda)), c);
      return;
    }
    const zyz_angles z = zyz(u);
    const gate1 a = product(gate::rz(z.beta), gate::ry(z.gamma / 2));
    const gate1 b = product(gate::ry(-z.gamma / 2), gate::rz(-(z.delta + z.beta) / 2));
    const gate1 cg = gate::rz((z.delta - z.beta) / 2);
    out_.single(cg, t);
    out_.cnot(c, t);
    out_.single(b, t);
    out_.cnot(c, t);
    out_.single(a, t);
    out_.single(gate::phase(z.alpha), c);
  }

  // Rules 1 and 3: u on t where every control holds.
  void controlled(const gate1& u, qubit_index t, std::span<const control> cs) {
    if (u.is_identity() || (opt_.optimize && distance_from_identity(u) <= decompose_tolerance)) return;
    if (cs.empty()) {
      out_.single(u, t);
      return;
    }
    for (const control& c : cs)
      if (!c.value) x(c.qubit);
    list<qubit_index> pos;
    pos.reserve(cs.size());
    for (const control& c : cs) pos.push_back(c.qubit);
    positive(u, t, pos);
    for (std::size_t i = cs.size(); i-- > 0;)
      if (!cs[i].value) x(cs[i].qubit);
  }
  void positive(const gate1& u, qubit_index t, std::span<const qubit_index> pos) {
    const std::size_t k = pos.size();
    if (k == 1) {
      controlled_1(u, pos[0], t);
      return;
    }
    if (is_scalar(u)) {  // C^k(e^{ia} I) = C^{k-1} phase(a) on the last control
      positive(gate::phase(std::arg(u.m[0][0])), pos[k - 1], pos.first(k - 1));
      return;
    }
    list<and_step> steps;
    if (is_pauli_x(u)) {
      if (k == 2) {
        toffoli(pos[0], pos[1], t);
        return;
      }
      const qubit_index a = compute_and(pos.first(k - 1), steps);
      toffoli(a, pos[k - 1], t);
    } else {
      const qubit_index a = compute_and(pos, steps);
      controlled_1(u, a, t);
    }
    uncompute_and(steps);
  }

  // Runs body(c) with c the single positive qubit standing for all of cs (or none if cs is
  // empty): X on negative controls, the AND of two or more into an ancilla.
  template <class Body>
  void with_one_control(std::span<const control> cs, Body body) {
    if (cs.empty()) {
      body(std::optional<qubit_index>{});
      return;
    }
    for (const control& c : cs)
      if (!c.value) x(c.qubit);
    if (cs.size() == 1) {
      body(std::optional<qubit_index>{cs[0].qubit});
    } else {
      list<qubit_index> pos;
      for (const control& c : cs) pos.push_back(c.qubit);
      list<and_step> steps;
      const qubit_index a = compute_and(pos, steps);
      body(std::optional<qubit_index>{a});
      uncompute_and(steps);
    }
    for (std::size_t i = cs.size(); i-- > 0;)
      if (!cs[i].value) x(cs[i].qubit);
  }

  // Local gates on `qubits`, the conditional ones also controlled by `extra`.
  void run_local(const list<local_gate>& gates, std::span<const qubit_index> qubits,
                 std::optional<qubit_index> extra) {
    list<control> cs;
    for (const local_gate& g : gates) {
      cs.clear();
      for (const control& c : g.controls) cs.push_back({qubits[c.qubit], c.value});
      if (g.conditional && extra) cs.push_back({*extra, true});
      controlled(g.gate, qubits[g.target], cs);
    }
  }

  // Rule 4 (and a controlled global phase for a 1x1 matrix).
  void unitary(const dense_matrix& m, std::span<const qubit_index> targets, std::span<const control> cs) {
    const double e = qrm::unitarity_error(m);
    if (!(e <= 1e-9))
      fail("the " + std::to_string(m.dim) + "x" + std::to_string(m.dim) +
           " matrix is not unitary (|U^dagger U - I| = " + std::to_string(e) + ")");
    const std::size_t k = targets.size();
    if (k == 0) {
      const complex z = m(0, 0);
      if (cs.empty()) {
        if (n_ > 0) out_.single(gate::u(z, 0.0, 0.0, z), 0);
        return;
      }
      const control last = cs.back();
      controlled(last.value ? gate::u(1.0, 0.0, 0.0, z) : gate::u(z, 0.0, 0.0, 1.0), last.qubit, cs.first(cs.size() - 1));
      return;
    }
    if (k == 1) {
      controlled(gate::u(m(0, 0), m(0, 1), m(1, 0), m(1, 1)), targets[0], cs);
      return;
    }
    const list<local_gate> gates = two_level_gates(m, k);
    with_one_control(cs, [&](std::optional<qubit_index> c) { run_local(gates, targets, c); });
  }

  // Per-entry controls: the select qubits holding `select`, then the op's controls.
  static list<control> entry_controls(std::uint64_t select, std::span<const qubit_index> sel,
                                             std::span<const control> cs) {
    list<control> r;
    for (std::size_t i = 0; i < sel.size(); ++i) r.push_back({sel[i], ((select >> i) & 1u) != 0});
    r.insert(r.end(), cs.begin(), cs.end());
    return r;
  }

  // CNOTs of one C^k U (generic U) under the options: the per-entry cost of rule 6.
  std::size_t controlled_cost(std::size_t k) const {
    const std::size_t and_cost = (opt_.relative_phase_toffoli && !opt_.keep_toffoli) ? 3 : 6;
    return k == 0 ? 0 : k == 1 ? 2 : 2 * (k - 1) * and_cost + 2;
  }

  // ---- ops --------------------------------------------------------------------------------
  void lower_op(const op::gate1_op& o) {
    check_unitary(o.gate);
    controlled(o.gate, o.target, o.controls);
  }
  void lower_op(const op::unitary_op& o) { unitary(o.matrix, o.targets, o.controls); }
  void lower_op(const op::add_op& o) {
    if (o.bits.empty()) return;
    if (o.bits.size() > 62) fail("add on more than 62 qubits");
    const list<local_gate> gates = add_gates(o.constant, o.bits.size());
    if (gates.empty()) return;
    with_one_control(o.controls, [&](std::optional<qubit_index> c) { run_local(gates, o.bits, c); });
  }
  void lower_op(const op::mux1_op& o) {
    const std::size_t m = o.select.size();
    if (auto problem = select_problem(std::span<const mux1_entry>(o.entries), m)) fail(*problem);
    bool all_ry = true;
    std::size_t active = 0;
    for (const mux1_entry& e : o.entries) {
      check_unitary(e.gate);
      if (!ry_angle(e.gate)) all_ry = false;
      if (!e.gate.is_identity()) ++active;
    }
    const std::size_t mm = m + o.controls.size();
    if (all_ry && mm >= 1 && mm <= 20 && (std::size_t{1} << mm) <= active * controlled_cost(mm)) {
      // Rule 6: the op's controls become the top select bits; other select values get angle 0.
      list<qubit_index> sel(o.select.begin(), o.select.end());
      std::uint64_t fixed = 0;
      for (std::size_t i = 0; i < o.controls.size(); ++i) {
        sel.push_back(o.controls[i].qubit);
        if (o.controls[i].value) fixed |= std::uint64_t{1} << (m + i);
      }
      const std::size_t n = std::size_t{1} << mm;
      list<double> alpha(n, 0.0);
      for (const mux1_entry& e : o.entries) alpha[e.select | fixed] = *ry_angle(e.gate);
      const list<double> theta = mottonen_angles(std::move(alpha));
      for (std::size_t i = 0; i < n; ++i) {
        out_.single(gate::ry(theta[i]), o.target);
        out_.cnot(sel[mottonen_cnot_bit(i, n, static_cast<unsigned>(mm))], o.target);
      }
      return;
    }
    for (const mux1_entry& e : o.entries) controlled(e.gate, o.target, entry_controls(e.select, o.select, o.controls));
  }
  void lower_op(const op::mux_unitary_op& o) {
    if (auto problem = select_problem(std::span<const mux_unitary_entry>(o.entries), o.select.size())) fail(*problem);
    for (const mux_unitary_entry& e : o.entries) {
      if (e.matrix >= o.matrices.size())
        fail("entry names matrix " + std::to_string(e.matrix) + " of " + std::to_string(o.matrices.size()));
      const dense_matrix& mat = o.matrices[e.matrix];
      if (mat == dense_matrix::identity(mat.dim)) continue;
      unitary(mat, o.targets, entry_controls(e.select, o.select, o.controls));
    }
  }

  std::size_t n_;
  decompose_options opt_;
  peephole_sink<Deferred> out_;
  std::size_t ancillas_ = 0;
  list<qubit_index> free_;
  std::size_t index_ = 0;
};

}  // namespace detail

// decompose(p): an equivalent program of single-qubit gates and CNOTs (rules in the header
// comment), with clean ancillas appended after p's qubits.
template <int Deferred = 0>
decomposition_result decompose(const program& p, decompose_options options = {}) {
  detail::lowerer<Deferred> l(p.width(), options);
  for (std::size_t i = 0; i < p.ops().size(); ++i) l.lower(p.ops()[i], i);
  return l.finish(p.registers());
}

// Gate counts and depth of the decomposed program.
struct decomposed_counts {
  std::size_t width = 0;               // program qubits + ancillas
  std::size_t ancillas = 0;            // clean ancillas the decomposition adds
  std::size_t cnot_count = 0;          // CNOTs
  std::size_t toffoli_count = 0;       // kept Toffolis (only with keep_toffoli)
  std::size_t single_qubit_count = 0;  // uncontrolled single-qubit gates
  std::size_t gate_count = 0;          // all of the above
  std::size_t depth = 0;               // ASAP depth (qrm::circuit_metrics_of) of the decomposed program
};

// decomposed_metrics(p): the cost of p on hardware with single-qubit gates and CNOTs.
template <int = 0>
decomposed_counts decomposed_metrics(const program& p, decompose_options options = {}) {
  const decomposition_result d = decompose(p, options);
  decomposed_counts c;
  c.width = d.circuit.width();
  c.ancillas = d.ancillas;
  for (const op::any& o : d.circuit.ops()) {
    const auto& g = std::get<op::gate1_op>(o);
    if (g.controls.empty()) ++c.single_qubit_count;
    else if (g.controls.size() == 1) ++c.cnot_count;
    else ++c.toffoli_count;
  }
  c.gate_count = d.circuit.ops().size();
  c.depth = circuit_metrics_of(d.circuit).logical_depth;
  return c;
}

}  // namespace qrm

// This header's part of <qrm/circuit/compiled_circuit.hpp> (QRM_COMPILED_CIRCUIT).
#define QRM_DETAIL_DECOMPOSE_INSTANCES(PREFIX)                                       \
  PREFIX decomposition_result decompose<0>(const program&, decompose_options);       \
  PREFIX decomposed_counts decomposed_metrics<0>(const program&, decompose_options);
#ifdef QRM_COMPILED_CIRCUIT
namespace qrm {
QRM_DETAIL_DECOMPOSE_INSTANCES(extern template)
}  // namespace qrm
#endif
