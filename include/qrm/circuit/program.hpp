// qrm/circuit/program.hpp: a run-time list of primitive operations (the lowered form of any circuit).
//
// A program records what a static circuit emits (it is a gate_sink), replays it into any other
// sink (a backend, a metrics counter, an exporter), and can be inverted, remapped and pruned at
// run time: the scene-dependent parts of the walk circuit are decided here.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>
#include <variant>
#include <vector>

#include "../support/detail/formatted_error.hpp"
#include "layout.hpp"
#include "ops.hpp"
#include "../support/detail/meta.hpp"

namespace qrm {

namespace op {
struct gate1_op {
  qrm::gate1 gate;
  qubit_index target;
  std::vector<control> controls;
};
struct unitary_op {
  dense_matrix matrix;
  std::vector<qubit_index> targets;
  std::vector<control> controls;
};
struct add_op {
  std::int64_t constant;
  std::vector<qubit_index> bits;
  std::vector<control> controls;
};
struct mux1_op {
  std::vector<mux1_entry> entries;
  qubit_index target;
  std::vector<qubit_index> select;
  std::vector<control> controls;
};
struct mux_unitary_op {
  std::vector<dense_matrix> matrices;
  std::vector<mux_unitary_entry> entries;
  std::vector<qubit_index> targets;
  std::vector<qubit_index> select;
  std::vector<control> controls;
};
using any = std::variant<gate1_op, unitary_op, add_op, mux1_op, mux_unitary_op>;
}  // namespace op

// visit_op(o, f): f applied to the alternative o holds. A switch rather than std::visit, whose
// instantiation for this variant cost ~0.4 s of the umbrella header's compile time.
template <class Op, class F>
decltype(auto) visit_op(Op&& o, F&& f) {
  switch (o.index()) {
    case 0: return f(*std::get_if<0>(&o));
    case 1: return f(*std::get_if<1>(&o));
    case 2: return f(*std::get_if<2>(&o));
    case 3: return f(*std::get_if<3>(&o));
    case 4: return f(*std::get_if<4>(&o));
  }
  throw std::logic_error("visit_op: an op holds no value");
}

// Replays one op into a sink.
template <gate_sink S>
void emit_op(const op::any& o, S& sink) {
  visit_op(o, [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, op::gate1_op>) {
          sink.apply_gate1(x.gate, x.target, x.controls);
        } else if constexpr (std::is_same_v<T, op::unitary_op>) {
          sink.apply_unitary(x.matrix, x.targets, x.controls);
        } else if constexpr (std::is_same_v<T, op::add_op>) {
          sink.apply_add(x.constant, x.bits, x.controls);
        } else if constexpr (std::is_same_v<T, op::mux1_op>) {
          sink.apply_mux1(x.entries, x.target, x.select, x.controls);
        } else {
          sink.apply_mux_unitary(x.matrices, x.entries, x.targets, x.select, x.controls);
        }
      });
}

// Qubits an op reads or writes.
template <int D = 0>
inline std::vector<qubit_index> op_qubits(const detail::deferred<op::any, D>& o) {
  detail::deferred<std::vector<qubit_index>, D> q;
  visit_op(o, [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, op::gate1_op>) {
          q.push_back(x.target);
        } else if constexpr (std::is_same_v<T, op::unitary_op>) {
          q = x.targets;
        } else if constexpr (std::is_same_v<T, op::add_op>) {
          q = x.bits;
        } else if constexpr (std::is_same_v<T, op::mux1_op>) {
          q.push_back(x.target);
          q.insert(q.end(), x.select.begin(), x.select.end());
        } else {
          q = x.targets;
          q.insert(q.end(), x.select.begin(), x.select.end());
        }
        for (const control& c : x.controls) q.push_back(c.qubit);
      });
  return q;
}

template <int D = 0>
inline bool op_is_real(const detail::deferred<op::any, D>& o) {
  return visit_op(o, [](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, op::gate1_op>) {
          return x.gate.is_real();
        } else if constexpr (std::is_same_v<T, op::unitary_op>) {
          return x.matrix.is_real();
        } else if constexpr (std::is_same_v<T, op::add_op>) {
          return true;
        } else if constexpr (std::is_same_v<T, op::mux1_op>) {
          return std::all_of(x.entries.begin(), x.entries.end(), [](const mux1_entry& e) { return e.gate.is_real(); });
        } else {
          return std::all_of(x.matrices.begin(), x.matrices.end(), [](const dense_matrix& m) { return m.is_real(); });
        }
      });
}

template <int D = 0>
inline detail::deferred<op::any, D> op_adjoint(const detail::deferred<op::any, D>& o) {
  return visit_op(o, [](const auto& x) -> detail::deferred<op::any, D> {
        using T = std::decay_t<decltype(x)>;
        T r = x;
        if constexpr (std::is_same_v<T, op::gate1_op>) {
          r.gate = adjoint(x.gate);
        } else if constexpr (std::is_same_v<T, op::unitary_op>) {
          r.matrix = adjoint(x.matrix);
        } else if constexpr (std::is_same_v<T, op::add_op>) {
          r.constant = -x.constant;
        } else if constexpr (std::is_same_v<T, op::mux1_op>) {
          for (auto& e : r.entries) e.gate = adjoint(e.gate);
        } else {
          for (auto& m : r.matrices) m = adjoint(m);
        }
        return r;
      });
}

// program: a width and a list of ops; records from any static circuit (it is a gate_sink). A
// class template only so that its members are compiled where used (see qrm.hpp).
template <int Deferred = 0>
class basic_program {
  template <class T>
  using list = detail::deferred<std::vector<T>, Deferred>;
  template <class T>
  using op_t = detail::deferred<T, Deferred>;

 public:
  basic_program() = default;
  explicit basic_program(std::size_t width) : width_(width) {}

  // A program recorded from circuit c, keeping its layout's register table for export.
  template <class C>
  static basic_program from(const C& c) {
    basic_program p(C::width);
    for (const register_info& r : C::layout_type::register_table) p.registers_.push_back(r);
    c.emit(p);
    return p;
  }

  std::size_t width() const { return width_; }
  const std::vector<op::any>& ops() const { return ops_; }
  std::vector<op::any>& ops() { return ops_; }
  const std::vector<register_info>& registers() const { return registers_; }
  void set_registers(std::vector<register_info> r) { registers_ = std::move(r); }
  std::size_t size() const { return ops_.size(); }

  // Layer labels: ops pushed after enter_layer(name) carry `name` (nullptr: no layer). Static
  // strings only; the label is what a typed circuit knew when it was lowered.
  void enter_layer(const char* name) { current_layer_ = name; }
  const char* layer_of(std::size_t op) const { return op < layers_.size() ? layers_[op] : nullptr; }
  const std::vector<const char*>& layers() const { return layers_; }
  bool is_real() const {
    return std::all_of(ops_.begin(), ops_.end(), [](const auto& o) { return op_is_real(o); });
  }

  void push(detail::deferred<op::any, Deferred> o) {
    for (qubit_index q : op_qubits(o))
      if (q >= width_)
        detail::throw_formatted<std::invalid_argument>("program: op uses qubit %u but the program has %zu qubits",
                                                       static_cast<unsigned>(q), width_);
    ops_.push_back(std::move(o));
    layers_.push_back(current_layer_);
  }
  void append(const basic_program& other) {
    if (other.width_ > width_) width_ = other.width_;
    ops_.insert(ops_.end(), other.ops_.begin(), other.ops_.end());
    layers_.insert(layers_.end(), other.layers_.begin(), other.layers_.end());
    layers_.resize(ops_.size(), nullptr);
  }

  // gate_sink: record.
  void apply_gate1(const gate1& g, qubit_index t, std::span<const control> cs) {
    push(op_t<op::gate1_op>{g, t, {cs.begin(), cs.end()}});
  }
  void apply_unitary(const dense_matrix& m, std::span<const qubit_index> ts, std::span<const control> cs) {
    push(op_t<op::unitary_op>{m, {ts.begin(), ts.end()}, {cs.begin(), cs.end()}});
  }
  void apply_add(std::int64_t c, std::span<const qubit_index> bits, std::span<const control> cs) {
    push(op_t<op::add_op>{c, {bits.begin(), bits.end()}, {cs.begin(), cs.end()}});
  }
  void apply_mux1(std::span<const mux1_entry> es, qubit_index t, std::span<const qubit_index> sel,
                  std::span<const control> cs) {
    push(op_t<op::mux1_op>{{es.begin(), es.end()}, t, {sel.begin(), sel.end()}, {cs.begin(), cs.end()}});
  }
  void apply_mux_unitary(std::span<const dense_matrix> ms, std::span<const mux_unitary_entry> es,
                         std::span<const qubit_index> ts, std::span<const qubit_index> sel,
                         std::span<const control> cs) {
    push(op_t<op::mux_unitary_op>{{ms.begin(), ms.end()}, {es.begin(), es.end()}, {ts.begin(), ts.end()},
                            {sel.begin(), sel.end()}, {cs.begin(), cs.end()}});
  }

  // Replay into a sink (a backend runs the program this way).
  template <gate_sink S>
  void emit(S& sink) const {
    const char* layer = nullptr;
    for (std::size_t i = 0; i < ops_.size(); ++i) {
      if (layer_of(i) != layer) qrm::enter_layer(sink, layer = layer_of(i));
      emit_op(ops_[i], sink);
    }
  }

  // The inverse program: ops reversed, each inverted.
  basic_program adjoint() const {
    basic_program r(width_);
    r.registers_ = registers_;
    r.ops_.reserve(ops_.size());
    for (std::size_t i = ops_.size(); i-- > 0;) r.ops_.push_back(op_adjoint(ops_[i]));
    r.layers_.assign(layers_.size(), nullptr);
    for (std::size_t i = 0; i < layers_.size(); ++i) r.layers_[i] = layers_[layers_.size() - 1 - i];
    r.layers_.resize(r.ops_.size(), nullptr);
    return r;
  }

 private:
  std::size_t width_ = 0;
  list<register_info> registers_;
  list<op::any> ops_;
  list<const char*> layers_;  // one per op
  const char* current_layer_ = nullptr;
};

using program = basic_program<>;

// run(backend, program): programs are checked at run time (width, and real vs complex).
template <class B, int Deferred>
void run(B& backend, const basic_program<Deferred>& p) {
  if (backend.num_qubits() < p.width())
    detail::throw_formatted<std::invalid_argument>("run: the program needs %zu qubits but the backend has %zu", p.width(),
                                                   static_cast<std::size_t>(backend.num_qubits()));
  if constexpr (requires { B::is_complex; }) {
    if constexpr (!B::is_complex) {
      for (std::size_t i = 0; i < p.ops().size(); ++i)
        if (!op_is_real(p.ops()[i]))
          detail::throw_formatted<std::invalid_argument>(
              "run: op %zu has a complex matrix but the backend stores real amplitudes", i);
    }
  }
  if constexpr (requires { backend.run_ops(p.ops()); })
    backend.run_ops(p.ops());  // a backend that schedules whole programs (the dense one: cache-sized chunks)
  else
    p.emit(backend);
}

}  // namespace qrm
