// The kernel test bodies: every primitive operation, at every placement of targets, select
// qubits and controls (with every control value) on small states, against the naive reference
// simulator. test_kernels_dense.cpp and test_kernels_compact.cpp run them on each backend
// (two translation units, so each compiles in half the time and both build in parallel).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <vector>

#include "support/backends.hpp"
#include "support/random_ops.hpp"
#include "support/reference.hpp"

using namespace qrm_test;
using qrm::control;
using qrm::qubit_index;

namespace {

// Every ordered tuple of `k` distinct qubits out of `pool`.
void for_each_tuple(const std::vector<qubit_index>& pool, std::size_t k,
                    const std::function<void(const std::vector<qubit_index>&)>& f) {
  std::vector<qubit_index> cur;
  std::vector<bool> used(pool.size(), false);
  std::function<void()> rec = [&] {
    if (cur.size() == k) {
      f(cur);
      return;
    }
    for (std::size_t i = 0; i < pool.size(); ++i) {
      if (used[i]) continue;
      used[i] = true;
      cur.push_back(pool[i]);
      rec();
      cur.pop_back();
      used[i] = false;
    }
  };
  rec();
}

// Every set of controls on qubits of `pool`: each qubit absent, controlled on 0 or on 1.
void for_each_control_set(const std::vector<qubit_index>& pool, const std::function<void(const std::vector<control>&)>& f) {
  std::size_t total = 1;
  for (std::size_t i = 0; i < pool.size(); ++i) total *= 3;
  for (std::size_t code = 0; code < total; ++code) {
    std::vector<control> cs;
    std::size_t c = code;
    for (qubit_index q : pool) {
      const std::size_t d = c % 3;
      c /= 3;
      if (d != 0) cs.push_back({q, d == 2});
    }
    f(cs);
  }
}

std::vector<qubit_index> all_but(std::size_t n, const std::vector<qubit_index>& used) {
  std::vector<qubit_index> r;
  for (qubit_index q = 0; q < n; ++q)
    if (std::find(used.begin(), used.end(), q) == used.end()) r.push_back(q);
  return r;
}

// Runs `apply` on a backend and on the reference from the same random state; returns the
// largest amplitude difference.
template <class B, class Apply>
double compare_with_reference(std::size_t n, qrm::rng& g, Apply apply, unsigned threads = 1) {
  using T = backend_traits<B>;
  B b = T::make(n, threads);
  T::load(b, random_state(n, g, T::is_complex));
  reference_state ref(n);
  ref.amp = T::dump(b);  // the start as the backend holds it (rounded to float if need be)
  apply(ref);
  apply(b);
  return max_diff(ref.amp, T::dump(b));
}

}  // namespace

TEST_CASE_TEMPLATE_DEFINE("single-qubit gates match the reference at every placement", B, gate1_placements) {
  using T = backend_traits<B>;
  qrm::rng g(11);
  const std::size_t n = 4;
  std::vector<qrm::gate1> gates = {qrm::gate::x(), qrm::gate::z(), qrm::gate::h(), qrm::gate::ry(0.7),
                                   // diagonal with both entries != 1 (both halves scaled)
                                   qrm::gate::u(-0.5, 0, 0, 2.0), random_gate1_nonunitary(g, false)};
  if constexpr (T::is_complex) {
    gates.push_back(qrm::gate::y());
    gates.push_back(qrm::gate::phase(0.3));
    gates.push_back(qrm::gate::rz(1.1));
    gates.push_back(random_gate1_nonunitary(g, true));
  }
  std::size_t cases = 0;
  for (qubit_index t = 0; t < n; ++t)
    for_each_control_set(all_but(n, {t}), [&](const std::vector<control>& cs) {
      for (const auto& gate : gates) {
        const double d = compare_with_reference<B>(n, g, [&](auto& s) { s.apply_gate1(gate, t, cs); });
        INFO("kind " << qrm::gate1_name(gate.kind) << " target " << t << " controls " << cs.size());
        CHECK(d <= T::tolerance);
        ++cases;
      }
    });
  CHECK(cases == 4 * 27 * gates.size());
}

TEST_CASE_TEMPLATE_DEFINE("dense k-qubit matrices match the reference at every placement", B, unitary_placements) {
  using T = backend_traits<B>;
  qrm::rng g(12);
  const std::size_t n = 5;
  for (std::size_t k = 1; k <= 3; ++k) {
    std::vector<qrm::dense_matrix> ms = {random_matrix(k, g, false), random_unitary(k, g, false)};
    ms[1](0, 0) = 0;  // a zero entry, so sparse rows are exercised
    if constexpr (T::is_complex) ms.push_back(random_matrix(k, g, true));
    std::vector<qubit_index> pool(n);
    std::iota(pool.begin(), pool.end(), 0u);
    for_each_tuple(pool, k, [&](const std::vector<qubit_index>& ts) {
      for_each_control_set(all_but(n, ts), [&](const std::vector<control>& cs) {
        for (const auto& m : ms) {
          const double d = compare_with_reference<B>(n, g, [&](auto& s) { s.apply_unitary(m, ts, cs); });
          INFO("k " << k << " first target " << ts[0] << " controls " << cs.size());
          CHECK(d <= T::tolerance * 4);
        }
      });
    });
  }
}

TEST_CASE_TEMPLATE_DEFINE("add-a-constant matches the reference at every placement", B, add_placements) {
  qrm::rng g(13);
  const std::size_t n = 5;
  std::vector<qubit_index> pool(n);
  std::iota(pool.begin(), pool.end(), 0u);
  for (std::size_t k = 1; k <= 3; ++k)
    for_each_tuple(pool, k, [&](const std::vector<qubit_index>& bits) {
      for_each_control_set(all_but(n, bits), [&](const std::vector<control>& cs) {
        const std::int64_t lim = std::int64_t{1} << k;
        for (std::int64_t c = -lim + 1; c < lim; ++c) {
          const double d = compare_with_reference<B>(n, g, [&](auto& s) { s.apply_add(c, bits, cs); });
          INFO("k " << k << " constant " << c << " controls " << cs.size());
          CHECK(d == 0.0);  // a permutation moves amplitudes without arithmetic
        }
      });
    });
}

TEST_CASE_TEMPLATE_DEFINE("multiplexed gates match the reference at every placement, both strategies", B,
                          mux_placements) {
  using T = backend_traits<B>;
  qrm::rng g(14);
  const std::size_t n = 5;
  std::vector<qubit_index> pool(n);
  std::iota(pool.begin(), pool.end(), 0u);
  for (qrm::mux_strategy strategy : {qrm::mux_strategy::per_entry, qrm::mux_strategy::sweep}) {
    auto make = [&](std::size_t qubits) { return T::make(qubits, 1, strategy); };
    for (qubit_index t = 0; t < n; ++t)
      for (std::size_t m = 1; m <= 2; ++m)
        for_each_tuple(all_but(n, {t}), m, [&](const std::vector<qubit_index>& sel) {
          std::vector<qubit_index> used = sel;
          used.push_back(t);
          for_each_control_set(all_but(n, used), [&](const std::vector<control>& cs) {
            // A random subset of select values, each with its own non-unitary matrix.
            std::vector<qrm::mux1_entry> es;
            for (std::uint64_t v = 0; v < (std::uint64_t{1} << m); ++v)
              if (g.uniform() < 0.7) es.push_back({v, random_gate1_nonunitary(g, T::is_complex)});
            B b = make(n);
            T::load(b, random_state(n, g, T::is_complex));
            reference_state ref(n);
            ref.amp = T::dump(b);
            ref.apply_mux1(es, t, sel, cs);
            b.apply_mux1(es, t, sel, cs);
            CHECK(max_diff(ref.amp, T::dump(b)) <= T::tolerance);
          });
        });
    // Multiplexed k-qubit matrices: targets of 1-2 qubits, select of 1-2 qubits, controls.
    for (std::size_t k = 1; k <= 2; ++k)
      for_each_tuple(pool, k, [&](const std::vector<qubit_index>& ts) {
        for_each_tuple(all_but(n, ts), 1 + (ts[0] % 2), [&](const std::vector<qubit_index>& sel) {
          std::vector<qubit_index> used = ts;
          used.insert(used.end(), sel.begin(), sel.end());
          for_each_control_set(all_but(n, used), [&](const std::vector<control>& cs) {
            std::vector<qrm::dense_matrix> ms = {random_matrix(k, g, T::is_complex), random_matrix(k, g, false)};
            std::vector<qrm::mux_unitary_entry> es;
            for (std::uint64_t v = 0; v < (std::uint64_t{1} << sel.size()); ++v)
              if (g.uniform() < 0.7) es.push_back({v, static_cast<std::uint32_t>(g.below(2))});
            B b = make(n);
            T::load(b, random_state(n, g, T::is_complex));
            reference_state ref(n);
            ref.amp = T::dump(b);
            ref.apply_mux_unitary(ms, es, ts, sel, cs);
            b.apply_mux_unitary(ms, es, ts, sel, cs);
            CHECK(max_diff(ref.amp, T::dump(b)) <= T::tolerance * 4);
          });
        });
      });
  }
}

TEST_CASE_TEMPLATE_DEFINE("norm stays 1 over 10^5 random unitary gates", B, norm_drift) {
  using T = backend_traits<B>;
  qrm::rng g(15);
  const std::size_t n = 8;
  B b = T::make(n);
  std::vector<qrm::gate1> pool;
  std::vector<qrm::dense_matrix> two;
  for (int i = 0; i < 16; ++i) pool.push_back(random_gate1_unitary(g, T::is_complex));
  for (int i = 0; i < 4; ++i) two.push_back(random_unitary(2, g, T::is_complex));
  for (int i = 0; i < 100000; ++i) {
    const auto t = static_cast<qubit_index>(g.below(n));
    switch (g.below(4)) {
      case 0: b.apply_gate1(pool[g.below(pool.size())], t, {}); break;
      case 1: {
        const auto c = static_cast<qubit_index>((t + 1 + g.below(n - 1)) % n);
        const std::vector<control> cs = {{c, g.below(2) == 1}};
        b.apply_gate1(pool[g.below(pool.size())], t, cs);
        break;
      }
      case 2: {
        const std::vector<qubit_index> ts = {t, static_cast<qubit_index>((t + 1 + g.below(n - 1)) % n)};
        b.apply_unitary(two[g.below(two.size())], ts, {});
        break;
      }
      default: {
        const std::vector<qubit_index> bits = {t, static_cast<qubit_index>((t + 1) % n)};
        b.apply_add(static_cast<std::int64_t>(g.below(3)) + 1, bits, {});
      }
    }
  }
  // Each gate rounds every amplitude once (relative eps: 1.1e-16 double, 6e-8 float); errors
  // add up like a random walk plus a small bias, ~sqrt(1e5) * eps * a few: about 1e-13 for
  // double and 1e-5 for float. The bars leave a factor ~100 / ~10 of room.
  const double drift = std::abs(b.norm_squared() - 1.0);
  const double bar = std::is_same_v<typename B::real_type, double> ? 1e-10 : 1e-4;
  MESSAGE(std::string(T::name()) << " norm drift after 1e5 gates: " << drift);
  CHECK(drift <= bar);
}

TEST_CASE_TEMPLATE_DEFINE("threads do not change a single bit of the result", B, thread_determinism) {
  using T = backend_traits<B>;
  const std::size_t n = 16;  // 2^15 pairs: several chunks, so the pool really splits the work
  qrm::rng g(16);
  qrm::program p(n);
  for (int i = 0; i < 60; ++i) {
    const auto t = static_cast<qubit_index>(g.below(n));
    const auto c = static_cast<qubit_index>((t + 1 + g.below(n - 1)) % n);
    switch (g.below(4)) {
      case 0: p.apply_gate1(random_gate1_unitary(g, T::is_complex), t, {}); break;
      case 1: {
        const std::vector<control> cs = {{c, true}};
        p.apply_gate1(random_gate1_unitary(g, T::is_complex), t, cs);
        break;
      }
      case 2: {
        const std::vector<qubit_index> ts = {t, c};
        p.apply_unitary(random_unitary(2, g, T::is_complex), ts, {});
        break;
      }
      default: {
        const std::vector<qubit_index> sel = {c};
        const std::vector<qrm::mux1_entry> es = {{1, qrm::gate::ry(g.uniform())}};
        p.apply_mux1(es, t, sel, {});
      }
    }
  }
  B a = T::make(n, 1), b = T::make(n, 2);
  b.set_min_parallel(1);  // force the pool even on this small state
  qrm::run(a, p);
  qrm::run(b, p);
  CHECK(T::dump(a) == T::dump(b));
  CHECK(a.norm_squared() == b.norm_squared());
}

// Kernels walk a subspace run by run, each run's first index stepped from the previous one; a
// parallel chunk starts the stepping in the middle of the subspace. Chunks exist only above 2^13
// members, so this runs at n = 17 with the pool forced on, where the exhaustive n = 4 placement
// tests never reach, with controls scattered low and high (runs of 1, 2 and 8 amplitudes).
TEST_CASE_TEMPLATE_DEFINE("chunked walks of scattered subspaces match the reference", B, chunked_subspaces) {
  using T = backend_traits<B>;
  const std::size_t n = 17;
  qrm::rng g(17);
  const std::vector<std::vector<control>> control_sets = {
      {{0, true}},                                  // runs of one amplitude
      {{0, true}, {2, false}, {5, true}},           // runs of one, gaps of different sizes
      {{1, false}, {9, true}},                      // runs of two
      {{3, true}, {4, true}, {12, false}},          // runs of eight
  };
  for (const auto& cs : control_sets)
    for (const qubit_index t : {qubit_index{6}, qubit_index{16}}) {
      for (const unsigned threads : {1u, 2u}) {
        INFO("target " << t << " controls " << cs.size() << " threads " << threads);
        const double dx = compare_with_reference<B>(n, g, [&](auto& s) {
          if constexpr (requires { s.set_min_parallel(1); }) s.set_min_parallel(1);
          s.apply_gate1(qrm::gate::x(), t, cs);
        }, threads);
        CHECK(dx == 0.0);  // a permutation moves amplitudes without arithmetic
        const double dr = compare_with_reference<B>(n, g, [&](auto& s) {
          if constexpr (requires { s.set_min_parallel(1); }) s.set_min_parallel(1);
          s.apply_gate1(qrm::gate::ry(0.9), t, cs);
        }, threads);
        CHECK(dr <= T::tolerance);
      }
    }
}

