// Noise: the event list of a small scheduled circuit, trajectories against an exact density
// matrix, the ideal model against the noiseless walk, determinism across threads, the damped
// Grover oscillation, noise-aware MLAE, and bad models.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <qrm/backends/dense.hpp>
#include <qrm/estimation/estimator.hpp>
#include <qrm/estimation/mlae.hpp>
#include <qrm/estimation/oracle.hpp>
#include <qrm/noise.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/paper_scenes.hpp>

#include "support/density_matrix.hpp"

namespace {

// A light-map cell of the paper's 4x4 scene: the A operator and good = out is 1.
qrm::estimation_problem paper_cell(unsigned steps, unsigned x, unsigned y) {
  const qrm::walk_model m(qrm::paper_4x4(), qrm::king_2d());
  qrm::walk_options o;
  o.steps = steps;
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({x, y, 0}), o);
  return {w.circuit, {qrm::control{w.out, true}}};
}

qrm::noise_model mixed_model() {  // every kind of error, strong enough to matter on a few gates
  qrm::noise_model m;
  m.depolarizing_1q = 0.01;
  m.depolarizing_2q = 0.04;
  m.t1 = 20e-6;
  m.t2 = 15e-6;
  m.time_1q = 0.1e-6;
  m.time_2q = 0.4e-6;
  m.readout = 0.03;
  return m;
}

}  // namespace

TEST_CASE("gate-level noise: the events of H then CNOT, worked out by hand") {
  qrm::program p(2);
  p.apply_gate1(qrm::gate::h(), 0, {});
  const qrm::control c0{0, true};
  p.apply_gate1(qrm::gate::x(), 1, std::span<const qrm::control>(&c0, 1));
  qrm::noise_model m;
  m.depolarizing_1q = 0.1;
  m.depolarizing_2q = 0.2;
  m.t1 = 10;
  m.t2 = 10;
  m.time_1q = 1;
  m.time_2q = 2;
  const qrm::noisy_circuit nc = qrm::gate_level_noise(p, m);
  using K = qrm::noise_event_kind;
  // Damping over t: 1 - e^(-t/10); dephasing rate 1/T2 - 1/(2 T1) = 0.05: P(Z) = (1 - e^(-0.05 t)) / 2.
  struct want {
    K kind;
    std::vector<qrm::qubit_index> qubits;
    double p;
  };
  const std::vector<want> expected = {
      {K::gate, {}, 0},
      {K::pauli, {0}, 0.1},
      {K::damping, {0}, 1 - std::exp(-0.1)},
      {K::dephasing, {0}, (1 - std::exp(-0.05)) / 2},
      {K::gate, {}, 0},  // starts at t = 1: qubit 0 did not wait, qubit 1 was never touched
      {K::pauli, {1, 0}, 0.2},
      {K::damping, {1}, 1 - std::exp(-0.2)},
      {K::dephasing, {1}, (1 - std::exp(-0.1)) / 2},
      {K::damping, {0}, 1 - std::exp(-0.2)},
      {K::dephasing, {0}, (1 - std::exp(-0.1)) / 2},
  };
  REQUIRE(nc.events.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CAPTURE(i);
    CHECK(nc.events[i].kind == expected[i].kind);
    CHECK(nc.events[i].qubits == expected[i].qubits);
    CHECK(nc.events[i].probability == doctest::Approx(expected[i].p).epsilon(1e-14));
  }
  CHECK(nc.events[4].op == 1);
  CHECK(nc.seconds == 3);

  // An op that is neither a single-qubit gate nor a CNOT is refused.
  qrm::program t(3);
  const qrm::control cc[2] = {{0, true}, {1, true}};
  t.apply_gate1(qrm::gate::x(), 2, cc);
  CHECK_THROWS_WITH(qrm::gate_level_noise(t, m), doctest::Contains("op 0 is not a single-qubit gate or a CNOT"));
}

TEST_CASE("trajectories agree with an exact density matrix within 3 standard errors") {
  // sine_integral_problem(2): 3 qubits, and ancillas for the Grover operator's reflections.
  const qrm::estimation_problem e = qrm::sine_integral_problem(2);
  const qrm::noise_model m = mixed_model();
  qrm::noisy_oracle_options o;
  o.trajectories = 4000;
  o.seed = 7;
  qrm::noisy_oracle oracle(e, m, o);
  const auto& c = oracle.circuits();
  REQUIRE(c.width <= 10);
  qrm_test::density_matrix rho(static_cast<unsigned>(c.width));
  rho.run(c.a);
  double largest_gap = 0;
  for (std::uint64_t k = 0; k <= 3; ++k) {
    if (k > 0) rho.run(c.grover);
    CAPTURE(k);
    CHECK(rho.trace() == doctest::Approx(1).epsilon(1e-12));
    const double exact = rho.measured(e.good, m.readout);
    const qrm::trajectory_mean t = oracle.probability_with_error(k);
    CHECK(t.standard_error > 0);
    CHECK(std::fabs(t.mean - exact) <= 3 * t.standard_error);
    largest_gap = std::max(largest_gap, std::fabs(t.mean - exact) / t.standard_error);
  }
  MESSAGE("largest |trajectories - density matrix| / standard error: " << largest_gap);

  // The noise is visible: the noisy and ideal values differ by many standard errors at k = 3.
  qrm::analytic_oracle ideal(qrm::sine_integral_value(2));
  const qrm::trajectory_mean t3 = oracle.probability_with_error(3);
  CHECK(std::fabs(t3.mean - ideal.probability(3)) > 10 * t3.standard_error);
}

TEST_CASE("the logical-level model against an exact density matrix of its own events") {
  // Gate-level events reference single-qubit gates; the logical model on an already decomposed
  // program is one Pauli channel per gate with p1 or p2, i.e. the gate-level model without time.
  const qrm::estimation_problem e = qrm::sine_integral_problem(2);
  const qrm::program d = qrm::decompose(e.a).circuit;
  const qrm::noise_model m = qrm::depolarizing_noise(0.02, 0.05);
  const qrm::noisy_circuit logical = qrm::logical_level_noise(d, m);
  const qrm::noisy_circuit gates = qrm::gate_level_noise(d, m);
  REQUIRE(logical.events.size() == gates.events.size());
  for (std::size_t i = 0; i < gates.events.size(); ++i) {
    CAPTURE(i);
    CHECK(logical.events[i].kind == gates.events[i].kind);
    CHECK(logical.events[i].probability == doctest::Approx(gates.events[i].probability).epsilon(1e-14));
  }
  // On the logical circuit: a C^2 X costs 6 CNOTs and 9 single-qubit gates (decompose.hpp's
  // Toffoli), so its rate is 1 - 0.98^9 0.95^6.
  qrm::program t(3);
  const qrm::control cc[2] = {{0, true}, {1, true}};
  t.apply_gate1(qrm::gate::x(), 2, cc);
  const qrm::noisy_circuit tl = qrm::logical_level_noise(t, m);
  REQUIRE(tl.events.size() == 2);
  const auto counts = qrm::decomposed_metrics(t);
  CHECK(counts.cnot_count == 6);
  CHECK(tl.events[1].qubits == std::vector<qrm::qubit_index>{0, 1, 2});
  CHECK(tl.events[1].probability ==
        doctest::Approx(1 - std::pow(0.98, static_cast<double>(counts.single_qubit_count)) * std::pow(0.95, 6)));
  CHECK_THROWS_WITH(qrm::logical_level_noise(t, mixed_model()), doctest::Contains("no T1/T2"));
}

TEST_CASE("the ideal model reproduces the noiseless walk: bit for bit, and the logical walk to 1e-12") {
  // paper_4x4, one step from cell (1, 1): 10 logical qubits; decomposed, the Grover operator's
  // reflection about |0...0> needs 8 ancillas (18 qubits).
  const qrm::estimation_problem e = paper_cell(1, 1, 1);
  qrm::noisy_oracle_options o;
  o.trajectories = 50;  // the ideal model runs one: they would all be equal
  o.fuse = false;       // gate by gate, as below (fused: to rounding, checked after)
  qrm::noisy_oracle noisy(e, qrm::noise_preset("ideal"), o);
  o.fuse = true;
  qrm::noisy_oracle fused(e, qrm::noise_preset("ideal"), o);
  CHECK(noisy.trajectories() == 1);
  qrm::simulated_oracle<qrm::state_vector<std::complex<double>>> logical(e);
  const auto& c = noisy.circuits();
  // The noiseless circuit's ops one by one in program order, as a trajectory applies them
  // (qrm::run may reorder commuting ops into a chunk's run: equal only to rounding).
  qrm::trajectory_state plain(c.width);
  const auto apply_in_order = [&plain](const qrm::program& p) {
    for (const qrm::op::any& o : p.ops()) qrm::emit_op(o, plain);
  };
  apply_in_order(c.a.circuit);
  const std::uint64_t kmax = 3;
  noisy.prepare(kmax);
  for (std::uint64_t k = 0; k <= kmax; ++k) {
    CAPTURE(k);
    if (k > 0) apply_in_order(c.grover.circuit);
    CHECK(noisy.probability(k) == plain.probability(e.good));  // bit for bit
    CHECK(std::fabs(fused.probability(k) - plain.probability(e.good)) <= 1e-12);
    CHECK(std::fabs(noisy.probability(k) - logical.probability(k)) <= 1e-12);
  }
  // Logical level, ideal, three steps (15 qubits): every k up to 2^5 (MLAE's default schedule).
  const qrm::estimation_problem e3 = paper_cell(3, 1, 1);
  qrm::simulated_oracle<qrm::state_vector<std::complex<double>>> logical3(e3);
  o.level = qrm::noise_level::logical;
  qrm::noisy_oracle noisy_logical(e3, qrm::noise_preset("ideal"), o);
  noisy_logical.prepare(32);
  for (std::uint64_t k = 0; k <= 32; ++k) {
    CAPTURE(k);
    CHECK(std::fabs(noisy_logical.probability(k) - logical3.probability(k)) <= 1e-12);
  }
}

namespace {
// Runs trajectories of `c` gate by gate and fused at `width` from the same seeds: the same errors
// (the generators end equal) and the same states. Bound: the fused blocks' rounding, a few units
// of 1e-16 per amplitude (measured up to 1.6e-15 on the 18-qubit walk).
// Returns how many runs took the shared fused ops (the others were cut at damping draws below gamma).
std::size_t check_fused_trajectories(const qrm::noisy_circuit& c, unsigned width, std::size_t trajectories,
                                     unsigned runs) {
  const qrm::fused_noisy_circuit f(c, width);
  CHECK(f.fused_ops() <= f.gates().size());
  std::size_t fused_runs = 0;
  for (std::size_t t = 0; t < trajectories; ++t) {
    CAPTURE(t);
    qrm::trajectory_state plain(c.width()), fused(c.width());
    qrm::rng g = qrm::rng::stream(11, t), h = qrm::rng::stream(11, t);
    for (unsigned r = 0; r < runs; ++r) {
      qrm::apply_noisy(plain, c, g);
      fused_runs += f.apply(fused, h);
    }
    CHECK(g() == h());
    double worst = 0;
    for (std::size_t i = 0; i < plain.amplitudes().size(); ++i)
      worst = std::max(worst, std::abs(plain.amplitudes()[i] - fused.amplitudes()[i]));
    CHECK(worst <= 1e-12);
  }
  return fused_runs;
}
}  // namespace

TEST_CASE("fused trajectories: the same errors and states as gate by gate, errors inside blocks included") {
  qrm::noisy_oracle_options o;
  const qrm::noise_model strong = qrm::depolarizing_noise(0.02, 0.1);  // errors in most blocks
  SUBCASE("the walk's A and Q, decomposed (18 qubits), width chosen") {
    const auto c = qrm::noisy_grover_circuits_of(paper_cell(1, 1, 1), strong, o);
    qrm::noisy_circuit both = c.grover;  // A then Q in one circuit of the wider width
    both.circuit = qrm::program(c.width);
    both.events.clear();
    for (const qrm::noisy_circuit* part : {&c.a, &c.grover}) {
      const auto offset = static_cast<std::uint32_t>(both.circuit.size());
      for (const qrm::op::any& op : part->circuit.ops()) both.circuit.push(op);
      for (qrm::noise_event ev : part->events) {
        if (ev.kind == qrm::noise_event_kind::gate) ev.op += offset;
        both.events.push_back(ev);
      }
    }
    check_fused_trajectories(both, 0, 2, 1);
  }
  SUBCASE("every width, with relaxation: damping as K0 in the blocks, cut and fused afresh where it may jump") {
    qrm::noise_model long_t1 = mixed_model();  // damping draws rarely below gamma: most runs fused
    long_t1.t1 = 0.5;
    long_t1.t2 = 20e-6;
    const auto c = qrm::noisy_grover_circuits_of(qrm::sine_integral_problem(3), long_t1, o);
    const auto strong_damping = qrm::noisy_grover_circuits_of(qrm::sine_integral_problem(3), mixed_model(), o);
    for (unsigned width = 0; width <= 6; ++width) {
      CAPTURE(width);
      CHECK(check_fused_trajectories(c.grover, width, 6, 2) >= 10);
      CHECK(check_fused_trajectories(strong_damping.grover, width, 6, 2) < 12);
    }
  }
  SUBCASE("an error right after a damping event that may jump comes after its decision") {
    qrm::noisy_circuit c{qrm::program(2), {}, 0};
    c.circuit.apply_gate1(qrm::gate::h(), 0, {});
    const qrm::control on0{0, true};
    c.circuit.apply_gate1(qrm::gate::x(), 1, std::span<const qrm::control>(&on0, 1));
    c.circuit.apply_gate1(qrm::gate::ry(0.7), 0, {});
    using kind = qrm::noise_event_kind;
    c.events = {{kind::gate, 0, {}, 0},        {kind::gate, 1, {}, 0},      {kind::damping, 0, {0}, 0.6},
                {kind::pauli, 0, {0, 1}, 1.0}, {kind::dephasing, 0, {0}, 0.5}, {kind::gate, 2, {}, 0},
                {kind::damping, 0, {1}, 0.9}};
    CHECK(check_fused_trajectories(c, 0, 32, 2) < 40);  // most runs are cut
  }
  SUBCASE("every width, depolarizing only (one segment)") {
    const auto c = qrm::noisy_grover_circuits_of(qrm::sine_integral_problem(4), strong, o);
    for (unsigned width = 0; width <= 6; ++width) {
      CAPTURE(width);
      check_fused_trajectories(c.grover, width, 6, 3);
    }
  }
  SUBCASE("the logical level: channels on whole logical ops") {
    o.level = qrm::noise_level::logical;
    const auto c = qrm::noisy_grover_circuits_of(paper_cell(1, 1, 1), strong, o);
    check_fused_trajectories(c.grover, 0, 4, 2);
  }
  SUBCASE("events out of order are refused") {
    const auto c = qrm::noisy_grover_circuits_of(qrm::sine_integral_problem(3), strong, o);
    qrm::noisy_circuit bad = c.a;
    std::swap(bad.events[0], bad.events[2]);
    REQUIRE(bad.events[0].kind == qrm::noise_event_kind::gate);
    CHECK_THROWS_WITH_AS(qrm::fused_noisy_circuit(bad, 0), doctest::Contains("the events must run the ops in order"),
                         std::invalid_argument);
    CHECK_THROWS_WITH_AS(qrm::fused_noisy_circuit(c.a, 7), doctest::Contains("must be 0 (chosen) or 1..6, got 7"),
                         std::invalid_argument);
  }
}

TEST_CASE("noisy trajectories do not depend on threads or on the order of questions") {
  const qrm::estimation_problem e = qrm::sine_integral_problem(3);
  qrm::noisy_oracle_options o;
  o.trajectories = 64;
  o.seed = 3;
  o.threads = 1;
  qrm::noisy_oracle one(e, mixed_model(), o);
  o.threads = 2;
  qrm::noisy_oracle two(e, mixed_model(), o);
  two.prepare(5);
  for (std::uint64_t k : {0u, 1u, 2u, 5u}) CHECK(one.probability(k) == two.probability(k));  // one grows 0, 1, 2, 4
  o.seed = 4;
  qrm::noisy_oracle other(e, mixed_model(), o);
  CHECK(other.probability(5) != two.probability(5));
}

TEST_CASE("depolarizing noise damps the Grover oscillation of a paper_4x4 cell, more with every k") {
  // Logical level (each op's rate from its 1q + CNOT count): one step, 10 qubits. p1 = 2e-5 and
  // p2 = 2e-4 lose about 9% of the signal per application of A.
  const qrm::estimation_problem e = paper_cell(1, 1, 1);
  qrm::noisy_oracle_options o;
  o.trajectories = 400;
  o.level = qrm::noise_level::logical;
  qrm::noisy_oracle noisy(e, qrm::depolarizing_noise(2e-5, 2e-4), o);
  qrm::simulated_oracle<qrm::state_vector<std::complex<double>>> ideal(e);
  const std::uint64_t kmax = 8;
  noisy.prepare(kmax);
  // Contrast: how much of the ideal swing from one power to the next survives,
  // (p_k - p_(k-1)) / (ideal_k - ideal_(k-1)). Differences cancel the level the noise drives p
  // towards (not 1/2 here: the logical model's errors mostly send the walker where out stays 0),
  // and under Pauli noise the surviving fraction is a product of per-iteration factors: it must
  // not grow with k beyond the trajectory error (a, 0.25 here, repeats every 3 powers).
  double previous = 1, previous_error = 0;
  int compared = 0;
  for (std::uint64_t k = 1; k <= kmax; ++k) {
    const double swing = ideal.probability(k) - ideal.probability(k - 1);
    if (std::fabs(swing) < 0.3) continue;  // the ratio is ill-conditioned for small swings
    const qrm::trajectory_mean t = noisy.probability_with_error(k), t0 = noisy.probability_with_error(k - 1);
    const double contrast = (t.mean - t0.mean) / swing;
    const double error = std::hypot(t.standard_error, t0.standard_error) / std::fabs(swing);
    CAPTURE(k);
    CAPTURE(contrast);
    CHECK(contrast < 1);
    CHECK(contrast <= previous + 3 * std::hypot(error, previous_error));
    previous = contrast;
    previous_error = error;
    ++compared;
  }
  CHECK(compared >= 4);
  CHECK(previous < 0.5);  // the decay is plain by the last compared k
}

TEST_CASE("the global model: every run of A or Q fully depolarizes with its decomposition's error") {
  const qrm::estimation_problem e = qrm::sine_integral_problem(3);
  const double a = qrm::sine_integral_value(3);
  const qrm::noise_model m = qrm::depolarizing_noise(1e-3, 1e-2);
  const qrm::global_noise_oracle o(e, m, a);
  // The survival probabilities from the gate counts of the decompositions (decompose.hpp, tested
  // in test_decompose): (1 - p1)^n1 (1 - p2)^n2.
  const auto ca = qrm::decomposed_metrics(e.a), cq = qrm::decomposed_metrics(qrm::grover_operator(e));
  const double fa = std::pow(1 - 1e-3, static_cast<double>(ca.single_qubit_count)) * std::pow(1 - 1e-2, static_cast<double>(ca.cnot_count));
  const double fq = std::pow(1 - 1e-3, static_cast<double>(cq.single_qubit_count)) * std::pow(1 - 1e-2, static_cast<double>(cq.cnot_count));
  CHECK(o.survival_a() == doctest::Approx(fa).epsilon(1e-12));
  CHECK(o.survival_q() == doctest::Approx(fq).epsilon(1e-12));
  CHECK(fq < fa);  // Q runs A twice
  const double theta = std::asin(std::sqrt(a));
  for (std::uint64_t k : {0u, 1u, 5u, 20u}) {
    const double l = fa * std::pow(fq, static_cast<double>(k));
    const double s = std::sin((2.0 * static_cast<double>(k) + 1) * theta);
    CHECK(o.probability(k) == doctest::Approx(l * s * s + (1 - l) * 0.5).epsilon(1e-12));
  }
  // Readout flips on the good qubit; the ideal model is the analytic oracle.
  qrm::noise_model r = m;
  r.readout = 0.1;
  const qrm::global_noise_oracle ro(e, r, a);
  CHECK(ro.probability(3) == doctest::Approx(0.9 * o.probability(3) + 0.1 * (1 - o.probability(3))).epsilon(1e-12));
  const qrm::global_noise_oracle ideal(e, qrm::noise_preset("ideal"), a);
  const qrm::analytic_oracle exact(a);
  for (std::uint64_t k = 0; k <= 32; ++k) CHECK(std::fabs(ideal.probability(k) - exact.probability(k)) <= 1e-15);
}

namespace {
// p_k of the damped model itself: what noise-aware MLAE assumes.
struct damped_oracle {
  double theta, rate;
  double probability(std::uint64_t k) const {
    const double K = 2.0 * static_cast<double>(k) + 1.0;
    return 0.5 * (1 - std::exp(-rate * K) * std::cos(2 * K * theta));
  }
  double coin_probability(double, std::uint64_t) const { return 0; }
  damped_oracle rescaled(double) const { return *this; }
};
}  // namespace

TEST_CASE("noise-aware MLAE recovers amplitude and decay where plain MLAE is biased") {
  const double a = 0.3, rate = 0.02;
  damped_oracle o{std::asin(std::sqrt(a)), rate};
  qrm::mlae_options opt;
  opt.m = 6;
  opt.shots = 200;
  opt.exact_probabilities = true;
  opt.noise_aware = true;
  qrm::rng g(1);
  const qrm::estimation_result exact = qrm::maximum_likelihood_amplitude_estimation(o, opt, g);
  CHECK(exact.estimator == "mlae_noise_aware");
  CHECK(exact.estimate == doctest::Approx(a).epsilon(1e-6));
  REQUIRE(exact.damping.has_value());
  CHECK(*exact.damping == doctest::Approx(rate).epsilon(1e-4));

  // Shots: over 40 seeds, noise-aware RMSE well below plain MLAE's.
  opt.exact_probabilities = false;
  double sq_aware = 0, sq_plain = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    qrm::rng g1(seed), g2(seed);
    opt.noise_aware = true;
    const double x = qrm::maximum_likelihood_amplitude_estimation(o, opt, g1).estimate;
    opt.noise_aware = false;
    const double y = qrm::maximum_likelihood_amplitude_estimation(o, opt, g2).estimate;
    sq_aware += (x - a) * (x - a);
    sq_plain += (y - a) * (y - a);
  }
  MESSAGE("RMSE noise-aware " << std::sqrt(sq_aware / 40) << ", plain " << std::sqrt(sq_plain / 40));
  CHECK(std::sqrt(sq_aware) * 2 < std::sqrt(sq_plain));

  // Without noise the noise-aware fit finds no decay to speak of and the same amplitude.
  damped_oracle clean{std::asin(std::sqrt(a)), 0.0};
  opt.exact_probabilities = true;
  opt.noise_aware = true;
  const qrm::estimation_result r0 = qrm::maximum_likelihood_amplitude_estimation(clean, opt, g);
  CHECK(r0.estimate == doctest::Approx(a).epsilon(1e-6));
  CHECK(*r0.damping < 1e-4);
}

TEST_CASE("any_oracle gives every estimator what the oracle it holds gives") {
  // (the renderer runs noisy oracles through it; rescaled and coin probabilities included)
  for (qrm::estimator_kind k : qrm::all_estimators) {
    CAPTURE(qrm::estimator_name(k));
    qrm::estimator_settings s;
    s.kind = k;
    qrm::analytic_oracle plain(0.3);
    qrm::any_oracle held(qrm::analytic_oracle(0.3));
    qrm::rng g1(5), g2(5);
    const qrm::estimation_result a = qrm::estimate_amplitude(plain, s, g1), b = qrm::estimate_amplitude(held, s, g2);
    CHECK(a.estimate == b.estimate);
    CHECK(a.a_calls == b.a_calls);
  }
}

TEST_CASE("bad noise models are refused with the value") {
  qrm::noise_model m;
  m.depolarizing_2q = 1.5;
  CHECK_THROWS_WITH(qrm::validate(m), doctest::Contains("two-qubit depolarizing rate must be a probability in [0, 1], got 1.5"));
  m = {};
  m.readout = -0.1;
  CHECK_THROWS_WITH(qrm::validate(m), doctest::Contains("readout error"));
  m = {};
  m.t1 = 1e-6;
  m.t2 = 3e-6;
  m.time_2q = 1e-7;
  CHECK_THROWS_WITH(qrm::validate(m), doctest::Contains("cannot exceed 2 T1"));
  m = {};
  m.t1 = 1e-6;
  m.t2 = 1e-6;
  CHECK_THROWS_WITH(qrm::validate(m), doctest::Contains("needs gate times"));
  m = {};
  m.time_1q = -1;
  CHECK_THROWS_WITH(qrm::validate(m), doctest::Contains("single-qubit gate time"));
  CHECK_THROWS_WITH(qrm::noise_preset("transmon"), doctest::Contains("unknown noise preset 'transmon'"));
}
