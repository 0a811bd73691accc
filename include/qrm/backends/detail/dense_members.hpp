// qrm/backends/detail/dense_members.hpp: state_vector's members that reach the kernels, defined
// outside the class so that they are not inline. dense.hpp includes this file unless
// QRM_COMPILED_BACKENDS is defined; then only <qrm/backends/compiled_backends.hpp> does (with the
// kernels), and every other file of the program calls the members compiled there.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "../dense.hpp"
#include "dense_blocked.hpp"
#include "dense_kernels.hpp"
#include "validate.hpp"

namespace qrm {

template <class Scalar>
detail::op_checks<std::uint64_t, Scalar> state_vector<Scalar>::checks() const {
  return {n_, "state_vector"};
}

template <class Scalar>
state_vector<Scalar>::state_vector(std::size_t num_qubits, dense_options opt) : n_(static_cast<unsigned>(num_qubits)) {
  const long double need = bytes_for(num_qubits);
  const std::uint64_t limit = opt.max_bytes ? opt.max_bytes : detail::physical_memory_bytes();
  if (num_qubits > 62 || (limit != 0 && need > static_cast<long double>(limit)))
    throw std::length_error("state_vector: " + std::to_string(num_qubits) + " qubits of " +
                            detail::scalar_name<Scalar>() + " need " + detail::format_bytes(need) + ", more than the " +
                            (limit ? detail::format_bytes(limit) : std::string("addressable")) +
                            " allowed (dense_options::max_bytes, default: physical memory); use the compact backend "
                            "or fewer qubits");
  ex_.threads = opt.threads ? opt.threads : std::max(1u, std::thread::hardware_concurrency());
  ex_.min_parallel = opt.min_parallel;
  ex_.mux = opt.mux;
  ex_.simd = opt.simd;
  ex_.math = opt.math;
  chunk_bytes_ = opt.chunk_bytes;
  set_chunk_min_passes(opt.chunk_min_passes);
  try {
    amps_.assign(static_cast<std::size_t>(std::uint64_t{1} << n_), Scalar{});
  } catch (const std::bad_alloc&) {
    throw std::length_error("state_vector: could not allocate " + detail::format_bytes(need) + " for " +
                            std::to_string(num_qubits) + " qubits");
  }
  amps_[0] = Scalar{1};
}

template <class Scalar>
void state_vector<Scalar>::apply_gate1(const gate1& g, qubit_index target, std::span<const control> controls) {
  const auto op = checks().gate1(g, target, controls);
  detail::kernel_gate1(amps_.data(), n_, g, target, op.cond.mask, op.cond.value, ex_);
}

template <class Scalar>
void state_vector<Scalar>::apply_unitary(const dense_matrix& m, std::span<const qubit_index> targets,
                                         std::span<const control> controls) {
  const auto op = checks().unitary(m, targets, controls);
  detail::kernel_unitary(amps_.data(), n_, m, targets, op.targets, op.cond.mask, op.cond.value, ex_);
}

template <class Scalar>
void state_vector<Scalar>::apply_add(std::int64_t constant, std::span<const qubit_index> bits,
                                     std::span<const control> controls) {
  const auto op = checks().add(bits, controls);
  if (bits.empty()) return;
  detail::kernel_add(amps_.data(), n_, constant, bits, op.targets, op.cond.mask, op.cond.value, ex_);
}

template <class Scalar>
void state_vector<Scalar>::apply_mux1(std::span<const mux1_entry> entries, qubit_index target,
                                      std::span<const qubit_index> select, std::span<const control> controls) {
  const auto op = checks().mux1(entries, target, select, controls);
  detail::kernel_mux1(amps_.data(), n_, entries, target, select, op.select, op.cond.mask, op.cond.value, ex_);
}

template <class Scalar>
void state_vector<Scalar>::apply_mux_unitary(std::span<const dense_matrix> matrices,
                                             std::span<const mux_unitary_entry> entries,
                                             std::span<const qubit_index> targets, std::span<const qubit_index> select,
                                             std::span<const control> controls) {
  const auto op = checks().mux_unitary(matrices, entries, targets, select, controls);
  detail::kernel_mux_unitary(amps_.data(), n_, matrices, entries, targets, op.targets, select, op.select,
                             op.cond.mask, op.cond.value, ex_);
}

template <class Scalar>
void state_vector<Scalar>::run_ops(std::span<const op::any> ops) {
  const unsigned m = detail::chunk_qubits<Scalar>(chunk_bytes_);
  if (m < 4 || m >= n_) {
    for (const op::any& o : ops) emit_op(o, *this);
    return;
  }
  // Every op is checked on the whole state first: chunks see renumbered qubits.
  const auto ck = checks();
  detail::validating_sink<decltype(ck)> validator{ck};
  for (const op::any& o : ops) emit_op(o, validator);
  const detail::run_plan plan = detail::plan_runs(ops, n_, m, detail::chunk_low_qubits<Scalar>(), chunk_min_passes_,
                                                  detail::memory_bound_dim<Scalar>(ex_));
  const std::span<const std::size_t> order(plan.order);
  for (const detail::op_run& r : plan.runs) {
    if (r.local == 0)
      emit_op(ops[order[r.first]], *this);
    else
      detail::run_in_chunks(amps_.data(), n_, ops, order.subspan(r.first, r.last - r.first), r.local, ex_);
  }
}

template <class Scalar>
void state_vector<Scalar>::set_chunk_min_passes(double passes) {
  // A NaN or negative count would chunk every run without saying so.
  if (!(passes >= 0) || !std::isfinite(passes))
    throw std::invalid_argument("dense_options::chunk_min_passes must be a finite number >= 0, got " +
                                std::to_string(passes));
  chunk_min_passes_ = passes;
}

template <class Scalar>
double state_vector<Scalar>::norm_squared() const {
  const detail::subspace all(n_, 0, 0);
  const Scalar* a = amps_.data();
  return detail::reduce_runs(all, ex_, [&](std::uint64_t f, std::uint64_t len) { return detail::norm_of_run(a, f, len); });
}

template <class Scalar>
double state_vector<Scalar>::probability(std::span<const control> condition) const {
  const auto cm = checks().probability(condition);
  const detail::subspace s(n_, cm.mask, cm.value);
  const Scalar* a = amps_.data();
  return detail::reduce_runs(s, ex_, [&](std::uint64_t f, std::uint64_t len) { return detail::norm_of_run(a, f, len); });
}

template <class Scalar>
std::vector<double> state_vector<Scalar>::distribution(std::span<const qubit_index> bits) const {
  checks().distribution(bits);
  std::vector<double> p(std::size_t{1} << bits.size(), 0.0);
  for (std::uint64_t v = 0; v < p.size(); ++v) {
    std::vector<control> cond;
    for (std::size_t i = 0; i < bits.size(); ++i) cond.push_back({bits[i], ((v >> i) & 1u) != 0});
    p[v] = probability(cond);
  }
  return p;
}

}  // namespace qrm
