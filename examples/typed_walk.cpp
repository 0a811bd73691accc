// typed_walk: the paper's 8x8 A operator with compile-time register widths, run on both
// backends and checked against the dynamic-width circuit `qrm lightmap` runs for the same cell.
// Built and run as a test (ctest -R typed_walk); includes only the layers it uses.
#include <cmath>
#include <cstdio>
#include <span>

#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/paper_scenes.hpp>

// 2D, 3 position bits per axis (8x8 cells), 3 direction bits (8 directions), s = 3 steps.
using A = qrm::ray_marching_circuit<2, 3, 3, 3>;

// Width, known at compile time: out + steps (2) + Le (3) + rho (2) + dir (3) + x (3) + y (3).
static_assert(A::width == 17);
// The unpruned depth bound O(s (p^2 + d)) of the paper's Section 6, also a constant.
static_assert(A::depth_bound == 633);
// Registers are types; where each sits is a constant too.
static_assert(A::layout_type::offset<qrm::walk_registers::out> == 0);
static_assert(A::layout_type::offset<qrm::walk_registers::x<3>> == 11);

template <class Backend>
double probability_out(const A& a) {
  Backend state(A::width);
  qrm::run(state, a);
  const qrm::control out{a.out_qubit(), true};
  return state.probability(std::span<const qrm::control>(&out, 1));
}

int main() {
  const qrm::walk_model model(qrm::paper_8x8(), qrm::king_2d());
  const qrm::walk_start start = model.light_map_start({2, 5, 0});  // an air cell: all 8 directions
  int failures = 0;
  for (qrm::pruning prune : {qrm::pruning::none, qrm::pruning::reachable}) {
    const A a(model, start, /*channel=*/0, prune);
    const double dense = probability_out<qrm::state_vector<double>>(a);
    const double compact = probability_out<qrm::compact_state<double>>(a);

    // What `qrm lightmap --exact` runs (its default backend, compact, real amplitudes for a real
    // circuit): the same gate templates on a layout whose widths come from the scene, recorded into
    // a program. make_walk_program<2> is make_walk_program for a scene known to be 2D.
    qrm::walk_options o;
    o.steps = 3;
    o.prune = prune;
    const qrm::walk_program w = qrm::make_walk_program<2>(model, start, o);
    qrm::compact_state<double> state(w.circuit.width());
    qrm::run(state, w.circuit);
    const qrm::control out{w.out, true};
    const double cli = state.probability(std::span<const qrm::control>(&out, 1));

    const bool ok = std::abs(dense - cli) <= 1e-15 && std::abs(compact - cli) <= 1e-15;
    std::printf("pruning %-9s  P(out=1): static dense %.17g, static compact %.17g, dynamic (CLI) %.17g  %s\n",
                qrm::pruning_name(prune), dense, compact, cli, ok ? "ok" : "MISMATCH");
    failures += ok ? 0 : 1;
  }
  return failures;
}
