// Numerical hard cases of the walk and its estimation, each against an independent value with a
// tolerance derived from how the numbers are computed:
//  - deep walks (s = 1..10): history circuit on the compact backend vs the classical path sum,
//    faithful circuit on the dense vs the compact backend;
//  - emission scaled by 1e-12 and 1e12, and exactly 0;
//  - reflectance 0 and 1 everywhere, also with a single emitting cell (closed forms);
//  - amplitude estimation of a walk whose P(out=1) is a in {0, 1e-12, 1e-6, 0.5, 1 - 1e-9, 1};
//  - float vs double storage on the paper's 8x8 light map;
//  - norm drift over 10^4 Grover iterations.
//
// Rounding model used throughout: u = 2^-53 (double), u_f = 2^-24 (float). A product of k
// floating-point factors has relative error <= k u; a sum of N nonnegative terms computed one
// after another has relative error <= (N - 1) u.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/backends/dense.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/estimation/grover.hpp>
#include <qrm/walk/lightmap.hpp>
#include <qrm/walk/paper_scenes.hpp>
#include <qrm/walk/circuit.hpp>

#include "support/estimation.hpp"

namespace {

constexpr double u = std::numeric_limits<double>::epsilon() / 2;  // 2^-53
constexpr double u_float = std::numeric_limits<float>::epsilon() / 2;  // 2^-24

struct compact_result {
  double p = 0;
  std::size_t nonzeros = 0;
};

// P(out = 1) on the compact backend (real double amplitudes; the 2D walks are real), and how
// many amplitudes were stored at the end.
compact_result run_compact(const qrm::walk_program& w) {
  qrm::compact_state<double> s(w.circuit.width());
  const double p = qrm::probability_out(s, w);
  return {p, s.nonzeros()};
}

double run_dense(const qrm::walk_program& w) {
  qrm::dense_options o;
  o.threads = 1;
  qrm::state_vector<double> s(w.circuit.width(), o);
  return qrm::probability_out(s, w);
}

// |P_history - P_classical| may reach this. In the history circuit the paths are orthogonal, so
// every amplitude is a single product: one factor per op (a coin entry, an Ry entry, the
// start's 1/sqrt(D), the steps preparation) each rounded once and multiplied once, relative
// error <= 2 ops u, squared <= 4 ops u; P sums the N stored out = 1 amplitudes: (N - 1) u more.
// The classical forward pass sums the same nonnegative path weights in another grouping, with at
// most N terms in all and the same products: again <= (4 s + N) u relatively. Worst-case bounds
// (errors of random sign grow like sqrt(N), so the observed errors are far smaller).
double history_tolerance(const qrm::walk_program& w, std::size_t nonzeros, double value) {
  const double ops = static_cast<double>(w.circuit.size());
  const double n = static_cast<double>(nonzeros);
  return (4 * ops + n + 4 * w.tables.steps + n) * u * value + std::numeric_limits<double>::denorm_min();
}

// |P_dense - P_compact| for the same (faithful) circuit. Both backends compute every amplitude as
// the same sum of at most D = 8 products (coins are 8x8) per op, in double, but may group sums
// differently (multiplexer strategies, reductions). An op's rounding error vector has norm
// <= 2 D u (the state has norm 1 and the entries are at most 1), unitary ops do not amplify
// earlier errors, so each state is within ops * 2 D u of the exact one and P within twice that;
// the final reductions over N amplitudes add N u each.
double backend_tolerance(const qrm::walk_program& w, std::size_t nonzeros) {
  const double ops = static_cast<double>(w.circuit.size());
  return 2 * 2 * (ops * 2 * 8 * u) + 2 * static_cast<double>(nonzeros) * u;
}

// Dense simulation stays below this many qubits here (2^22 doubles = 32 MiB).
constexpr std::size_t dense_limit = 22;

// A scene of all air (reflectance 1, no emission), the walk's free motion: directions never change.
qrm::scene air_scene(unsigned n) {
  return qrm::scene("air", 2, n);
}

// The paper's king moves, written out again (independently of qrm::king_2d).
constexpr int king[8][2] = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}};

}  // namespace

TEST_CASE("deep walks, s = 1..10: history = classical path sum, faithful dense = faithful compact") {
  // Start points: on the 8x8 box a light on the top wall (3, 0), a cell of the central block
  // (4, 3) and the air cell (5, 2), up to s = 10 (60 qubits in the history circuit, 2e5 to 8e5
  // stored amplitudes, at most 41 MB). On paper_4x4, whose walls scatter into 4 directions at
  // almost every step, the history state grows about 5x per step: from the air cell (1, 2) it
  // holds 1.1e6 amplitudes (60 MB) at s = 8 and would hold ~3e7 at s = 10, too much for a unit
  // test; there the walks go to s = 8, from (1, 2) and from the light on the top wall (2, 0).
  struct start_cell {
    qrm::scene sc;
    std::array<unsigned, 3> cell;
    unsigned max_steps;
  };
  const start_cell starts[] = {{qrm::box_2d(8), {3, 0, 0}, 10},
                               {qrm::box_2d(8), {4, 3, 0}, 10},
                               {qrm::box_2d(8), {5, 2, 0}, 10},
                               {qrm::paper_4x4(), {2, 0, 0}, 8},
                               {qrm::paper_4x4(), {1, 2, 0}, 8}};
  std::vector<double> worst_relative(11, 0.0), worst_bound_use(11, 0.0);
  std::vector<std::size_t> most_amplitudes(11, 0);
  for (const start_cell& sc : starts) {
    const qrm::walk_model m(sc.sc, qrm::king_2d());
    const qrm::walk_start start = m.light_map_start(sc.cell);
    for (unsigned s = 1; s <= sc.max_steps; ++s) {
      INFO(sc.sc.name() << " cell (" << sc.cell[0] << ", " << sc.cell[1] << ") s = " << s);
      qrm::walk_options o;
      o.steps = s;
      o.variant = qrm::walk_variant::history;
      const qrm::walk_program h = qrm::make_walk_program(m, start, o);
      const compact_result hc = run_compact(h);
      const double classical = qrm::path_sum(m, start, s, 0) / (static_cast<double>(s) * h.tables.emission_scale);
      const double err = std::abs(hc.p - classical), tol = history_tolerance(h, hc.nonzeros, classical);
      CHECK(err <= tol);
      if (classical > 0) worst_relative[s] = std::max(worst_relative[s], err / classical);
      worst_bound_use[s] = std::max(worst_bound_use[s], err / tol);
      most_amplitudes[s] = std::max(most_amplitudes[s], hc.nonzeros);
      o.variant = qrm::walk_variant::faithful;
      const qrm::walk_program f = qrm::make_walk_program(m, start, o);
      const compact_result fc = run_compact(f);
      if (f.circuit.width() <= dense_limit) CHECK(std::abs(run_dense(f) - fc.p) <= backend_tolerance(f, std::size_t{1} << f.circuit.width()));
      CHECK(fc.p >= 0.0);
      CHECK(fc.p <= 1.0);
    }
  }
  // How the error grows with s: more paths (amplitudes) and more ops per amplitude.
  for (unsigned s = 1; s <= 10; ++s)
    MESSAGE("s = " << s << ": largest |history - classical| / classical " << worst_relative[s] << ", "
                   << worst_bound_use[s] << " of the bound, up to " << most_amplitudes[s] << " amplitudes");
}

TEST_CASE("emission scaled by 1e-12 and 1e12: radiance = P(out=1) S scale = path sum; emission 0 gives exactly 0") {
  for (double factor : {1e-12, 1e12}) {
    for (qrm::scene sc : {qrm::paper_4x4(), qrm::box_2d(8)}) {
      for (std::size_t i = 0; i < sc.voxel_count(); ++i)
        for (int c = 0; c < 3; ++c) sc[i].emission[c] *= factor;
      const qrm::walk_model m(sc, qrm::king_2d());
      // Below 1 the emission is encoded as it is (scale 1: sqrt(1e-12) = 1e-6 amplitudes); above 1
      // it is divided by the largest emission, so the circuit is the unscaled one.
      CHECK(sc.emission_scale(0) == (factor < 1 ? 1.0 : factor));
      for (std::size_t cell = 0; cell < sc.voxel_count(); cell += 3) {
        const auto start = m.light_map_start(sc.coords(cell));
        qrm::walk_options o;
        o.steps = 3;
        o.variant = qrm::walk_variant::history;
        const qrm::walk_program w = qrm::make_walk_program(m, start, o);
        const compact_result r = run_compact(w);
        const double radiance = r.p * 3.0 * w.tables.emission_scale;
        const double reference = qrm::path_sum(m, start, 3, 0);
        INFO(sc.name() << " x " << factor << " cell " << cell);
        // The bound of history_tolerance, relative, so it scales with the radiance; plus the
        // rounding of the scale-out multiplication (2 u).
        CHECK(std::abs(radiance - reference) <= history_tolerance(w, r.nonzeros, reference) * 3.0 * w.tables.emission_scale + 2 * u * reference);
        if (factor < 1) CHECK(radiance < 1e-11);  // the scale factor did not get lost
      }
    }
  }
  // No emission anywhere: every term is pruned (or, unpruned, every Le rotation is Ry(0) = I
  // exactly), so P(out = 1) is exactly 0 on both backends, both variants, every pruning level.
  qrm::scene dark = qrm::paper_4x4();
  for (std::size_t i = 0; i < dark.voxel_count(); ++i) dark[i].emission = {};
  const qrm::walk_model m(dark, qrm::king_2d());
  for (std::size_t cell = 0; cell < dark.voxel_count(); ++cell)
    for (qrm::walk_variant v : {qrm::walk_variant::faithful, qrm::walk_variant::history})
      for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::scene, qrm::pruning::reachable}) {
        const auto start = m.light_map_start(dark.coords(cell));
        qrm::walk_options o;
        o.steps = 3;
        o.variant = v;
        o.prune = p;
        const qrm::walk_program w = qrm::make_walk_program(m, start, o);
        CHECK(run_compact(w).p == 0.0);
        if (w.circuit.width() <= dense_limit) CHECK(run_dense(w) == 0.0);
        CHECK(qrm::path_sum(m, start, 3, 0) == 0.0);
      }
}

TEST_CASE("reflectance 0 and 1 everywhere, with a single emitting cell: closed forms, and no spurious branches") {
  // An all-air 8x8 grid (air does not turn the walker) with one emitter of Le = 1 at `target`;
  // starting in air, the walker goes straight in one of 8 directions with probability 1/8,
  // wrapping around the grid. With reflectance 1 everywhere, P(out = 1) = (1/(8 s)) times the
  // number of (direction, step i <= s) that land on the target; with reflectance 0 only step 1
  // counts. Counted here directly from the king moves.
  const unsigned n = 8;
  const std::array<unsigned, 2> target{5, 2};
  for (double rho : {0.0, 1.0}) {
    qrm::scene sc = air_scene(n);
    for (std::size_t i = 0; i < sc.voxel_count(); ++i) sc[i].reflectance = {rho, rho, rho};
    sc.at(target[0], target[1]).emission = {1, 1, 1};
    const qrm::walk_model m(sc, qrm::king_2d());
    for (unsigned s : {1u, 2u, 5u, 9u}) {
      for (std::size_t cell = 0; cell < sc.voxel_count(); cell += 7) {
        const auto xy = sc.coords(cell);
        unsigned hits = 0;
        for (const auto& d : king)
          for (unsigned i = 1; i <= (rho == 1.0 ? s : 1u); ++i) {
            const unsigned x = (xy[0] + n * i + static_cast<unsigned>(d[0] * static_cast<int>(i))) % n;
            const unsigned y = (xy[1] + n * i + static_cast<unsigned>(d[1] * static_cast<int>(i))) % n;
            hits += (x == target[0] && y == target[1]) ? 1 : 0;
          }
        const double closed = hits / (8.0 * s);
        INFO("rho " << rho << " s " << s << " start (" << xy[0] << ", " << xy[1] << ") hits " << hits);
        const auto start = m.light_map_start(xy);
        // The path sum adds at most 8 s products of s + 1 factors: relative error <= 2 (s + 1) 8 s u.
        CHECK(std::abs(qrm::path_sum(m, start, s, 0) / s - closed) <= 16.0 * (s + 1) * s * u * closed);
        for (qrm::walk_variant v : {qrm::walk_variant::faithful, qrm::walk_variant::history}) {
          qrm::walk_options o;
          o.steps = s;
          o.variant = v;
          const qrm::walk_program w = qrm::make_walk_program(m, start, o);
          const compact_result r = run_compact(w);
          // Free motion: paths never meet, so faithful = history = classical, within the history
          // bound (each amplitude is a product of at most `ops` factors).
          CHECK(std::abs(r.p - closed) <= history_tolerance(w, r.nonzeros, closed));
          // Ry(2 asin sqrt 1) and Ry(0) are exactly |1> and I: every stored amplitude belongs
          // to one of the 8 directions in one of the s terms of the steps register (2^bits >= s
          // values, s of them prepared). A rotation whose cos(pi/2) = 6e-17 is not exactly zero
          // would store an extra branch per reflectance qubit: 8 s 2^(s-1) amplitudes.
          CHECK(r.nonzeros <= 8 * s);
        }
      }
    }
  }
  // Reflectance 0 and 1 on the paper's 4x4 scene (walls turn the walker): history = path sum,
  // faithful dense = faithful compact; with reflectance 0 only the first step counts, so nothing
  // can interfere and faithful = classical too.
  for (double rho : {0.0, 1.0}) {
    qrm::scene sc = qrm::paper_4x4();
    for (std::size_t i = 0; i < sc.voxel_count(); ++i) sc[i].reflectance = {rho, rho, rho};
    const qrm::walk_model m(sc, qrm::king_2d());
    for (std::size_t cell = 0; cell < sc.voxel_count(); ++cell) {
      const auto start = m.light_map_start(sc.coords(cell));
      INFO("paper_4x4 rho " << rho << " cell " << cell);
      qrm::walk_options o;
      o.steps = 4;
      o.variant = qrm::walk_variant::history;
      const qrm::walk_program h = qrm::make_walk_program(m, start, o);
      const compact_result hc = run_compact(h);
      const double classical = qrm::path_sum(m, start, 4, 0) / 4.0;
      CHECK(std::abs(hc.p - classical) <= history_tolerance(h, hc.nonzeros, classical));
      o.variant = qrm::walk_variant::faithful;
      const qrm::walk_program f = qrm::make_walk_program(m, start, o);
      const compact_result fc = run_compact(f);
      CHECK(std::abs(run_dense(f) - fc.p) <= backend_tolerance(f, std::size_t{1} << f.circuit.width()));
      if (rho == 0.0) CHECK(std::abs(fc.p - classical) <= history_tolerance(f, fc.nonzeros, classical));
    }
  }
}

TEST_CASE("amplitude estimation of a walk with P(out=1) = a, a in {0, 1e-12, 1e-6, 0.5, 1 - 1e-9, 1}") {
  // An all-air 4x4 grid emitting a everywhere (a <= 1, so the scale is 1), one step from an air
  // cell: every direction lands on a cell of emission a, so P(out = 1) = a. The oracle simulates
  // every Grover iteration of this walk on the dense backend; every estimator, exact and sampled.
  // Sampled cells use alpha = 1e-5: 4 random values x 8 estimators give a false failure with
  // probability below 32e-5 (a = 0 and a = 1 are deterministic: p_k is 0 or 1 to rounding).
  for (double a : {0.0, 1e-12, 1e-6, 0.5, 1.0 - 1e-9, 1.0}) {
    qrm::scene sc = air_scene(4);
    for (std::size_t i = 0; i < sc.voxel_count(); ++i) sc[i].emission = {a, a, a};
    const qrm::walk_model m(sc, qrm::king_2d());
    qrm::walk_options o;
    o.steps = 1;
    const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({1, 2, 0}), o);
    qrm::estimation_problem e{w.circuit, {qrm::control{w.out, true}}};
    const double p = run_dense(w);
    // The walk's own rounding: 8 equal terms (1/8) sqrt(a)^2, each a product of 4 rounded
    // factors: relative <= (16 + 8) u.
    CHECK(std::abs(p - a) <= 24 * u * a);
    for (const std::string& name : qrm_test::estimator_names()) {
      for (bool exact : {true, false}) {
        INFO("a " << a << " estimator " << name << " exact " << exact << " p " << p);
        qrm_test::simulated oracle(e);
        qrm::rng g(4000 + static_cast<std::uint64_t>(a * 1e6));
        const qrm::estimation_result r = qrm_test::run_named(name, oracle, g, exact, 1e-5);
        CHECK(std::isfinite(r.estimate));
        CHECK(std::isfinite(r.confidence_interval[0]));
        CHECK(std::isfinite(r.confidence_interval[1]));
        CHECK(r.confidence_interval[0] <= r.confidence_interval[1]);
        // The interval covers the amplitude the oracle really has (p, which is a to rounding).
        CHECK(r.confidence_interval[0] <= p);
        CHECK(p <= r.confidence_interval[1]);
        CHECK(r.warning.empty());
        // And the radiance it implies covers a * S * scale = a.
        const qrm::radiance_estimate rad = qrm::to_radiance(r, 1.0, w.tables.emission_scale);
        CHECK(rad.confidence_interval[0] <= a + 24 * u * a);
        CHECK(a - 24 * u * a <= rad.confidence_interval[1]);
      }
    }
  }
}

TEST_CASE("float vs double storage: the paper's 8x8 light map within the derived bound") {
  // Bound. The float backends store amplitudes as float and compute each op in double, so each op
  // rounds each amplitude it writes to float once: an error vector of norm <= u_f (the state has
  // norm 1), plus the double arithmetic's 18 u (see the norm-drift case below). Unitary ops
  // carry earlier errors along without growing them, so after K ops
  // |psi_float - psi| <= K (u_f + 18 u) =: eps, and for P = |Pi psi|^2 (Pi the projector on
  // out = 1): |P_float - P| <= 2 eps sqrt(P) + eps^2 (the sums themselves are in double). The
  // double run is itself within 2 K 18 u sqrt(P) of the exact P: added to the bound.
  const qrm::scene sc = qrm::paper_8x8();
  const qrm::walk_model m(sc, qrm::king_2d());
  double worst_ratio = 0, worst_abs = 0;
  for (std::size_t cell = 0; cell < sc.voxel_count(); ++cell)
    for (int c = 0; c < 3; ++c) {
      qrm::walk_options o;
      o.channel = c;
      const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start(sc.coords(cell)), o);
      qrm::dense_options d1;
      d1.threads = 1;
      qrm::state_vector<double> dd(w.circuit.width(), d1);
      qrm::state_vector<float> df(w.circuit.width(), d1);
      qrm::compact_state<float> cf(w.circuit.width());
      const double p = qrm::probability_out(dd, w);
      const double pdf = qrm::probability_out(df, w), pcf = qrm::probability_out(cf, w);
      const double k = static_cast<double>(w.circuit.size());
      const double eps = k * (u_float + 18 * u);
      const double bound = 2 * eps * std::sqrt(p) + eps * eps + 2 * k * 18 * u * std::sqrt(p);
      INFO("cell " << cell << " channel " << c << " P " << p << " ops " << w.circuit.size());
      CHECK(std::abs(pdf - p) <= bound);
      CHECK(std::abs(pcf - p) <= bound);
      const double e = std::max(std::abs(pdf - p), std::abs(pcf - p));
      worst_abs = std::max(worst_abs, e);
      if (bound > 0) worst_ratio = std::max(worst_ratio, e / bound);
    }
  MESSAGE("float vs double on paper_8x8 (s = 3): largest |difference| " << worst_abs << ", at most " << worst_ratio
                                                                        << " of the bound");
  // The margin: rounding errors of random sign add up like sqrt(K), not K; with ~50 ops the
  // observed error is expected far below the worst case. (The check above is the guarantee; this
  // one documents the margin, and fails if it is ever nearly used up.)
  CHECK(worst_ratio < 0.5);
}

TEST_CASE("norm drift over 10^4 Grover iterations of a walk operator") {
  // A = the paper_4x4 walk from the air cell (1, 1), s = 2; Q = A S0 A^dagger S_chi, run 10^4
  // times on the dense double backend. Per op, each output amplitude is a sum of at most D = 8
  // products (8x8 coins) computed in double: error <= D u sum_c |M_rc| |x_c|, a vector of norm
  // <= D u || |M| || <= 16 u (the coins' |M| has 4 entries 1/2 per row and column, norm 2; 2x2
  // gates give less); the matrices themselves are exact (+-1/2, 0, 1) or rounded sin/cos (off
  // unitary by <= 2 u). So after K ops the state is within eps = 18 K u of the exact one, and
  // | |psi|^2 - 1 | <= 2 eps + eps^2.
  const qrm::scene sc = qrm::paper_4x4();
  const qrm::walk_model m(sc, qrm::king_2d());
  qrm::walk_options o;
  o.steps = 2;
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start({1, 1, 0}), o);
  const qrm::estimation_problem e{w.circuit, {qrm::control{w.out, true}}};
  const qrm::program q = qrm::grover_operator(e);
  qrm::dense_options d1;
  d1.threads = 1;
  qrm::state_vector<double> s(w.circuit.width(), d1);
  qrm::run(s, e.a);
  const double a = s.probability(std::span<const qrm::control>(e.good));
  REQUIRE(a > 0.0);
  const double theta = qrm::detail::amplitude_angle(a);
  const std::uint64_t iterations = 10000;
  const double a_ops = static_cast<double>(e.a.size()), q_ops = static_cast<double>(q.size());
  auto state_error = [&](double k) { return 18 * (a_ops + k * q_ops) * u; };
  double worst_drift = 0;
  for (std::uint64_t k = 1; k <= iterations; ++k) {
    qrm::run(s, q);
    if (k % 1000 == 0) {
      const double drift = std::abs(s.norm_squared() - 1.0), eps = state_error(static_cast<double>(k));
      worst_drift = std::max(worst_drift, drift);
      CHECK(drift <= 2 * eps + eps * eps);
    }
  }
  // The amplified probability still follows sin^2((2k + 1) theta): P moves by at most 2 eps with
  // the state; theta comes from the simulated a, whose error (<= 4 ops u: a sum of nonnegative
  // products, see history_tolerance) moves theta by da / sin(2 theta) and p_k by 2 (2k + 1) dtheta.
  const double eps = state_error(static_cast<double>(iterations));
  const double dtheta = (4 * a_ops + static_cast<double>(s.size())) * u * a / std::sin(2 * theta);
  const double want = std::pow(std::sin((2.0 * iterations + 1) * theta), 2);
  const double got = s.probability(std::span<const qrm::control>(e.good));
  CHECK(std::abs(got - want) <= 2 * eps + 2 * (2.0 * iterations + 1) * dtheta);
  MESSAGE("norm drift after " << iterations << " Grover iterations (" << a_ops + iterations * q_ops
                              << " ops): " << worst_drift << " (bound " << 2 * eps + eps * eps << "); |p_k - sin^2((2k+1) theta)| = "
                              << std::abs(got - want));
}
