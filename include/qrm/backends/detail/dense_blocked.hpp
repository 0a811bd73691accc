// qrm/backends/detail/dense_blocked.hpp: runs a list of ops one cache-sized chunk of the state at a time.
//
// A kernel makes one pass over the state per op, and a state larger than the cache makes each
// pass a trip to memory. But ops whose moving qubits (targets, added bits, select qubits; not
// controls) all lie in a set L of m qubits never mix amplitudes whose bits outside L differ: the
// state splits into 2^(n-m) chunks of 2^m amplitudes that evolve independently. So a run of such
// ops costs one trip: each chunk is brought into cache (in place when L is the lowest m qubits,
// else copied into a buffer in runs of the contiguous low qubits), every op of the run is
// applied to it with its qubits renumbered (a control outside L is a constant of the chunk: the op
// is skipped, or applied without that control), and the chunk is written back. Chunks are
// independent, so they are also the unit of parallel work.
//
// Runs are formed greedily: an op joins the current run while the union of the run's moving
// qubits stays within m, and an op further on may join it ahead of ops it commutes with (see
// group_runs in circuit/detail/runs.hpp). A run whose ops would make fewer than
// min_chunked_passes passes over memory (see memory_passes) is applied op by op as usual.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "../../circuit/detail/runs.hpp"
#include "../../circuit/program.hpp"
#include "../../support/detail/thread_pool.hpp"
#include "bits.hpp"
#include "dense_kernels.hpp"

namespace qrm::detail {

// Whether an op's kernel waits on memory, for matrices up to `widest_memory_bound` rows (see
// memory_bound_dim): every op but a matrix on more qubits, whose multiply-adds per amplitude
// outlast the trip to memory. Only such ops gain from a chunk; for the others its copy is cost.
template <int = 0>
bool memory_bound(const op::any& o, std::size_t widest_memory_bound) {
  if (const auto* u = std::get_if<op::unitary_op>(&o)) return u->matrix.dim <= widest_memory_bound;
  if (const auto* u = std::get_if<op::mux_unitary_op>(&o))
    return (std::size_t{1} << u->targets.size()) <= widest_memory_bound;
  return true;
}

// The widest matrix that still waits on memory for amplitudes of type S computed as `ex` says:
// a d x d real matrix costs d multiply-adds per amplitude component, so d * components * (bytes
// of the arithmetic's type) against the amplitude's bytes. 8x8 blocks wait on memory in
// complex<float> float arithmetic, complex<double> and double (one 16-lane or 8-lane FMA per 8
// bytes), not in complex<float> double arithmetic (two per 8 bytes, plus the widening): measured
// on the fused random suite (24 qubits) and decomposed walk (21 qubits), one thread, AMD EPYC
// VM, 2026-12-05, bench/RESULTS.md: chunking the 8x8 blocks took complex<float> float arithmetic
// from 0.57-0.68 s to 0.52 s and 0.144 s to 0.122-0.133 s, complex<double> from 1.47 s to
// 1.31-1.34 s and 0.34-0.39 s to 0.27-0.33 s, and complex<float> in double arithmetic from
// 0.72-0.74 s to 0.76-0.80 s (worse: left op by op).
template <class S>
constexpr std::size_t memory_bound_dim(const exec_policy& ex) {
  const std::size_t arithmetic_bytes = float_arithmetic<S>(ex) ? 4 : 8;
  const std::size_t components = scalar_traits<S>::is_complex ? 2 : 1;
  return 8 * sizeof(S) / (components * arithmetic_bytes);
}

// The passes over memory an op costs applied on its own: 0 for an arithmetic-bound op, else 1
// halved for each control on a qubit at or above `low` (below it, every line is read anyway).
template <int = 0>
double memory_passes(const op::any& o, unsigned low, std::size_t widest_memory_bound) {
  if (!memory_bound(o, widest_memory_bound)) return 0;
  double passes = 1;
  visit_op(o, [&](const auto& x) {
    for (const control& c : x.controls)
      if (c.qubit >= low) passes /= 2;
  });
  return passes;
}

// The runs of `ops` for chunks of m qubits in an n-qubit state (see the top of this header and
// group_runs). Every chunk holds the lowest `low` qubits, so a copied chunk moves runs of 2^low
// contiguous amplitudes (one amplitude at a time would cost more than the ops it saves). A run is
// chunked when its ops' memory_passes (matrices up to widest_memory_bound rows waiting on memory)
// add up to min_passes; its ops are otherwise applied one by one.
template <int>
run_plan plan_runs(std::span<const op::any> ops, unsigned n, unsigned m, unsigned low, double min_passes,
                   std::size_t widest_memory_bound) {
  run_plan plan = group_runs(ops, m, (std::uint64_t{1} << std::min(low, m)) - 1);
  std::vector<op_run> runs;
  runs.reserve(plan.runs.size());
  for (op_run r : plan.runs) {
    double passes = 0;
    for (std::size_t j = r.first; j < r.last; ++j) passes += memory_passes(ops[plan.order[j]], low, widest_memory_bound);
    if (r.local == 0 || passes < min_passes) {
      for (std::size_t j = r.first; j < r.last; ++j) runs.push_back({j, j + 1, 0});
      continue;
    }
    // Pad with the lowest free qubits: longer contiguous runs to copy, and in place when L = {0..m-1}.
    for (unsigned q = 0; q < n && std::popcount(r.local) < static_cast<int>(m); ++q) r.local |= std::uint64_t{1} << q;
    runs.push_back(r);
  }
  plan.runs = std::move(runs);
  return plan;
}

// A gate sink that only checks operands (op_checks), so ops are validated on the whole state
// before chunks apply them.
template <class Checks>
struct validating_sink {
  const Checks& checks;
  void apply_gate1(const gate1& g, qubit_index t, std::span<const control> cs) { checks.gate1(g, t, cs); }
  void apply_unitary(const dense_matrix& m, std::span<const qubit_index> ts, std::span<const control> cs) {
    checks.unitary(m, ts, cs);
  }
  void apply_add(std::int64_t, std::span<const qubit_index> bits, std::span<const control> cs) { checks.add(bits, cs); }
  void apply_mux1(std::span<const mux1_entry> e, qubit_index t, std::span<const qubit_index> sel,
                  std::span<const control> cs) {
    checks.mux1(e, t, sel, cs);
  }
  void apply_mux_unitary(std::span<const dense_matrix> ms, std::span<const mux_unitary_entry> e,
                         std::span<const qubit_index> ts, std::span<const qubit_index> sel, std::span<const control> cs) {
    checks.mux_unitary(ms, e, ts, sel, cs);
  }
};

// A gate sink on one chunk: 2^m amplitudes at `a`, qubit q of the state is bit local_of[q] of a
// chunk index (or outside the chunk, at its value in `base`). Ops come validated on the whole state.
template <class S>
struct chunk_sink {
  S* a;
  unsigned m;
  const std::array<signed char, 64>* local_of;
  std::uint64_t base;  // the chunk's bits outside L, at their positions in the state
  exec_policy ex;
  const unitary_plan<S>* plan = nullptr;  // the plan of the unitary op about to be emitted, if any

  unsigned local(qubit_index q) const { return static_cast<unsigned>((*local_of)[q]); }
  // Local masks of the controls; false if a control outside the chunk does not hold in it.
  bool condition(std::span<const control> cs, std::uint64_t& mask, std::uint64_t& value) const {
    mask = value = 0;
    for (const control& c : cs) {
      if ((*local_of)[c.qubit] < 0) {
        if (((base >> c.qubit) & 1u) != static_cast<std::uint64_t>(c.value)) return false;
        continue;
      }
      mask |= std::uint64_t{1} << local(c.qubit);
      if (c.value) value |= std::uint64_t{1} << local(c.qubit);
    }
    return true;
  }
  // Local positions of qs (order kept) in buf, and their mask.
  std::span<const qubit_index> renumber(std::span<const qubit_index> qs, std::array<qubit_index, 64>& buf,
                                        std::uint64_t& mask) const {
    mask = 0;
    for (std::size_t i = 0; i < qs.size(); ++i) {
      buf[i] = local(qs[i]);
      mask |= std::uint64_t{1} << buf[i];
    }
    return {buf.data(), qs.size()};
  }

  void apply_gate1(const gate1& g, qubit_index t, std::span<const control> cs) {
    std::uint64_t cm, cv;
    if (condition(cs, cm, cv)) kernel_gate1(a, m, g, local(t), cm, cv, ex);
  }
  void apply_unitary(const dense_matrix& mat, std::span<const qubit_index> targets, std::span<const control> cs) {
    std::uint64_t cm, cv, tm;
    std::array<qubit_index, 64> tb;
    if (!condition(cs, cm, cv)) return;
    const auto lt = renumber(targets, tb, tm);
    if (plan)
      apply_unitary_plan(a, m, *plan, tm, cm, cv, ex);
    else
      kernel_unitary(a, m, mat, lt, tm, cm, cv, ex);
  }
  void apply_add(std::int64_t constant, std::span<const qubit_index> bits, std::span<const control> cs) {
    std::uint64_t cm, cv, rm;
    std::array<qubit_index, 64> bb;
    if (bits.empty() || !condition(cs, cm, cv)) return;
    const auto lb = renumber(bits, bb, rm);
    kernel_add(a, m, constant, lb, rm, cm, cv, ex);
  }
  void apply_mux1(std::span<const mux1_entry> entries, qubit_index t, std::span<const qubit_index> select,
                  std::span<const control> cs) {
    std::uint64_t cm, cv, sm;
    std::array<qubit_index, 64> sb;
    if (!condition(cs, cm, cv)) return;
    const auto ls = renumber(select, sb, sm);
    kernel_mux1(a, m, entries, local(t), ls, sm, cm, cv, ex);
  }
  void apply_mux_unitary(std::span<const dense_matrix> matrices, std::span<const mux_unitary_entry> entries,
                         std::span<const qubit_index> targets, std::span<const qubit_index> select,
                         std::span<const control> cs) {
    std::uint64_t cm, cv, tm, sm;
    std::array<qubit_index, 64> tb, sb;
    if (!condition(cs, cm, cv)) return;
    const auto lt = renumber(targets, tb, tm);
    const auto ls = renumber(select, sb, sm);
    kernel_mux_unitary(a, m, matrices, entries, lt, tm, ls, sm, cm, cv, ex);
  }
};

// Copies `count` amplitudes in 128-byte pieces, each a memcpy of constant size (inlined as vector
// moves), when count fills whole pieces; std::copy_n called memmove once per copied run, and runs
// are often just 128 bytes (chunk_low_qubits): 38% of a chunked fused run's time went there.
template <class S>
inline void copy_run(const S* from, std::uint64_t count, S* to) {
  constexpr std::uint64_t piece = 128 / sizeof(S);
  if (count % piece != 0) {
    std::copy_n(from, count, to);
    return;
  }
  for (std::uint64_t i = 0; i < count; i += piece) std::memcpy(static_cast<void*>(to + i), from + i, 128);
}

// The copied runs lie 2^q apart for the chunk's upper qubits q, a pattern the hardware prefetcher
// does not follow: fetch the run `copy_ahead` places on.
inline constexpr std::uint64_t copy_ahead = 16;
template <class S>
inline void prefetch_lines(const S* p, std::uint64_t count, bool for_write) {
  const char* c = reinterpret_cast<const char*>(p);
  for (std::uint64_t b = 0; b < count * sizeof(S); b += 64) {
    if (for_write)
      __builtin_prefetch(c + b, 1);
    else
      __builtin_prefetch(c + b, 0);
  }
}

// Chunks whose bases differ only in the outside qubits just above the chunk's contiguous low
// qubits lie side by side in memory: up to grouped_run_bytes of them are copied together, so a
// copied run of 128 bytes becomes one of 512. Each run is a separate trip to DRAM: copying every
// chunk of a 2^24-amplitude complex<double> state in and out in runs 2^21 amplitudes apart took
// 50-68 ms in runs of 128 bytes, 42-45 ms grouped to 512, 23-33 ms in runs of 2 KiB; grouping
// further (8 chunks and more in flight) overflowed the 1 MiB L2 and was slower (AMD EPYC VM,
// 2026-12-07).
inline constexpr std::uint64_t grouped_run_bytes = 512;

// Applies ops[which[0]], ops[which[1]], ... (validated) chunk by chunk over the qubits of `local`
// (m of the state's n).
template <class S>
void run_in_chunks(S* a, unsigned n, std::span<const op::any> ops, std::span<const std::size_t> which,
                   std::uint64_t local, const exec_policy& ex) {
  const unsigned m = static_cast<unsigned>(std::popcount(local));
  std::array<signed char, 64> local_of;
  local_of.fill(-1);
  std::vector<qubit_index> inside, outside;
  for (unsigned q = 0; q < n; ++q) {
    if ((local >> q) & 1u) {
      local_of[q] = static_cast<signed char>(inside.size());
      inside.push_back(q);
    } else {
      outside.push_back(q);
    }
  }
  const unsigned low = static_cast<unsigned>(std::countr_one(local));  // contiguous lowest qubits of L
  const bool in_place = low == m;
  const std::uint64_t run_len = std::uint64_t{1} << low, runs = std::uint64_t{1} << (m - low);
  const std::span<const qubit_index> upper(inside.data() + low, inside.size() - low);
  std::vector<std::uint64_t> run_offset(static_cast<std::size_t>(runs));  // state offset of each copied run
  if (!in_place)
    for (std::uint64_t r = 0; r < runs; ++r) run_offset[r] = deposit(r, upper);
  exec_policy one = ex;
  one.threads = 1;
  // Every chunk applies a matrix with the same local targets and controls: plan each once (see
  // unitary_plan).
  std::vector<unitary_plan<S>> plans;
  std::vector<const unitary_plan<S>*> plan_of(which.size(), nullptr);
  for (const std::size_t i : which)
    if (const auto* u = std::get_if<op::unitary_op>(&ops[i])) {
      std::array<qubit_index, 64> lt;
      for (std::size_t j = 0; j < u->targets.size(); ++j) lt[j] = static_cast<qubit_index>(local_of[u->targets[j]]);
      std::uint64_t cmask = 0;  // of the controls inside the chunk (the others select chunks)
      for (const control& c : u->controls)
        if (local_of[c.qubit] >= 0) cmask |= std::uint64_t{1} << local_of[c.qubit];
      plans.emplace_back(u->matrix, std::span<const qubit_index>(lt.data(), u->targets.size()), cmask, one);
    }
  for (std::size_t j = 0, next = 0; j < which.size(); ++j)
    if (std::holds_alternative<op::unitary_op>(ops[which[j]])) plan_of[j] = &plans[next++];
  // 2^g chunks side by side are copied together (see grouped_run_bytes), each to its own buffer,
  // leaving at least 4 groups per thread.
  unsigned g = 0;
  if (!in_place)
    while ((run_len << g) * sizeof(S) < grouped_run_bytes && low + g < n && ((local >> (low + g)) & 1u) == 0 &&
           (std::uint64_t{1} << (n - m - g - 1)) >= 4 * std::max(ex.threads, 1u))
      ++g;
  const std::uint64_t group = std::uint64_t{1} << g, groups = std::uint64_t{1} << (n - m - g);
  const std::uint64_t chunk_len = std::uint64_t{1} << m;
  auto do_group = [&](std::uint64_t c) {
    const std::uint64_t base = deposit(c << g, outside);
    thread_local std::vector<S> buffer;
    S* chunk = a + base;
    if (!in_place) {
      if (buffer.size() < group * chunk_len) buffer.resize(static_cast<std::size_t>(group * chunk_len));
      chunk = buffer.data();
      for (std::uint64_t r = 0; r < runs; ++r) {
        if (r + copy_ahead < runs) prefetch_lines(a + base + run_offset[r + copy_ahead], run_len << g, false);
        const S* from = a + base + run_offset[r];
        for (std::uint64_t k = 0; k < group; ++k) copy_run(from + (k << low), run_len, chunk + k * chunk_len + (r << low));
      }
    }
    for (std::uint64_t k = 0; k < group; ++k) {
      chunk_sink<S> sink{chunk + k * chunk_len, m, &local_of, base + (k << low), one};
      for (std::size_t j = 0; j < which.size(); ++j) {
        sink.plan = plan_of[j];
        emit_op(ops[which[j]], sink);
      }
    }
    if (!in_place)
      for (std::uint64_t r = 0; r < runs; ++r) {
        if (r + copy_ahead < runs) prefetch_lines(a + base + run_offset[r + copy_ahead], run_len << g, true);
        S* to = a + base + run_offset[r];
        for (std::uint64_t k = 0; k < group; ++k) copy_run(chunk + k * chunk_len + (r << low), run_len, to + (k << low));
      }
  };
  if (ex.threads <= 1 || groups < 2) {
    for (std::uint64_t c = 0; c < groups; ++c) do_group(c);
    return;
  }
  shared_pool().parallel_for(static_cast<std::size_t>(groups), ex.threads,
                             [&](std::size_t c) { do_group(static_cast<std::uint64_t>(c)); });
}

}  // namespace qrm::detail
