// qrm/circuit/qasm.hpp: OpenQASM 3 export (`to_qasm`) and import (`from_qasm`) of programs.
//
// Export, logical form (default): `OPENQASM 3.0; include "stdgates.inc"; qubit[n] q;` (the
// program's registers as comments), then one line per logical gate:
//   - a (multi-)controlled single-qubit gate as `ctrl(n) @ negctrl(m) @` modifiers on x, y, z,
//     h, ry(t), rz(t), p(t), or on U(theta, phi, lambda) followed by `gphase(alpha)` under the
//     same controls when the matrix is e^{i alpha} U(theta, phi, lambda) (OpenQASM 3's U has
//     no global phase, and a controlled gate exposes it); uncontrolled global phases are summed
//     into one `gphase` line at the end;
//   - a multiplexed gate as one controlled gate per entry (select qubits as ctrl / negctrl with
//     the entry's value): the logical circuit, one gate per voxel;
//   - a dense k-qubit unitary (k >= 2) as a `gate` definition whose body is its two-level
//     decomposition (qrm/circuit/decompose.hpp, rule 4) with ctrl / negctrl modifiers, applied with
//     the op's controls as modifiers; add-a-constant likewise (rule 5).
// With `qasm_options::decomposed`, the program is first lowered by `qrm::decompose` and
// written as single-qubit gates and `cx` (and `ccx` with keep_toffoli), ancillas declared as
// `qubit[a] anc;`. Numbers are printed with 17 significant digits (round-trip exact).
//
// Import: the header, `include "stdgates.inc"`, `qubit[n] name;` / `qubit name;` /
// `qreg name[n];` declarations (qubits numbered in declaration order), `gate` definitions with
// parameters and calls of them, every gate of stdgates.inc (p x y z h s sdg t tdg sx rx ry rz
// cx cy cz cp crx cry crz ch swap ccx cswap cu CX phase cphase id u1 u2 u3), U and gphase, the
// modifiers ctrl @, ctrl(n) @, negctrl @, negctrl(n) @ and inv @, operands `name[i]` (or a
// one-qubit register by name), parameter expressions (+ - * / **, pi / π, tau / τ, euler / ℇ,
// sin cos tan arcsin arccos arctan exp ln sqrt), // and /* */ comments, and `barrier`
// (ignored). A call of a user-defined gate on at most 6 qubits becomes one unitary op (its
// matrix, computed from the body); larger ones are expanded. Errors throw qrm::qasm_error (a
// std::invalid_argument) reading `qasm:LINE:COLUMN: what was expected, found what`.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "decompose.hpp"
#include "program.hpp"
#include "../support/detail/meta.hpp"
#include "../version.hpp"

namespace qrm {

struct qasm_options {
  bool decomposed = false;               // write decompose(p) as single-qubit gates and cx
  decompose_options decomposition = {};  // options of that decomposition
  bool comments = true;                  // a header comment and the register table
};

// A malformed OpenQASM input: the message starts with `qasm:LINE:COLUMN:`.
class qasm_error : public std::invalid_argument {
 public:
  template <int = 0>
  qasm_error(std::size_t line, std::size_t column, const std::string& what)
      : std::invalid_argument("qasm:" + std::to_string(line) + ":" + std::to_string(column) + ": " + what),
        line_(line),
        column_(column) {}
  std::size_t line() const { return line_; }
  std::size_t column() const { return column_; }

 private:
  std::size_t line_, column_;
};

namespace detail {

// ---- export ---------------------------------------------------------------------------------

// 17 significant digits: parsing the text gives back the same double.
template <int = 0>
inline std::string qasm_number(double v) {
  if (!std::isfinite(v)) throw std::invalid_argument("to_qasm: a gate angle is not finite (" + std::to_string(v) + ")");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
  return std::string(buf, r.ptr);
}

// A value in a message: like qasm_number, and "nan" / "inf" / "-inf" for the rest.
template <int = 0>
inline std::string qasm_value_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return qasm_number(v);
}

// g = e^{i gamma} U(theta, phi, lambda), OpenQASM 3's
// U = [[cos t/2, -e^{i lambda} sin t/2], [e^{i phi} sin t/2, e^{i (phi + lambda)} cos t/2]].
struct u_angles {
  double theta, phi, lambda, gamma;
};
template <int = 0>
inline u_angles qasm_u_angles(const gate1& g) {
  const complex m00 = g.m[0][0], m01 = g.m[0][1], m10 = g.m[1][0], m11 = g.m[1][1];
  u_angles a{};
  a.theta = 2.0 * std::atan2(std::abs(m10), std::abs(m00));
  // A noisy arg of a vanishing entry only multiplies that vanishing entry.
  a.gamma = std::arg(m00);
  a.phi = std::arg(m10) - a.gamma;
  a.lambda = std::abs(m00) >= std::abs(m10) ? std::arg(m11) - a.gamma - a.phi : std::arg(-m01) - a.gamma;
  return a;
}
// e^{i (phi + lambda)} is formed as a product: for large angles phi + lambda rounds (by 0.25 at
// 3e15) and the matrix would not be unitary.
template <int = 0>
inline gate1 qasm_u_matrix(double theta, double phi, double lambda) {
  const double c = std::cos(theta / 2), s = std::sin(theta / 2);
  const complex ep = std::polar(1.0, phi), el = std::polar(1.0, lambda);
  return gate::u(c, -el * s, ep * s, ep * el * c);
}

// The OpenQASM spelling of g: a standard gate when g is one (to 1e-15, far below the 1e-12
// simulations are checked to), else U plus a global phase.
struct qasm_gate1 {
  std::string call;
  double phase = 0;  // gphase to add under the same controls
};
template <int = 0>
inline qasm_gate1 qasm_form(const gate1& g) {
  auto same = [&](const gate1& ref) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        if (std::abs(g.m[i][j] - ref.m[i][j]) > 1e-15) return false;
    return true;
  };
  switch (g.kind) {
    case gate1_kind::x: if (same(gate::x())) return {"x"}; break;
    case gate1_kind::y: if (same(gate::y())) return {"y"}; break;
    case gate1_kind::z: if (same(gate::z())) return {"z"}; break;
    case gate1_kind::h: if (same(gate::h())) return {"h"}; break;
    case gate1_kind::ry: if (same(gate::ry(g.angle))) return {"ry(" + qasm_number(g.angle) + ")"}; break;
    case gate1_kind::rz: if (same(gate::rz(g.angle))) return {"rz(" + qasm_number(g.angle) + ")"}; break;
    case gate1_kind::phase: if (same(gate::phase(g.angle))) return {"p(" + qasm_number(g.angle) + ")"}; break;
    case gate1_kind::u: break;
  }
  if (is_pauli_x(g)) return {"x"};
  const u_angles a = qasm_u_angles(g);
  return {"U(" + qasm_number(a.theta) + ", " + qasm_number(a.phi) + ", " + qasm_number(a.lambda) + ")", a.gamma};
}

// Writes gate lines; qubit names come from a callback (q[i], anc[j] or a gate's a0, a1, ...).
template <class Name>
class qasm_writer {
 public:
  qasm_writer(std::string& out, std::string indent, Name name) : out_(out), indent_(std::move(indent)), name_(name) {}

  // `call` on `targets` where every control holds; `phase`: a gphase under the same controls.
  void line(const std::string& call, std::span<const qubit_index> targets, std::span<const control> cs, double phase = 0) {
    std::string prefix, operands;
    std::size_t pos = 0, neg = 0;
    for (const control& c : cs) (c.value ? pos : neg)++;
    auto modifier = [](const char* m, std::size_t n) {
      return n == 0 ? std::string() : n == 1 ? std::string(m) + " @ " : std::string(m) + "(" + std::to_string(n) + ") @ ";
    };
    prefix = modifier("ctrl", pos) + modifier("negctrl", neg);
    for (bool value : {true, false})
      for (const control& c : cs)
        if (c.value == value) operands += (operands.empty() ? "" : ", ") + name_(c.qubit);
    const std::string control_operands = operands;
    for (qubit_index t : targets) operands += (operands.empty() ? "" : ", ") + name_(t);
    if (!call.empty()) out_ += indent_ + prefix + call + " " + operands + ";\n";
    if (phase != 0) {
      if (cs.empty()) global_phase_ += phase;
      else out_ += indent_ + prefix + "gphase(" + qasm_number(phase) + ") " + control_operands + ";\n";
    }
  }
  void gate(const gate1& g, qubit_index target, std::span<const control> cs) {
    const qasm_gate1 f = qasm_form(g);
    line(f.call, std::span<const qubit_index>(&target, 1), cs, f.phase);
  }
  // The summed phase of uncontrolled gates, as one line.
  void flush_global_phase() {
    if (global_phase_ != 0) out_ += indent_ + "gphase(" + qasm_number(global_phase_) + ");\n";
    global_phase_ = 0;
  }

 private:
  std::string& out_;
  std::string indent_;
  Name name_;
  double global_phase_ = 0;
};

// Gate definitions the logical export needs: one per distinct matrix (k >= 2) and per add.
template <int = 0>
struct qasm_definitions {
  std::vector<std::pair<dense_matrix, std::string>> unitaries;
  std::map<std::pair<std::size_t, std::uint64_t>, std::string> adds;  // (bits, constant mod 2^bits)
  std::string text;

  const std::string& unitary(const dense_matrix& m, std::size_t k, std::size_t op_index) {
    for (const auto& [mat, name] : unitaries)
      if (mat == m) return name;
    const double e = qrm::unitarity_error(m);
    if (!(e <= 1e-9))
      throw std::invalid_argument("to_qasm: op " + std::to_string(op_index) + ": the " + std::to_string(m.dim) + "x" +
                                  std::to_string(m.dim) + " matrix is not unitary (|U^dagger U - I| = " + std::to_string(e) + ")");
    const std::string name = "qrm_unitary" + std::to_string(k) + "_" + std::to_string(unitaries.size());
    define(name, k, two_level_gates(m, k));
    unitaries.emplace_back(m, name);
    return unitaries.back().second;
  }
  const std::string& add(std::uint64_t c, std::size_t k) {
    const auto key = std::make_pair(k, c);
    if (auto it = adds.find(key); it != adds.end()) return it->second;
    const std::string name = "qrm_add" + std::to_string(k) + "_" + std::to_string(c);
    define(name, k, add_gates(static_cast<std::int64_t>(c), k));
    return adds.emplace(key, name).first->second;
  }

 private:
  void define(const std::string& name, std::size_t k, const std::vector<local_gate>& body) {
    text += "gate ";
    text += name;
    for (std::size_t i = 0; i < k; ++i) {
      text += i ? ", a" : " a";
      text += std::to_string(i);
    }
    text += " {\n";
    // Built by appending: g++ 12 at -O3 warns falsely (-Wrestrict) on "a" + std::to_string(q).
    qasm_writer w(text, "  ", [](qubit_index q) {
      std::string r = "a";
      r += std::to_string(q);
      return r;
    });
    for (const local_gate& g : body) w.gate(g.gate, g.target, g.controls);
    w.flush_global_phase();
    text += "}\n";
  }
};

template <int = 0>
inline std::vector<control> qasm_entry_controls(std::uint64_t select, std::span<const qubit_index> sel,
                                                std::span<const control> cs) {
  std::vector<control> r;
  for (std::size_t i = 0; i < sel.size(); ++i) r.push_back({sel[i], ((select >> i) & 1u) != 0});
  r.insert(r.end(), cs.begin(), cs.end());
  return r;
}

template <int = 0>
inline void qasm_check_gate(const gate1& g, std::size_t op_index) {
  const double e = unitarity_error(g);
  if (!(e <= 1e-9))
    throw std::invalid_argument("to_qasm: op " + std::to_string(op_index) +
                                ": the 2x2 matrix is not unitary (|U^dagger U - I| = " + std::to_string(e) + ")");
}

template <int = 0>
inline std::string qasm_header(const program& p, const qasm_options& o, const char* form) {
  std::string s = "OPENQASM 3.0;\ninclude \"stdgates.inc\";\n";
  if (o.comments) {
    s += "// Written by qrm " + std::string(version) + ": " + std::to_string(p.width()) + " qubits, " +
         std::to_string(p.size()) + " ops, " + form + ".\n";
    for (const register_info& r : p.registers()) {
      s += "// register " + std::string(r.name) + " (" + std::string(role_name(r.kind)) + "): q[" + std::to_string(r.offset);
      if (r.width > 1) s += ":" + std::to_string(r.offset + r.width - 1);
      s += "]\n";
    }
  }
  if (p.width() > 0) s += "qubit[" + std::to_string(p.width()) + "] q;\n";
  return s;
}

template <int Deferred = 0>
inline std::string to_qasm_logical(const program& p, const qasm_options& o) {
  qasm_definitions<Deferred> defs;
  std::string body;
  qasm_writer w(body, "", [](qubit_index q) { return "q[" + std::to_string(q) + "]"; });
  for (std::size_t i = 0; i < p.ops().size(); ++i) {
    visit_op(p.ops()[i], [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, op::gate1_op>) {
            qasm_check_gate(x.gate, i);
            w.gate(x.gate, x.target, x.controls);
          } else if constexpr (std::is_same_v<T, op::unitary_op>) {
            const std::size_t k = x.targets.size();
            if (k == 0) {
              w.line("", {}, x.controls, std::arg(x.matrix(0, 0)));
            } else if (k == 1) {
              const gate1 g = gate::u(x.matrix(0, 0), x.matrix(0, 1), x.matrix(1, 0), x.matrix(1, 1));
              qasm_check_gate(g, i);
              w.gate(g, x.targets[0], x.controls);
            } else {
              w.line(defs.unitary(x.matrix, k, i), x.targets, x.controls);
            }
          } else if constexpr (std::is_same_v<T, op::add_op>) {
            const std::size_t k = x.bits.size();
            if (k == 0) return;
            if (k > 62) throw std::invalid_argument("to_qasm: op " + std::to_string(i) + ": add on more than 62 qubits");
            const std::uint64_t c = static_cast<std::uint64_t>(x.constant) & ((std::uint64_t{1} << k) - 1);
            if (c != 0) w.line(defs.add(c, k), x.bits, x.controls);
          } else if constexpr (std::is_same_v<T, op::mux1_op>) {
            if (auto problem = select_problem(std::span<const mux1_entry>(x.entries), x.select.size()))
              throw std::invalid_argument("to_qasm: op " + std::to_string(i) + ": " + *problem);
            for (const mux1_entry& e : x.entries) {
              qasm_check_gate(e.gate, i);
              w.gate(e.gate, x.target, qasm_entry_controls(e.select, x.select, x.controls));
            }
          } else {
            const std::size_t k = x.targets.size();
            if (auto problem = select_problem(std::span<const mux_unitary_entry>(x.entries), x.select.size()))
              throw std::invalid_argument("to_qasm: op " + std::to_string(i) + ": " + *problem);
            for (const mux_unitary_entry& e : x.entries) {
              if (e.matrix >= x.matrices.size())
                throw std::invalid_argument("to_qasm: op " + std::to_string(i) + ": entry names matrix " +
                                            std::to_string(e.matrix) + " of " + std::to_string(x.matrices.size()));
              const dense_matrix& m = x.matrices[e.matrix];
              const auto cs = qasm_entry_controls(e.select, x.select, x.controls);
              if (k == 0) {
                w.line("", {}, cs, std::arg(m(0, 0)));
              } else if (k == 1) {
                const gate1 g = gate::u(m(0, 0), m(0, 1), m(1, 0), m(1, 1));
                qasm_check_gate(g, i);
                w.gate(g, x.targets[0], cs);
              } else {
                w.line(defs.unitary(m, k, i), x.targets, cs);
              }
            }
          }
        });
  }
  w.flush_global_phase();
  return qasm_header(p, o, "logical form: one line per gate, multiplexed gates one line per entry") + defs.text + body;
}

template <int = 0>
inline std::string to_qasm_decomposed(const program& p, const qasm_options& o) {
  const decomposition_result d = decompose(p, o.decomposition);
  const std::size_t n = p.width();
  std::string s = qasm_header(p, o, "decomposed into single-qubit gates and cx");
  if (d.ancillas > 0) {
    if (o.comments) s += "// clean ancillas: start and end in |0>\n";
    s += "qubit[" + std::to_string(d.ancillas) + "] anc;\n";
  }
  auto name = [n](qubit_index q) { return q < n ? "q[" + std::to_string(q) + "]" : "anc[" + std::to_string(q - n) + "]"; };
  qasm_writer w(s, "", name);
  for (const op::any& any : d.circuit.ops()) {
    const auto& g = std::get<op::gate1_op>(any);
    if (g.controls.empty()) {
      w.gate(g.gate, g.target, {});
      continue;
    }
    s += g.controls.size() == 1 ? "cx " : "ccx ";
    for (const control& c : g.controls) s += name(c.qubit) + ", ";
    s += name(g.target) + ";\n";
  }
  w.flush_global_phase();
  return s;
}

// ---- import ---------------------------------------------------------------------------------

struct qasm_token {
  enum kind_t : unsigned char { identifier, number, string, punct, end };
  kind_t kind = end;
  std::string_view text;
  double value = 0;
  std::size_t line = 1, column = 1;

  bool is(char p) const { return kind == punct && text.size() == 1 && text[0] == p; }
  bool is(std::string_view word) const { return kind == identifier && text == word; }
  template <int = 0>
  std::string describe() const {
    switch (kind) {
      case end: return "end of input";
      case string: return "\"" + std::string(text) + "\"";
      default: return "'" + std::string(text) + "'";
    }
  }
};

[[noreturn]] inline void qasm_fail(const qasm_token& t, const std::string& what) { throw qasm_error(t.line, t.column, what); }

// Tokens on demand (one of lookahead), skipping white space and comments.
template <int = 0>
class qasm_lexer {
 public:
  explicit qasm_lexer(std::string_view src) : src_(src) {}
  const qasm_token& peek() {
    if (!ready_) {
      token_ = scan();
      ready_ = true;
    }
    return token_;
  }
  qasm_token next() {
    peek();
    ready_ = false;
    return token_;
  }

 private:
  static bool digit(char c) { return c >= '0' && c <= '9'; }
  static bool ident_start(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || static_cast<unsigned char>(c) >= 0x80;
  }
  static bool ident_char(char c) { return ident_start(c) || digit(c); }
  char at(std::size_t i) const { return i < src_.size() ? src_[i] : '\0'; }
  void advance() {
    if (src_[pos_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++pos_;
  }
  void skip() {
    for (;;) {
      while (pos_ < src_.size() && (src_[pos_] == ' ' || src_[pos_] == '\t' || src_[pos_] == '\n' || src_[pos_] == '\r'))
        advance();
      if (at(pos_) == '/' && at(pos_ + 1) == '/') {
        while (pos_ < src_.size() && src_[pos_] != '\n') advance();
      } else if (at(pos_) == '/' && at(pos_ + 1) == '*') {
        const std::size_t line = line_, column = column_;
        advance();
        advance();
        while (pos_ < src_.size() && !(src_[pos_] == '*' && at(pos_ + 1) == '/')) advance();
        if (pos_ >= src_.size()) throw qasm_error(line, column, "unterminated comment: expected '*/'");
        advance();
        advance();
      } else {
        return;
      }
    }
  }
  qasm_token scan() {
    skip();
    qasm_token t;
    t.line = line_;
    t.column = column_;
    const std::size_t start = pos_;
    if (pos_ >= src_.size()) return t;
    const char c = src_[pos_];
    if (ident_start(c)) {
      while (pos_ < src_.size() && ident_char(src_[pos_])) advance();
      t.kind = qasm_token::identifier;
    } else if (digit(c) || (c == '.' && digit(at(pos_ + 1)))) {
      while (digit(at(pos_))) advance();
      if (at(pos_) == '.') {
        advance();
        while (digit(at(pos_))) advance();
      }
      if ((at(pos_) == 'e' || at(pos_) == 'E') &&
          (digit(at(pos_ + 1)) || ((at(pos_ + 1) == '+' || at(pos_ + 1) == '-') && digit(at(pos_ + 2))))) {
        advance();
        if (at(pos_) == '+' || at(pos_) == '-') advance();
        while (digit(at(pos_))) advance();
      }
      t.kind = qasm_token::number;
      const char* first = src_.data() + start;
      const char* last = src_.data() + pos_;
      const auto r = std::from_chars(first, last, t.value);
      if (r.ec != std::errc() || r.ptr != last)
        throw qasm_error(t.line, t.column, "malformed number '" + std::string(first, last) + "'");
    } else if (c == '"') {
      advance();
      while (pos_ < src_.size() && src_[pos_] != '"' && src_[pos_] != '\n') advance();
      if (at(pos_) != '"') throw qasm_error(t.line, t.column, "unterminated string: expected '\"'");
      advance();
      t.kind = qasm_token::string;
      t.text = src_.substr(start + 1, pos_ - start - 2);
      return t;
    } else if (c == '*' && at(pos_ + 1) == '*') {
      advance();
      advance();
      t.kind = qasm_token::punct;
    } else if (std::string_view(";,()[]{}@+-*/:=").find(c) != std::string_view::npos) {
      advance();
      t.kind = qasm_token::punct;
    } else {
      throw qasm_error(t.line, t.column, std::string("unexpected character '") + c + "'");
    }
    t.text = src_.substr(start, pos_ - start);
    return t;
  }

  std::string_view src_;
  std::size_t pos_ = 0, line_ = 1, column_ = 1;
  qasm_token token_;
  bool ready_ = false;
};

struct qasm_std_gate {
  std::string_view name;
  unsigned char params, qubits;
};
// The gates of OpenQASM 3's stdgates.inc.
inline constexpr qasm_std_gate qasm_std_gates[] = {
    {"p", 1, 1},   {"x", 0, 1},     {"y", 0, 1},   {"z", 0, 1},     {"h", 0, 1},      {"s", 0, 1},   {"sdg", 0, 1},
    {"t", 0, 1},   {"tdg", 0, 1},   {"sx", 0, 1},  {"rx", 1, 1},    {"ry", 1, 1},     {"rz", 1, 1},  {"cx", 0, 2},
    {"cy", 0, 2},  {"cz", 0, 2},    {"cp", 1, 2},  {"crx", 1, 2},   {"cry", 1, 2},    {"crz", 1, 2}, {"ch", 0, 2},
    {"swap", 0, 2}, {"ccx", 0, 3},  {"cswap", 0, 3}, {"cu", 4, 2},  {"CX", 0, 2},     {"phase", 1, 1}, {"cphase", 1, 2},
    {"id", 0, 1},  {"u1", 1, 1},    {"u2", 2, 1},  {"u3", 3, 1}};

template <int Deferred = 0>
class qasm_parser {
  template <class T>
  using list = deferred<std::vector<T>, Deferred>;

 public:
  explicit qasm_parser(std::string_view text) : lex_(text) {}

  program parse() {
    if (lex_.peek().is("OPENQASM")) {
      lex_.next();
      const qasm_token v = lex_.next();
      if (v.kind != qasm_token::number) qasm_fail(v, "expected a version number after OPENQASM, found " + v.describe());
      if (std::floor(v.value) != 3)
        qasm_fail(v, "only OpenQASM 3 is supported, found version " + std::string(v.text));
      expect(';', "after the version");
    }
    while (lex_.peek().kind != qasm_token::end) statement();
    program p(width_);
    for (op::any& o : ops_) p.push(std::move(o));
    if (global_phase_ != 0 && width_ > 0) {
      const complex z = std::polar(1.0, global_phase_);
      p.push(op::gate1_op{gate::u(z, 0.0, 0.0, z), 0, {}});
    }
    return p;
  }

 private:
  // ---- syntax tree ------------------------------------------------------------------------
  struct expr {
    char op = 'n';  // n number, p parameter, f function, u unary minus, + - * / ^
    double value = 0;
    std::size_t param = 0;
    std::string fn;
    list<expr> args;
    std::size_t depth = 1;  // of the tree: eval recurses this deep
  };
  struct modifier {
    bool inverse = false, negative = false;
    std::size_t count = 1;
  };
  struct call {
    list<modifier> mods;
    std::string name;
    qasm_token at;
    list<expr> params;
    list<qubit_index> operands;  // global qubits at top level, argument numbers in a gate body
  };
  struct gate_def {
    list<std::string> params, qubits;
    list<call> body;
  };
  // A controlled single-qubit gate, or a controlled global phase.
  struct instr {
    gate1 g;
    qubit_index target = 0;
    list<control> controls;
    bool is_phase = false;
    double phase = 0;
  };
  struct reg {
    std::string name;
    std::size_t offset, size;
  };
  struct arity {
    std::size_t params, qubits;
  };

  // ---- helpers ------------------------------------------------------------------------------
  qasm_token expect(char p, const char* context) {
    const qasm_token t = lex_.next();
    if (!t.is(p)) qasm_fail(t, std::string("expected '") + p + "' " + context + ", found " + t.describe());
    return t;
  }
  qasm_token expect_identifier(const char* what) {
    const qasm_token t = lex_.next();
    if (t.kind != qasm_token::identifier) qasm_fail(t, std::string("expected ") + what + ", found " + t.describe());
    return t;
  }
  static std::optional<arity> std_arity(std::string_view name) {
    for (const qasm_std_gate& g : qasm_std_gates)
      if (g.name == name) return arity{g.params, g.qubits};
    return std::nullopt;
  }
  std::optional<arity> lookup(std::string_view name) const {
    if (name == "U") return arity{3, 1};
    if (name == "gphase") return arity{1, 0};
    if (auto it = gates_.find(name); it != gates_.end()) return arity{it->second.params.size(), it->second.qubits.size()};
    if (std_included_) return std_arity(name);
    return std::nullopt;
  }
  static bool reserved(std::string_view w) {
    for (std::string_view r : {"ctrl", "negctrl", "inv", "pow", "gate", "qubit", "qreg", "include", "OPENQASM", "barrier"})
      if (w == r) return true;
    return false;
  }
  // A constant expression's value as an integer in [lo, hi].
  std::size_t integer(const qasm_token& at, double v, const char* what, std::size_t lo, std::size_t hi) {
    if (!(v == std::floor(v)) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
      qasm_fail(at, std::string(what) + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], got " + qasm_value_text(v));
    return static_cast<std::size_t>(v);
  }

  // ---- expressions --------------------------------------------------------------------------
  // Parsing and evaluating recurse as deep as an expression nests (parentheses, signs, powers,
  // and chains like 1+1+...+1): deeper ones are refused before they can exhaust the stack. Every
  // nesting passes through parse_unary, which counts the levels.
  static constexpr std::size_t max_expression_depth = 1000;
  class nesting_guard {
   public:
    nesting_guard(qasm_parser& p, const qasm_token& at) : p_(p) {
      if (++p_.nesting_ > max_expression_depth) {
        --p_.nesting_;
        too_deep(at);
      }
    }
    ~nesting_guard() { --p_.nesting_; }
    nesting_guard(const nesting_guard&) = delete;
    nesting_guard& operator=(const nesting_guard&) = delete;

   private:
    qasm_parser& p_;
  };
  [[noreturn]] static void too_deep(const qasm_token& at) {
    qasm_fail(at, "expression nested more than " + std::to_string(max_expression_depth) + " levels deep");
  }
  // An operator node over `args`.
  static expr node(char op, list<expr> args, const qasm_token& at, std::string fn = {}) {
    expr r{op, 0, 0, std::move(fn), std::move(args), 1};
    for (const expr& a : r.args) r.depth = std::max(r.depth, a.depth + 1);
    if (r.depth > max_expression_depth) too_deep(at);
    return r;
  }
  expr parse_expr(const gate_def* def) {
    expr e = parse_term(def);
    while (lex_.peek().is('+') || lex_.peek().is('-')) {
      const qasm_token op = lex_.next();
      list<expr> args;
      args.push_back(std::move(e));
      args.push_back(parse_term(def));
      e = node(op.text[0], std::move(args), op);
    }
    return e;
  }
  expr parse_term(const gate_def* def) {
    expr e = parse_unary(def);
    while (lex_.peek().is('*') || lex_.peek().is('/')) {
      const qasm_token op = lex_.next();
      list<expr> args;
      args.push_back(std::move(e));
      args.push_back(parse_unary(def));
      e = node(op.text[0], std::move(args), op);
    }
    return e;
  }
  expr parse_unary(const gate_def* def) {
    const nesting_guard guard(*this, lex_.peek());
    if (lex_.peek().is('-') || lex_.peek().is('+')) {
      const qasm_token sign = lex_.next();
      expr inner = parse_unary(def);
      if (sign.is('+')) return inner;
      list<expr> args;
      args.push_back(std::move(inner));
      return node('u', std::move(args), sign);
    }
    expr base = parse_primary(def);
    if (lex_.peek().kind == qasm_token::punct && lex_.peek().text == "**") {
      const qasm_token op = lex_.next();
      list<expr> args;
      args.push_back(std::move(base));
      args.push_back(parse_unary(def));
      return node('^', std::move(args), op);
    }
    return base;
  }
  expr parse_primary(const gate_def* def) {
    const qasm_token t = lex_.next();
    if (t.kind == qasm_token::number) return {'n', t.value, 0, {}, {}};
    if (t.is('(')) {
      expr e = parse_expr(def);
      expect(')', "to close the parenthesis");
      return e;
    }
    if (t.kind != qasm_token::identifier) qasm_fail(t, "expected a number or an expression, found " + t.describe());
    const double pi = std::acos(-1.0);
    if (t.text == "pi" || t.text == "\xCF\x80") return {'n', pi, 0, {}, {}};
    if (t.text == "tau" || t.text == "\xCF\x84") return {'n', 2 * pi, 0, {}, {}};
    if (t.text == "euler" || t.text == "\xE2\x84\x87") return {'n', std::exp(1.0), 0, {}, {}};
    if (def != nullptr)
      for (std::size_t i = 0; i < def->params.size(); ++i)
        if (def->params[i] == t.text) return {'p', 0, i, {}, {}};
    for (std::string_view f : {"sin", "cos", "tan", "arcsin", "arccos", "arctan", "exp", "ln", "sqrt"})
      if (t.text == f) {
        expect('(', ("after the function " + std::string(f)).c_str());
        list<expr> args;
        args.push_back(parse_expr(def));
        expect(')', "to close the function argument");
        return node('f', std::move(args), t, std::string(f));
      }
    qasm_fail(t, "unknown identifier '" + std::string(t.text) + "' in an expression");
  }
  static double eval(const expr& e, std::span<const double> env) {
    switch (e.op) {
      case 'n': return e.value;
      case 'p': return env[e.param];
      case 'u': return -eval(e.args[0], env);
      case '+': return eval(e.args[0], env) + eval(e.args[1], env);
      case '-': return eval(e.args[0], env) - eval(e.args[1], env);
      case '*': return eval(e.args[0], env) * eval(e.args[1], env);
      case '/': return eval(e.args[0], env) / eval(e.args[1], env);
      case '^': return std::pow(eval(e.args[0], env), eval(e.args[1], env));
      default: break;
    }
    const double x = eval(e.args[0], env);
    if (e.fn == "sin") return std::sin(x);
    if (e.fn == "cos") return std::cos(x);
    if (e.fn == "tan") return std::tan(x);
    if (e.fn == "arcsin") return std::asin(x);
    if (e.fn == "arccos") return std::acos(x);
    if (e.fn == "arctan") return std::atan(x);
    if (e.fn == "exp") return std::exp(x);
    if (e.fn == "ln") return std::log(x);
    return std::sqrt(x);
  }
  // A constant integer expression in [lo, hi].
  std::size_t constant(const char* what, std::size_t lo, std::size_t hi) {
    const qasm_token at = lex_.peek();
    return integer(at, eval(parse_expr(nullptr), {}), what, lo, hi);
  }

  // ---- statements ---------------------------------------------------------------------------
  void statement() {
    const qasm_token t = lex_.peek();
    if (t.kind != qasm_token::identifier)
      qasm_fail(t, "expected a statement (a qubit declaration, a gate definition or a gate call), found " + t.describe());
    if (t.is("include")) {
      lex_.next();
      const qasm_token f = lex_.next();
      if (f.kind != qasm_token::string) qasm_fail(f, "expected a file name in quotes after include, found " + f.describe());
      if (f.text != "stdgates.inc")
        qasm_fail(f, "cannot include \"" + std::string(f.text) + "\": only \"stdgates.inc\" is built in");
      std_included_ = true;
      expect(';', "after the include");
    } else if (t.is("qubit")) {
      lex_.next();
      std::size_t size = 1;
      if (lex_.peek().is('[')) {
        lex_.next();
        size = constant("a register size", 1, 1u << 20);
        expect(']', "after the register size");
      }
      declare(expect_identifier("a register name"), size);
      expect(';', "after the qubit declaration");
    } else if (t.is("qreg")) {
      lex_.next();
      const qasm_token name = expect_identifier("a register name");
      std::size_t size = 1;
      expect('[', "after the register name");
      size = constant("a register size", 1, 1u << 20);
      expect(']', "after the register size");
      declare(name, size);
      expect(';', "after the qreg declaration");
    } else if (t.is("gate")) {
      definition();
    } else if (t.is("barrier")) {
      lex_.next();
      while (!lex_.peek().is(';')) {
        if (lex_.peek().kind == qasm_token::end) qasm_fail(lex_.peek(), "expected ';' after the barrier, found end of input");
        lex_.next();
      }
      lex_.next();
    } else if (t.is("OPENQASM")) {
      qasm_fail(t, "the OPENQASM version must be the first statement");
    } else {
      for (std::string_view w : {"bit", "creg", "measure", "reset", "if", "for", "while", "def", "let", "const", "input",
                                 "output", "box", "delay", "defcal", "cal", "int", "uint", "float", "angle", "bool"})
        if (t.text == w) qasm_fail(t, "'" + std::string(w) + "' statements are not supported (qrm imports unitary circuits)");
      execute(parse_call(nullptr));
    }
  }

  void declare(const qasm_token& name, std::size_t size) {
    if (width_ + size > max_qubits)
      qasm_fail(name, "the registers declared add up to more than " + std::to_string(max_qubits) + " qubits");
    for (const reg& r : regs_)
      if (r.name == name.text) qasm_fail(name, "register '" + r.name + "' is already declared");
    if (reserved(name.text)) qasm_fail(name, "'" + std::string(name.text) + "' is a keyword");
    regs_.push_back({std::string(name.text), width_, size});
    width_ += size;
  }

  void definition() {
    lex_.next();
    const qasm_token name = expect_identifier("a gate name");
    if (reserved(name.text)) qasm_fail(name, "'" + std::string(name.text) + "' is a keyword");
    if (lookup(name.text)) qasm_fail(name, "gate '" + std::string(name.text) + "' is already defined");
    gate_def def;
    auto unique = [&](const list<std::string>& names, const qasm_token& t) {
      if (std::find(names.begin(), names.end(), t.text) != names.end())
        qasm_fail(t, "'" + std::string(t.text) + "' is declared twice in the definition of gate '" + std::string(name.text) + "'");
    };
    if (lex_.peek().is('(')) {
      lex_.next();
      if (!lex_.peek().is(')'))
        for (;;) {
          const qasm_token p = expect_identifier("a parameter name");
          unique(def.params, p);
          def.params.emplace_back(p.text);
          if (!lex_.peek().is(',')) break;
          lex_.next();
        }
      expect(')', "after the gate parameters");
    }
    for (;;) {
      const qasm_token q = expect_identifier("a qubit argument name");
      unique(def.params, q);
      unique(def.qubits, q);
      def.qubits.emplace_back(q.text);
      if (!lex_.peek().is(',')) break;
      lex_.next();
    }
    const qasm_token open = expect('{', "to open the gate body");
    while (!lex_.peek().is('}')) {
      if (lex_.peek().kind == qasm_token::end)
        qasm_fail(lex_.peek(), "expected '}' to close the body of gate '" + std::string(name.text) + "' opened at " +
                                   std::to_string(open.line) + ":" + std::to_string(open.column) + ", found end of input");
      def.body.push_back(parse_call(&def));
    }
    lex_.next();
    gates_.emplace(std::string(name.text), std::move(def));
  }

  qubit_index parse_operand(const gate_def* def) {
    const qasm_token t = expect_identifier("a qubit operand");
    if (def != nullptr) {
      const auto it = std::find(def->qubits.begin(), def->qubits.end(), t.text);
      if (it == def->qubits.end()) qasm_fail(t, "'" + std::string(t.text) + "' is not a qubit argument of this gate");
      if (lex_.peek().is('[')) qasm_fail(lex_.peek(), "a gate's qubit arguments are single qubits and cannot be indexed");
      return static_cast<qubit_index>(it - def->qubits.begin());
    }
    const auto r = std::find_if(regs_.begin(), regs_.end(), [&](const reg& x) { return x.name == t.text; });
    if (r == regs_.end()) qasm_fail(t, "unknown qubit register '" + std::string(t.text) + "'");
    if (!lex_.peek().is('[')) {
      if (r->size != 1)
        qasm_fail(t, "register '" + r->name + "' has " + std::to_string(r->size) +
                         " qubits: index it (" + r->name + "[i]); broadcasting is not supported");
      return static_cast<qubit_index>(r->offset);
    }
    lex_.next();
    const qasm_token at = lex_.peek();
    const double v = eval(parse_expr(nullptr), {});
    if (!(v == std::floor(v)) || v < 0)
      qasm_fail(at, "a qubit index must be a non-negative integer, got " + qasm_value_text(v));
    if (v >= static_cast<double>(r->size))
      qasm_fail(at, "qubit index " + qasm_value_text(v) + " is out of range for '" + r->name + "' (" + std::to_string(r->size) +
                        (r->size == 1 ? " qubit)" : " qubits)"));
    expect(']', "after the qubit index");
    return static_cast<qubit_index>(r->offset + static_cast<std::size_t>(v));
  }

  std::string operand_name(const gate_def* def, qubit_index q) const {
    if (def != nullptr) return def->qubits[q];
    for (const reg& r : regs_)
      if (q >= r.offset && q < r.offset + r.size) return r.name + "[" + std::to_string(q - r.offset) + "]";
    return std::to_string(q);
  }

  call parse_call(const gate_def* def) {
    call c;
    for (;;) {
      const qasm_token t = lex_.peek();
      if (!(t.is("ctrl") || t.is("negctrl") || t.is("inv") || t.is("pow"))) break;
      lex_.next();
      if (t.is("pow")) qasm_fail(t, "the pow modifier is not supported");
      modifier m;
      m.inverse = t.is("inv");
      m.negative = t.is("negctrl");
      if (!m.inverse && lex_.peek().is('(')) {
        lex_.next();
        m.count = constant("a control count", 1, 64);
        expect(')', "after the control count");
      }
      expect('@', "after the modifier");
      c.mods.push_back(m);
    }
    c.at = expect_identifier("a gate name");
    c.name = std::string(c.at.text);
    const std::optional<arity> a = lookup(c.name);
    if (!a) {
      if (!std_included_ && std_arity(c.name))
        qasm_fail(c.at, "unknown gate '" + c.name + "' (the standard gates need include \"stdgates.inc\";)");
      qasm_fail(c.at, "unknown gate '" + c.name + "'");
    }
    if (lex_.peek().is('(')) {
      lex_.next();
      if (!lex_.peek().is(')'))
        for (;;) {
          c.params.push_back(parse_expr(def));
          if (!lex_.peek().is(',')) break;
          lex_.next();
        }
      expect(')', "after the gate parameters");
    }
    if (c.params.size() != a->params)
      qasm_fail(c.at, "gate '" + c.name + "' takes " + std::to_string(a->params) +
                          (a->params == 1 ? " parameter" : " parameters") + ", got " + std::to_string(c.params.size()));
    if (!lex_.peek().is(';'))
      for (;;) {
        c.operands.push_back(parse_operand(def));
        if (!lex_.peek().is(',')) break;
        lex_.next();
      }
    expect(';', "after the gate call");
    std::size_t controls = 0;
    for (const modifier& m : c.mods)
      if (!m.inverse) controls += m.count;
    if (c.operands.size() != controls + a->qubits)
      qasm_fail(c.at, "gate '" + c.name + "' acts on " + std::to_string(a->qubits) +
                          (a->qubits == 1 ? " qubit" : " qubits") +
                          (controls ? " plus " + std::to_string(controls) + " controls from its modifiers" : std::string()) +
                          ", got " + std::to_string(c.operands.size()) + " operands");
    for (std::size_t i = 0; i < c.operands.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (c.operands[i] == c.operands[j])
          qasm_fail(c.at, "qubit " + operand_name(def, c.operands[i]) + " appears twice in this gate call");
    return c;
  }

  // ---- semantics ----------------------------------------------------------------------------
  static instr single(const gate1& g, qubit_index q) { return {g, q, {}, false, 0}; }
  static instr controlled(const gate1& g, qubit_index c, qubit_index q) { return {g, q, {{c, true}}, false, 0}; }

  // Gate definitions that call each other multiply (a body calling the previous gate twice, ten
  // levels deep, is 2^10 gates): their expansion is bounded so a small file cannot exhaust time
  // or memory. Counted over the whole import: the primitive gates (controlled single-qubit
  // gates and phases) that expanding definitions produces; the matrix of a definition on k <= 6
  // qubits costs its expanded size x 4^k operations.
  static constexpr std::size_t max_expanded_gates = std::size_t{1} << 20;
  static constexpr std::uint64_t max_matrix_work = std::uint64_t{1} << 30;
  static constexpr std::size_t max_qubits = std::size_t{1} << 24;

  // Where the top-level call being executed is (for errors found while expanding it).
  std::string site_text(const qasm_token& at) const {
    if (!site_ || (site_->line == at.line && site_->column == at.column)) return "";
    return " (expanding the call of '" + std::string(site_->text) + "' at " + std::to_string(site_->line) + ":" +
           std::to_string(site_->column) + ")";
  }
  void charge_expansion(std::size_t gates) {
    expanded_ += gates;
    if (expanded_ > max_expanded_gates)
      qasm_fail(*site_, "gate '" + std::string(site_->text) + "' expands to more than " +
                            std::to_string(max_expanded_gates) +
                            " gates (gate definitions that call each other multiply); qrm imports at most that many");
  }
  // The parameters of call c, evaluated in env; angles must be finite.
  list<double> parameters(const call& c, std::span<const double> env) const {
    list<double> params;
    for (const expr& e : c.params) params.push_back(eval(e, env));
    for (std::size_t i = 0; i < params.size(); ++i)
      if (!std::isfinite(params[i]))
        qasm_fail(c.at, "gate '" + c.name + "': parameter " + std::to_string(i + 1) + " is " + qasm_value_text(params[i]) +
                            "; angles must be finite" + site_text(c.at));
    return params;
  }

  // The gate `name` on `args` (no modifiers), appended to out.
  void base(const std::string& name, std::span<const double> p, std::span<const qubit_index> a, list<instr>& out) {
    const double pi = std::acos(-1.0);
    const std::size_t before = out.size();
    if (name == "U") {
      out.push_back(single(qasm_u_matrix(p[0], p[1], p[2]), a[0]));
    } else if (name == "gphase") {
      out.push_back({gate1{}, 0, {}, true, p[0]});
    } else if (auto it = gates_.find(name); it != gates_.end()) {
      in_definition_ += 1;
      for (const call& c : it->second.body) expand(c, p, a, out);
      in_definition_ -= 1;
      return;
    } else if (name == "x" || name == "y" || name == "z" || name == "h") {
      out.push_back(single(name == "x" ? gate::x() : name == "y" ? gate::y() : name == "z" ? gate::z() : gate::h(), a[0]));
    } else if (name == "s" || name == "sdg" || name == "t" || name == "tdg") {
      const double angle = (name[0] == 's' ? pi / 2 : pi / 4) * (name.size() == 3 ? -1.0 : 1.0);
      out.push_back(single(gate::phase(angle), a[0]));
    } else if (name == "sx") {
      const complex pl(0.5, 0.5), mi(0.5, -0.5);
      out.push_back(single(gate::u(pl, mi, mi, pl), a[0]));
    } else if (name == "rx") {
      out.push_back(single(qasm_u_matrix(p[0], -pi / 2, pi / 2), a[0]));
    } else if (name == "ry") {
      out.push_back(single(gate::ry(p[0]), a[0]));
    } else if (name == "rz") {
      out.push_back(single(gate::rz(p[0]), a[0]));
    } else if (name == "p" || name == "phase" || name == "u1") {
      out.push_back(single(gate::phase(p[0]), a[0]));
    } else if (name == "id") {
    } else if (name == "u2" || name == "u3") {
      const double theta = name == "u2" ? pi / 2 : p[0], phi = p[name == "u2" ? 0 : 1], lambda = p[name == "u2" ? 1 : 2];
      gate1 g = qasm_u_matrix(theta, phi, lambda);
      const complex z = std::polar(1.0, -phi / 2) * std::polar(1.0, -lambda / 2);  // no overflow of phi + lambda
      for (auto& row : g.m)
        for (complex& v : row) v *= z;
      out.push_back(single(g, a[0]));
    } else if (name == "cx" || name == "CX") {
      out.push_back(controlled(gate::x(), a[0], a[1]));
    } else if (name == "cy") {
      out.push_back(controlled(gate::y(), a[0], a[1]));
    } else if (name == "cz") {
      out.push_back(controlled(gate::z(), a[0], a[1]));
    } else if (name == "ch") {
      out.push_back(controlled(gate::h(), a[0], a[1]));
    } else if (name == "cp" || name == "cphase") {
      out.push_back(controlled(gate::phase(p[0]), a[0], a[1]));
    } else if (name == "crx") {
      out.push_back(controlled(qasm_u_matrix(p[0], -pi / 2, pi / 2), a[0], a[1]));
    } else if (name == "cry") {
      out.push_back(controlled(gate::ry(p[0]), a[0], a[1]));
    } else if (name == "crz") {
      out.push_back(controlled(gate::rz(p[0]), a[0], a[1]));
    } else if (name == "cu") {
      out.push_back(single(gate::phase(p[3]), a[0]));
      out.push_back(controlled(qasm_u_matrix(p[0], p[1], p[2]), a[0], a[1]));
    } else if (name == "swap" || name == "cswap") {
      const std::size_t o = name == "cswap" ? 1 : 0;
      for (int i = 0; i < 3; ++i) {
        instr cx = controlled(gate::x(), a[o + (i % 2)], a[o + 1 - (i % 2)]);
        if (o) cx.controls.push_back({a[0], true});
        out.push_back(cx);
      }
    } else if (name == "ccx") {
      out.push_back({gate::x(), a[2], {{a[0], true}, {a[1], true}}, false, 0});
    }
    if (in_definition_ > 0) charge_expansion(out.size() - before);
  }

  // The call c (its operands mapped through `qubits` inside a gate body), appended to out.
  void expand(const call& c, std::span<const double> env, std::span<const qubit_index> qubits, list<instr>& out,
              bool top_level = false) {
    const list<double> params = parameters(c, env);
    list<qubit_index> q;
    for (qubit_index o : c.operands) q.push_back(top_level ? o : qubits[o]);
    list<control> cs;
    bool inverse = false;
    std::size_t next = 0;
    for (const modifier& m : c.mods) {
      if (m.inverse) {
        inverse = !inverse;
        continue;
      }
      for (std::size_t i = 0; i < m.count; ++i) cs.push_back({q[next++], !m.negative});
    }
    list<instr> body;
    base(c.name, params, std::span<const qubit_index>(q).subspan(next), body);
    if (inverse) {
      std::reverse(body.begin(), body.end());
      for (instr& i : body) {
        i.g = adjoint(i.g);
        i.phase = -i.phase;
      }
    }
    for (instr& i : body) {
      i.controls.insert(i.controls.end(), cs.begin(), cs.end());
      out.push_back(std::move(i));
    }
  }

  // The matrix of user gate `name` with parameters p, from its body (cached).
  const dense_matrix& matrix_of(const std::string& name, const list<double>& p, std::size_t k) {
    auto key = std::make_pair(name, p);
    if (auto it = matrices_.find(key); it != matrices_.end()) return it->second;
    list<qubit_index> args(k);
    for (std::size_t i = 0; i < k; ++i) args[i] = static_cast<qubit_index>(i);
    list<instr> body;
    base(name, p, args, body);
    const std::size_t d = std::size_t{1} << k;
    matrix_work_ += static_cast<std::uint64_t>(body.size()) * d * d;
    if (matrix_work_ > max_matrix_work)
      qasm_fail(*site_, "gate '" + name + "' is too large to import: the matrices of the gate definitions need more than " +
                            std::to_string(max_matrix_work) + " operations (gate definitions that call each other multiply)");
    dense_matrix m(d);
    list<complex> v(d);
    for (std::size_t col = 0; col < d; ++col) {
      std::fill(v.begin(), v.end(), complex{});
      v[col] = 1.0;
      for (const instr& in : body) {
        for (std::size_t i = 0; i < d; ++i) {
          bool hold = true;
          for (const control& c : in.controls) hold = hold && (((i >> c.qubit) & 1u) != 0) == c.value;
          if (!hold) continue;
          if (in.is_phase) {
            v[i] *= std::polar(1.0, in.phase);
          } else if (((i >> in.target) & 1u) == 0) {
            const std::size_t j = i | (std::size_t{1} << in.target);
            const complex a0 = v[i], a1 = v[j];
            v[i] = in.g.m[0][0] * a0 + in.g.m[0][1] * a1;
            v[j] = in.g.m[1][0] * a0 + in.g.m[1][1] * a1;
          }
        }
      }
      for (std::size_t r = 0; r < d; ++r) m(r, col) = v[r];
    }
    return matrices_.emplace(std::move(key), std::move(m)).first->second;
  }

  void execute(const call& c) {
    site_ = c.at;
    const auto user = gates_.find(c.name);
    const std::size_t k = user == gates_.end() ? 0 : user->second.qubits.size();
    if (k >= 1 && k <= 6) {
      const list<double> params = parameters(c, {});
      list<control> cs;
      bool inverse = false;
      std::size_t next = 0;
      for (const modifier& m : c.mods) {
        if (m.inverse) {
          inverse = !inverse;
          continue;
        }
        for (std::size_t i = 0; i < m.count; ++i) cs.push_back({c.operands[next++], !m.negative});
      }
      const dense_matrix& m = matrix_of(c.name, params, k);
      list<qubit_index> targets(c.operands.begin() + static_cast<std::ptrdiff_t>(next), c.operands.end());
      ops_.push_back(op::unitary_op{inverse ? adjoint(m) : m, std::move(targets), std::move(cs)});
      return;
    }
    list<instr> out;
    expand(c, {}, {}, out, true);
    for (instr& i : out) {
      if (!i.is_phase) {
        ops_.push_back(op::gate1_op{i.g, i.target, std::move(i.controls)});
      } else if (i.controls.empty()) {
        // Reduced modulo 2 pi as it is summed: many large finite phases must not add up to inf.
        const double turn = 2 * std::acos(-1.0);
        global_phase_ = std::remainder(global_phase_ + std::remainder(i.phase, turn), turn);
      } else {
        const control last = i.controls.back();
        i.controls.pop_back();
        const complex z = std::polar(1.0, i.phase);
        ops_.push_back(op::gate1_op{last.value ? gate::phase(i.phase) : gate::u(z, 0.0, 0.0, 1.0), last.qubit,
                                    std::move(i.controls)});
      }
    }
  }

  qasm_lexer<Deferred> lex_;
  list<reg> regs_;
  std::size_t width_ = 0;
  bool std_included_ = false;
  std::map<std::string, gate_def, std::less<>> gates_;
  std::map<std::pair<std::string, list<double>>, dense_matrix> matrices_;
  list<op::any> ops_;
  double global_phase_ = 0;
  std::size_t nesting_ = 0;             // current expression nesting while parsing
  std::optional<qasm_token> site_;      // the top-level call being executed
  std::size_t in_definition_ = 0;       // > 0 while expanding the body of a definition
  std::size_t expanded_ = 0;            // gates produced by expanding definitions so far
  std::uint64_t matrix_work_ = 0;       // operations spent on definition matrices so far
};

}  // namespace detail

// to_qasm(p): p as an OpenQASM 3 program (the forms are described at the top of this header).
template <int = 0>
std::string to_qasm(const program& p, qasm_options options = {}) {
  return options.decomposed ? detail::to_qasm_decomposed(p, options) : detail::to_qasm_logical(p, options);
}

// from_qasm(text): the program an OpenQASM 3 text describes (the subset is listed at the top
// of this header); throws qrm::qasm_error naming the line, the column and what was expected.
template <int Deferred = 0>
program from_qasm(std::string_view text) { return detail::qasm_parser<Deferred>(text).parse(); }

}  // namespace qrm

// This header's part of <qrm/circuit/compiled_circuit.hpp> (QRM_COMPILED_CIRCUIT).
#define QRM_DETAIL_QASM_INSTANCES(PREFIX)                      \
  PREFIX std::string to_qasm<0>(const program&, qasm_options); \
  PREFIX program from_qasm<0>(std::string_view);
#ifdef QRM_COMPILED_CIRCUIT
namespace qrm {
QRM_DETAIL_QASM_INSTANCES(extern template)
}  // namespace qrm
#endif
