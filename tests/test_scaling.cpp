// Width and depth of the A operator against formulas derived by hand from the construction
// (walk.hpp), pruning never adding anything, and the OpenQASM 3 round trip of the paper's 8x8
// circuit simulated gate by gate.
//
// The formulas here are written independently of qrm/walk/cost.hpp (which states the same ones for
// the report): both must agree with what qrm::circuit_metrics_of counts on the built circuits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/circuit/qasm.hpp>
#include <qrm/walk/cost.hpp>
#include "scaling_study.hpp"  // examples/qrm: the study's sweep points

namespace {

using qrm::pruning;
using qrm::walk_variant;

// Smallest b >= 1 with 2^b >= n: the qubits of a register holding 0..n-1.
std::size_t register_bits(std::size_t n) {
  std::size_t b = 1;
  while ((std::size_t{1} << b) < n) ++b;
  return b;
}

// The width by counting registers (walk.hpp's register list): out, steps, Le_0..Le_{s-1},
// rho_0..rho_{s-2}, history copies of the direction after every step but the last, the direction,
// and dims axes of log2 p integer and F fractional bits.
std::size_t width_by_hand(unsigned dims, unsigned p, unsigned fractional, std::size_t directions, unsigned s,
                          bool history) {
  const std::size_t position_bits = static_cast<std::size_t>(std::log2(p) + 0.5);
  const std::size_t D = register_bits(directions);
  std::size_t w = 1;              // out
  w += register_bits(s);          // steps register, holds 0..s-1
  w += s;                         // Le_i
  w += s - 1;                     // rho_i, none after the last step
  if (history) w += (s - 1) * D;  // a direction copy after each step but the last
  w += D;                         // direction
  w += dims * (position_bits + fractional);
  return w;
}

// Layers of the Ry cascade preparing a uniform superposition over n values on register_bits(n)
// qubits, counted by enumeration: one Ry on the top qubit, then for each lower qubit i one
// multiplexer entry per prefix q whose block [q 2^(i+1), (q+1) 2^(i+1)) has values with bit i set.
std::size_t cascade_layers(std::size_t n) {
  if (n < 2) return 0;
  const std::size_t k = register_bits(n);
  std::size_t layers = 1;
  for (std::size_t i = 0; i + 1 < k; ++i)
    for (std::size_t q = 0; q < (std::size_t{1} << (k - 1 - i)); ++q)
      if (q * (std::size_t{2} << i) + (std::size_t{1} << i) < n) ++layers;
  return layers;
}

// (direction, axis) pairs with a nonzero displacement, read from the direction set.
std::size_t adds_per_shift(const qrm::direction_set& dirs) {
  std::size_t a = 0;
  for (const auto& d : dirs.displacement)
    for (unsigned axis = 0; axis < dirs.dims; ++axis)
      if (d[axis] != 0) ++a;
  return a;
}

// The unpruned circuit's logical depth, derived from walk.hpp's emit order and qrm::circuit_metrics_of's
// rules (ASAP; a multiplexer is one layer per entry; a multi-controlled gate one layer):
//  - init: X on the start voxel's set bits and on the start direction's set bits, one parallel
//    layer each, or H on all direction qubits (d a power of two), or the Ry cascade; the first
//    coin reads the voxel bits and the direction, so it starts after the longer of the two.
//  - per step: coin p^dims layers (direction + voxel bits), [1 layer of history CNOTs on the
//    direction qubits, all steps but the last], a adds (all controlled by the whole direction,
//    so in sequence), Le p^dims layers and rho p^dims layers (voxel bits), no rho in the last
//    step. Each part shares qubits with the one before, so their layers add up.
//  - path: its steps-register preparation runs alongside the walk (fresh qubits); term i waits
//    for Le_i, and the last term for the last Le layer, which ends the walk: + 1.
std::size_t depth_by_hand(const qrm::walk_model& m, const qrm::walk_start& start, unsigned s, bool history) {
  const std::size_t d = m.direction_count();
  std::size_t direction_layers = 0;
  if (start.direction >= 0)
    direction_layers = start.direction != 0 ? 1 : 0;
  else if (d == (std::size_t{1} << register_bits(d)))
    direction_layers = 1;
  else
    direction_layers = cascade_layers(d);
  const bool voxel_bits = start.voxel[0] + start.voxel[1] + start.voxel[2] != 0;
  const std::size_t init = std::max<std::size_t>(voxel_bits ? 1 : 0, direction_layers);
  const std::size_t cells = m.scene_data().voxel_count(), a = adds_per_shift(m.directions());
  std::size_t depth = init;
  for (unsigned i = 0; i < s; ++i) {
    depth += cells;                        // coin
    if (history && i + 1 < s) depth += 1;  // direction copy
    depth += a;                            // shift
    depth += cells;                        // Le_i
    if (i + 1 < s) depth += cells;         // rho_i
  }
  return depth + 1;  // the last path term
}

qrm::walk_program build(const qrm::walk_model& m, const qrm::walk_start& start, unsigned s, walk_variant v, pruning p) {
  qrm::walk_options o;
  o.steps = s;
  o.variant = v;
  o.prune = p;
  return qrm::make_walk_program(m, start, o);
}

// Starts that exercise every init case: a surface cell (one direction, maybe 0), an air cell
// (all directions), and the origin with direction 0 (no init gate at all).
std::vector<qrm::walk_start> starts_of(const qrm::walk_model& m) {
  const unsigned p = m.scene_data().size();
  std::vector<qrm::walk_start> out;
  if (m.dims() == 2) {
    out.push_back(m.light_map_start({p / 2 - 1, 2, 0}));
    out.push_back(m.light_map_start({0, p / 2, 0}));
    out.push_back(m.light_map_start({p - 1, p - 1, 0}));
  } else {
    out.push_back(m.light_map_start({p / 2, p / 2, p / 2}));
    out.push_back(m.light_map_start({p / 2, p - 4, p / 2}));
    out.push_back(m.light_map_start({2, 3, 2}));
  }
  qrm::walk_start origin;
  origin.direction = 0;
  out.push_back(origin);
  qrm::walk_start origin_all;  // all directions from voxel 0
  out.push_back(origin_all);
  return out;
}

}  // namespace

TEST_CASE("hand-counted constants: the paper's 8x8 circuit and the uniform preparations") {
  // Paper 8x8, s = 3: out 1 + steps 2 + Le 3 + rho 2 + direction 3 + x 3 + y 3 = 17 qubits;
  // the history variant adds 2 copies of the 3 direction qubits: 23.
  CHECK(width_by_hand(2, 8, 0, 8, 3, false) == 17);
  CHECK(width_by_hand(2, 8, 0, 8, 3, true) == 23);
  // Depth from air cell (1, 1): init 1 (H on the directions; x = y = 1 set), 3 coins of 64,
  // 3 shifts of 12 adds (4 axis moves + 4 diagonals x 2 axes), 3 Le and 2 rho layers of 64, and
  // the last path term: 1 + 3*64 + 36 + 5*64 + 1 = 550; the history copies add 2.
  const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  CHECK(adds_per_shift(m.directions()) == 12);
  CHECK(depth_by_hand(m, m.light_map_start({1, 1, 0}), 3, false) == 550);
  CHECK(depth_by_hand(m, m.light_map_start({1, 1, 0}), 3, true) == 552);
  // 15 directions on 4 qubits: 1 + 7 + 4 + 2 = 14 layers; 3 values on 2 qubits: 1 + 1.
  CHECK(cascade_layers(15) == 14);
  CHECK(cascade_layers(3) == 2);
  CHECK(cascade_layers(6) == 1 + 3 + 1);
  for (std::size_t n = 1; n <= 300; ++n) CHECK(qrm::uniform_preparation_depth(n) == cascade_layers(n));
}

TEST_CASE("width: the register count, the library's formula and the built circuits agree") {
  std::size_t checked = 0;
  for (unsigned dims : {2u, 3u}) {
    const std::vector<unsigned> sizes = dims == 2 ? std::vector<unsigned>{4, 8, 16, 32} : std::vector<unsigned>{8, 16};
    const std::vector<std::size_t> direction_counts =
        dims == 2 ? std::vector<std::size_t>{8} : std::vector<std::size_t>{6, 14, 15, 26, 32};
    for (unsigned p : sizes)
      for (std::size_t d : direction_counts) {
        const qrm::walk_model m = qrm::scaling_model(dims, p, d);
        const unsigned fractional = dims == 3 ? 3 : 0;
        const qrm::walk_start start = qrm::scaling_start_of(m, qrm::scaling_start::near_light);
        const unsigned max_steps = dims == 2 ? 8 : (p == 8 ? 4 : 2);
        for (bool history : {false, true})
          for (unsigned s = 1; s <= max_steps; ++s) {
            const walk_variant v = history ? walk_variant::history : walk_variant::faithful;
            const std::size_t want = width_by_hand(dims, p, fractional, d, s, history);
            CAPTURE(dims);
            CAPTURE(p);
            CAPTURE(d);
            CAPTURE(s);
            CAPTURE(history);
            CHECK(qrm::walk_width_formula(dims, m.position_bits(), m.fractional_bits(), m.direction_bits(), s, v) ==
                  want);
            const auto full = build(m, start, s, v, pruning::none);
            CHECK(full.circuit.width() == want);
            CHECK(full.full_width == want);
            // One more step: Le_s and rho_{s-1}, one more steps-register qubit when s + 1 needs
            // it, and one more direction copy in the history variant.
            if (s + 1 <= max_steps) {
              const std::size_t grows = register_bits(s + 1) - register_bits(s);
              CHECK(width_by_hand(dims, p, fractional, d, s + 1, history) - want ==
                    2 + grows + (history ? register_bits(d) : 0));
            }
            for (pruning pr : {pruning::scene, pruning::reachable}) {
              const auto pruned = build(m, start, s, v, pr);
              CHECK(pruned.circuit.width() <= want);
              CHECK(pruned.full_width == want);
            }
            ++checked;
          }
      }
  }
  MESSAGE(checked << " (dims, p, d, s, variant) points");
}

TEST_CASE("the typed circuit's constexpr width is the register count") {
  static_assert(qrm::ray_marching_circuit<2, 3, 3, 3>::width == 17);
  static_assert(qrm::ray_marching_circuit<2, 3, 3, 3, walk_variant::history>::width == 23);
  CHECK(qrm::ray_marching_circuit<2, 5, 3, 7>::width == width_by_hand(2, 32, 0, 8, 7, false));
  CHECK(qrm::ray_marching_circuit<3, 4, 4, 5, walk_variant::history, 3>::width == width_by_hand(3, 16, 3, 15, 5, true));
  CHECK(qrm::ray_marching_circuit<3, 3, 5, 1, walk_variant::faithful, 3>::width ==
        width_by_hand(3, 8, 3, 32, 1, false));
}

TEST_CASE("unpruned depth equals the closed form derived from the construction") {
  std::size_t checked = 0;
  for (unsigned dims : {2u, 3u}) {
    const std::vector<unsigned> sizes = dims == 2 ? std::vector<unsigned>{4, 8, 16, 32} : std::vector<unsigned>{8, 16};
    const std::vector<std::size_t> direction_counts =
        dims == 2 ? std::vector<std::size_t>{8} : std::vector<std::size_t>{6, 14, 15, 26, 32};
    for (unsigned p : sizes)
      for (std::size_t d : direction_counts) {
        const qrm::walk_model m = qrm::scaling_model(dims, p, d);
        const unsigned max_steps = dims == 2 ? 6 : (p == 8 ? 3 : 2);
        for (const qrm::walk_start& start : starts_of(m))
          for (bool history : {false, true})
            for (unsigned s = 1; s <= max_steps; ++s) {
              const walk_variant v = history ? walk_variant::history : walk_variant::faithful;
              const auto w = build(m, start, s, v, pruning::none);
              const qrm::circuit_metrics got = qrm::circuit_metrics_of(w.circuit);
              CAPTURE(dims);
              CAPTURE(p);
              CAPTURE(d);
              CAPTURE(s);
              CAPTURE(history);
              CAPTURE(start.direction);
              const std::size_t want = depth_by_hand(m, start, s, history);
              CHECK(got.logical_depth == want);
              CHECK(qrm::unpruned_walk_depth(m, start, s, v) == want);
              // Each layer on its own: coin s p^dims, samples (2s - 1) p^dims, shift s a,
              // history s - 1, and every gate belongs to exactly one layer.
              const qrm::walk_layer_metrics layers = qrm::walk_layers(w.circuit);
              const std::size_t cells = m.scene_data().voxel_count();
              CHECK(layers[qrm::walk_layer::coin] == s * cells);
              CHECK(layers[qrm::walk_layer::sample] == (2 * s - 1) * cells);
              CHECK(layers[qrm::walk_layer::shift] == s * adds_per_shift(m.directions()));
              CHECK(layers[qrm::walk_layer::history] == (history ? s - 1 : 0));
              std::size_t gates = 0;
              for (std::size_t g : layers.gates) gates += g;
              CHECK(gates == got.gate_count);
              ++checked;
            }
      }
  }
  MESSAGE(checked << " unpruned circuits");
}

TEST_CASE("pruning never adds qubits, layers or gates; reachable prunes at least as much as scene") {
  for (unsigned dims : {2u, 3u})
    for (unsigned p : dims == 2 ? std::vector<unsigned>{4, 8, 16} : std::vector<unsigned>{8, 16}) {
      const qrm::walk_model m = qrm::scaling_model(dims, p, dims == 2 ? 8 : 15);
      for (const qrm::walk_start& start : starts_of(m))
        for (walk_variant v : {walk_variant::faithful, walk_variant::history})
          for (unsigned s = 1; s <= (dims == 2 ? 5u : 3u); ++s) {
            const auto full = qrm::circuit_metrics_of(build(m, start, s, v, pruning::none).circuit);
            const auto scene = qrm::circuit_metrics_of(build(m, start, s, v, pruning::scene).circuit);
            const auto reach = qrm::circuit_metrics_of(build(m, start, s, v, pruning::reachable).circuit);
            CAPTURE(dims);
            CAPTURE(p);
            CAPTURE(s);
            CHECK(scene.width <= full.width);
            CHECK(scene.logical_depth <= full.logical_depth);
            CHECK(scene.gate_count <= full.gate_count);
            CHECK(reach.width <= scene.width);
            CHECK(reach.logical_depth <= scene.logical_depth);
            CHECK(reach.gate_count <= scene.gate_count);
          }
    }
}

TEST_CASE("bad input to the scaling helpers is named") {
  CHECK_THROWS_WITH_AS(qrm::scaling_model(2, 8, 15), doctest::Contains("8 directions, got 15"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(qrm::scaling_model(4, 8, 8), doctest::Contains("dims must be 2 or 3, got 4"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(qrm::scaling_model(3, 4, 15), doctest::Contains("got 4"), std::invalid_argument);
  const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  CHECK_THROWS_AS(qrm::unpruned_walk_depth(m, m.light_map_start({1, 1, 0}), 0, walk_variant::faithful),
                  std::invalid_argument);
}

// ---- OpenQASM 3 round trip of the paper's 8x8 circuit -------------------------------------------

namespace {

using cvec = std::vector<std::complex<double>>;

// The state of program p from |0...0> on the dense backend (complex: a parsed program may carry
// complex matrices even where the original was real).
cvec dense_state(const qrm::program& p) {
  qrm::dense_options o;
  o.threads = 1;
  qrm::state_vector<std::complex<double>> b(p.width(), o);
  qrm::run(b, p);
  return {b.amplitudes().begin(), b.amplitudes().end()};
}

}  // namespace

TEST_CASE("the paper's 8x8 circuit exported to OpenQASM 3, parsed back and simulated reproduces the state") {
  const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
  double worst_logical_all = 0, worst_lowered_all = 0, dropped_all = 0;
  std::size_t most_gates = 0;
  for (const std::array<unsigned, 3> cell : {std::array<unsigned, 3>{3, 4, 0}, {1, 1, 0}, {5, 6, 0}})
    for (walk_variant v : {walk_variant::faithful, walk_variant::history})
      for (pruning pr : {pruning::none, pruning::reachable}) {
        const auto w = build(m, m.light_map_start(cell), 3, v, pr);
        const std::size_t n = w.circuit.width();
        CAPTURE(cell[0]);
        CAPTURE(cell[1]);
        CAPTURE(v == walk_variant::history);
        CAPTURE(qrm::pruning_name(pr));
        const cvec want = dense_state(w.circuit);

        // Logical form: one line per gate and per multiplexer entry (ctrl / negctrl modifiers),
        // the coins as gate definitions; simulated gate by gate on the dense backend.
        const std::string text = qrm::to_qasm(w.circuit);
        CHECK(text.find("ctrl(") != std::string::npos);
        const qrm::program logical = qrm::from_qasm(text);
        REQUIRE(logical.width() == n);
        CHECK(logical.size() >= qrm::circuit_metrics_of(w.circuit).gate_count);  // every entry became its own gate
        const cvec got = dense_state(logical);
        double worst = 0;
        for (std::size_t i = 0; i < want.size(); ++i) worst = std::max(worst, std::abs(got[i] - want[i]));
        // 17 significant digits round-trip every angle exactly; the coins' two-level bodies are
        // a few hundred roundings of O(1) numbers (~1e-14); a lost control or phase is O(0.1).
        CHECK(worst < 1e-12);

        // Decomposed form: single-qubit gates and cx only, ancillas declared after the qubits.
        // ~10^5 gates on 21 to 32 qubits: simulated gate by gate on the compact backend (the walk
        // from one cell keeps a few thousand amplitudes nonzero). Cancellations in the lowered
        // gates leave rounding residues (~1e-17) where exact zeros belong, and left alone they
        // spread over all 2^n labels; the backend drops amplitudes with |a|^2 below 1e-22 of the
        // mean probability (~1e-26 here, |a| ~ 1e-13), and the total it dropped is checked below.
        qrm::qasm_options o;
        o.decomposed = true;
        const std::string flat = qrm::to_qasm(w.circuit, o);
        CHECK(flat.find(" @ ") == std::string::npos);
        const qrm::program lowered = qrm::from_qasm(flat);
        REQUIRE(lowered.width() >= n);
        qrm::compact_options co;
        co.prune_threshold = 1e-22;
        qrm::compact_state<std::complex<double>> c(lowered.width(), co);
        qrm::run(c, lowered);
        // Dropped: residues only (~1e-28 in total); one dropped genuine amplitude (>= 1e-3 in
        // these walks) would be >= 1e-6. Below 1e-24, what was dropped is < 1e-12 in norm.
        CHECK(c.pruned().probability < 1e-24);
        double worst_lowered = 0, ancilla_probability = 0;
        std::vector<bool> seen(want.size(), false);
        for (const auto& e : c.entries()) {
          const std::uint64_t label = e.label;
          if (label >> n) {
            ancilla_probability += std::norm(e.amp);
            continue;
          }
          seen[label] = true;
          worst_lowered = std::max(worst_lowered, std::abs(e.amp - want[label]));
        }
        for (std::size_t i = 0; i < want.size(); ++i)
          if (!seen[i]) worst_lowered = std::max(worst_lowered, std::abs(want[i]));
        CHECK(worst_lowered < 1e-12);        // as above, over ~10^5 gates of rounding ~1e-16 each
        CHECK(ancilla_probability < 1e-24);  // rounding only; an ancilla left in |1> is O(1)
        worst_logical_all = std::max(worst_logical_all, worst);
        worst_lowered_all = std::max(worst_lowered_all, worst_lowered);
        dropped_all = std::max(dropped_all, c.pruned().probability);
        most_gates = std::max(most_gates, lowered.size());
      }
  MESSAGE("largest amplitude error: logical " << worst_logical_all << ", decomposed " << worst_lowered_all << " (up to "
                                              << most_gates << " gates; residues dropped <= " << dropped_all
                                              << " in probability)");
}
