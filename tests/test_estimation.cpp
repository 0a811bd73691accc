// Amplitude estimation, deterministic parts: the special functions, the problems, the Grover
// operator and the coin against closed forms, analytic vs simulated oracles (same seed, same
// counts), FAE against an independent transcription of the FAE rules stated in fae.hpp's header, the hard-case table,
// call counting, input errors and the radiance helper.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <qrm/qrm.hpp>
#include <string>
#include <variant>
#include <vector>

#include "support/errors.hpp"
#include "support/estimation.hpp"
#include "support/random_ops.hpp"

using qrm_test::error_of;

namespace {
using qrm_test::dense_real;
using qrm_test::simulated;
using std::numbers::pi;

// P(Bin(n, p) >= k) by direct summation of the pmf.
double binomial_upper_tail(int n, double p, int k) {
  double s = 0;
  for (int i = k; i <= n; ++i)
    s += std::exp(qrm::detail::log_factorial(n) - qrm::detail::log_factorial(i) - qrm::detail::log_factorial(n - i) +
                  i * std::log(p) + (n - i) * std::log1p(-p));
  return s;
}

double simulated_probability(const qrm::estimation_problem& e) {
  dense_real s(e.a.width());
  qrm::run(s, e.a);
  return s.probability(std::span<const qrm::control>(e.good));
}
}  // namespace

TEST_CASE("special functions: log-gamma, incomplete beta, quantiles against closed forms") {
  for (std::uint64_t k = 1; k < 300; k += 7)
    CHECK(qrm::detail::log_gamma(double(k)) == doctest::Approx(qrm::detail::log_factorial(k - 1)).epsilon(1e-13));
  CHECK(qrm::detail::log_gamma(0.5) == doctest::Approx(0.5 * std::log(pi)).epsilon(1e-14));
  for (double x : {0.01, 0.3, 0.5, 0.77, 0.999}) {
    CHECK(qrm::detail::incomplete_beta(1, 1, x) == doctest::Approx(x).epsilon(1e-13));
    CHECK(qrm::detail::incomplete_beta(3.5, 1, x) == doctest::Approx(std::pow(x, 3.5)).epsilon(1e-12));
    CHECK(qrm::detail::incomplete_beta(1, 2.5, x) == doctest::Approx(1 - std::pow(1 - x, 2.5)).epsilon(1e-12));
    // I_p(k, n - k + 1) = P(Bin(n, p) >= k): an independent sum of binomial terms.
    for (int k : {1, 4, 17})
      CHECK(qrm::detail::incomplete_beta(k, 40 - k + 1, x) ==
            doctest::Approx(binomial_upper_tail(40, x, k)).epsilon(1e-10));
  }
  for (double q : {1e-9, 0.025, 0.5, 0.975}) {
    const double x = qrm::detail::beta_quantile(q, 7.25, 93.5);
    CHECK(qrm::detail::incomplete_beta(7.25, 93.5, x) == doctest::Approx(q).epsilon(1e-10));
  }
  // 1.959963984540054 is the textbook 97.5% normal quantile.
  CHECK(qrm::detail::normal_quantile(0.975) == doctest::Approx(1.959963984540054).epsilon(1e-13));
  for (double p : {1e-10, 0.01, 0.3, 0.9})
    CHECK(qrm::detail::normal_cdf(qrm::detail::normal_quantile(p)) == doctest::Approx(p).epsilon(1e-12));
}

TEST_CASE("Clopper-Pearson ends leave alpha/2 in each tail; Wilson ends solve the score equation") {
  const int n = 60;
  for (int h : {0, 1, 13, 59, 60}) {
    const auto [lo, hi] = qrm::detail::clopper_pearson(h, n, 0.1);
    if (h > 0)
      CHECK(binomial_upper_tail(n, lo, h) == doctest::Approx(0.05).epsilon(1e-8));
    else
      CHECK(lo == 0.0);
    if (h < n)
      CHECK(1.0 - binomial_upper_tail(n, hi, h + 1) == doctest::Approx(0.05).epsilon(1e-8));
    else
      CHECK(hi == 1.0);
    const auto [wl, wh] = qrm::detail::wilson(h, n, 0.1);
    const double z = qrm::detail::normal_quantile(0.95), ph = double(h) / n;
    for (double e : {wl, wh})
      if (e > 0 && e < 1) CHECK(std::fabs(ph - e) / std::sqrt(e * (1 - e) / n) == doctest::Approx(z).epsilon(1e-9));
  }
}

TEST_CASE("problems: Bernoulli gives a = P; SineIntegral matches the closed form and the direct mean") {
  for (double p : {0.0, 1e-6, 0.2, 0.5, 0.93, 1.0})
    CHECK(simulated_probability(qrm::bernoulli_problem(p)) == doctest::Approx(p).epsilon(1e-14));
  for (unsigned n = 1; n <= 8; ++n) {
    const double N = std::ldexp(1.0, int(n));
    double direct = 0;
    for (int x = 0; x < int(N); ++x) direct += std::pow(std::sin((x + 0.5) / N), 2) / N;
    CHECK(qrm::sine_integral_value(n) == doctest::Approx(direct).epsilon(1e-13));
    CHECK(simulated_probability(qrm::sine_integral_problem(n)) == doctest::Approx(direct).epsilon(1e-13));
    CHECK(qrm::sine_integral_problem(n).a.is_real());
  }
}

TEST_CASE("the simulated Grover operator gives sin^2((2k+1) theta) on random real and complex circuits") {
  qrm::rng g(71);
  for (std::size_t n : {6, 8, 10}) {
    for (bool extra : {false, true}) {
      const auto e = qrm_test::random_real_problem(n, g, extra);
      const double a = simulated_probability(e);
      INFO("n " << n << " extra " << extra << " a " << a);
      REQUIRE(a > 0.01);
      REQUIRE(a < 0.99);
      const double theta = qrm::detail::amplitude_angle(a);
      simulated o(e);
      // Increasing k continues from the stored state: 20 iterations in total, one preparation.
      for (std::uint64_t k = 0; k <= 20; ++k)
        CHECK(o.probability(k) == doctest::Approx(std::pow(std::sin((2 * k + 1) * theta), 2)).epsilon(1e-11).scale(1));
      CHECK(o.simulated_grover_iterations() == 20);
      CHECK(o.restarts() == 1);
      // A fresh oracle asked in decreasing order restarts each time and still agrees.
      simulated back(e);
      for (std::uint64_t k : {7, 3, 5})
        CHECK(back.probability(k) ==
              doctest::Approx(std::pow(std::sin((2 * k + 1) * theta), 2)).epsilon(1e-11).scale(1));
      CHECK(back.restarts() == 2);
      CHECK(back.simulated_grover_iterations() == 7 + 3 + 2);
    }
  }
  // Complex A on the complex backend: the same law.
  qrm::estimation_problem e{qrm::program(4), {qrm::control{3, true}}};
  const qrm::qubit_index all[] = {0, 1, 2, 3};
  e.a.apply_unitary(qrm_test::random_unitary(4, g, true), all, {});
  qrm::state_vector<std::complex<double>> s(4);
  qrm::run(s, e.a);
  const double theta = qrm::detail::amplitude_angle(s.probability(std::span<const qrm::control>(e.good)));
  qrm::simulated_oracle<qrm::state_vector<std::complex<double>>> oc(e);
  for (std::uint64_t k = 0; k <= 12; ++k)
    CHECK(oc.probability(k) == doctest::Approx(std::pow(std::sin((2 * k + 1) * theta), 2)).epsilon(1e-11).scale(1));
}

TEST_CASE("rescaling appends a real ancilla: p_0 becomes a/16") {
  qrm::rng g(5);
  const auto e = qrm_test::random_real_problem(7, g);
  const double a = simulated_probability(e);
  simulated o(e);
  auto r = o.rescaled(0.25);
  CHECK(r.problem().a.width() == 8);
  CHECK(r.problem().good.size() == 2);
  CHECK(r.probability(0) == doctest::Approx(a / 16).epsilon(1e-13));
  CHECK(qrm::analytic_oracle(a).rescaled(0.25).amplitude() == doctest::Approx(a / 16).epsilon(1e-15));
}

TEST_CASE("the quantum coin circuit has amplitude l - a on |0...0>, and its amplified law is sin^2(2 n asin|l - a|)") {
  qrm::rng g(9);
  for (bool extra : {false, true}) {
    const auto e = qrm_test::random_real_problem(6, g, extra);
    const double a = simulated_probability(e);
    simulated o(e);
    for (double l : {0.0, 0.1, a, 0.49, 0.5, 0.73, 1.0}) {
      dense_real s(e.a.width() + 2);
      qrm::run(s, qrm::coin_program(e, l));
      // l - a above the branch point 1/2, a - l below it; rounding of a few dozen O(1) operations.
      CHECK(s.amplitude(0) == doctest::Approx(l >= 0.5 ? l - a : a - l).epsilon(1e-12).scale(1));
      for (std::uint64_t n : {1, 2, 4})
        CHECK(o.coin_probability(l, n) ==
              doctest::Approx(std::pow(std::sin(2.0 * n * std::asin(std::fabs(l - a))), 2)).epsilon(1e-11).scale(1));
    }
  }
}

namespace {
// Every op of p with one more control.
qrm::program with_control(const qrm::program& p, qrm::control c, std::size_t width) {
  qrm::program r(width);
  for (qrm::op::any o : p.ops()) {
    std::visit([&](auto& x) { x.controls.push_back(c); }, o);
    r.push(o);
  }
  return r;
}
}  // namespace

TEST_CASE("canonical AE: the closed-form phase law equals a simulated phase-estimation circuit") {
  // The real circuit: A on the system, H on m evaluation qubits, controlled Q^(2^j) on evaluation
  // qubit j with Brassard's sign (Q_B = -Q: a Z on the control, for j = 0 only since
  // (-1)^(2^j) = 1 for j >= 1), then the inverse Fourier transform as one dense unitary.
  qrm::rng g(17);
  const auto random_problem = qrm_test::random_real_problem(3, g);
  for (const auto& e : {qrm::bernoulli_problem(0.3), qrm::bernoulli_problem(0.02), random_problem}) {
    const unsigned m = 4;
    const std::size_t w = e.a.width(), M = std::size_t{1} << m;
    qrm::state_vector<std::complex<double>> s(w + m);
    qrm::run(s, e.a);
    std::vector<qrm::qubit_index> eval;
    for (unsigned j = 0; j < m; ++j) eval.push_back(static_cast<qrm::qubit_index>(w + j));
    for (auto q : eval) s.apply_gate1(qrm::gate::h(), q, {});
    const qrm::program q = qrm::grover_operator(e);
    for (unsigned j = 0; j < m; ++j) {
      const qrm::program cq = with_control(q, {eval[j], true}, w + m);
      for (std::size_t r = 0; r < (std::size_t{1} << j); ++r) qrm::run(s, cq);
      if (j == 0) s.apply_gate1(qrm::gate::z(), eval[j], {});
    }
    qrm::dense_matrix iqft(M);
    for (std::size_t x = 0; x < M; ++x)
      for (std::size_t y = 0; y < M; ++y)
        iqft(x, y) = std::polar(1.0 / std::sqrt(double(M)), -2 * pi * double(x * y) / double(M));
    s.apply_unitary(iqft, eval, {});
    const auto simulated_law = s.distribution(eval);
    dense_real sa(w);
    qrm::run(sa, e.a);
    const double theta = qrm::detail::amplitude_angle(sa.probability(std::span<const qrm::control>(e.good)));
    const auto law = qrm::canonical_phase_distribution(theta, m);
    // Rounding of a few hundred gates on <= 7 qubits.
    for (std::size_t y = 0; y < M; ++y) CHECK(law[y] == doctest::Approx(simulated_law[y]).epsilon(1e-11).scale(1));
  }
}

TEST_CASE("the shot sampler treats rounding-level probabilities as exactly 0 and 1") {
  // An analytic 0 and a simulated 1e-17 must leave the generator in the same state, or every
  // later count of the run would differ between the two oracles.
  qrm::estimation_result r1, r2;
  qrm::rng g1(8), g2(8);
  qrm::detail::shot_sampler s1(g1, false, r1), s2(g2, false, r2);
  CHECK(s1.hits(0.0, 1000) == 0);
  CHECK(s2.hits(1e-17, 1000) == 0);
  CHECK(s1.hits(1.0, 1000) == 1000);
  CHECK(s2.hits(1.0 - 1e-16, 1000) == 1000);
  CHECK(g1() == g2());
  // Exact mode returns shots * p without drawing.
  qrm::detail::shot_sampler e(g1, true, r1);
  CHECK(e.hits(0.25, 1000) == 250.0);
}

TEST_CASE("analytic and simulated oracles give identical counts for the same seed, for every estimator") {
  qrm::rng gp(2024);
  for (std::size_t n : {6, 8, 10}) {
    const auto e = qrm_test::random_real_problem(n, gp, n == 8);
    simulated sim(e);
    auto ana = qrm::analytic_oracle::from_problem<dense_real>(e);
    for (const std::string& name : qrm_test::estimator_names()) {
      INFO("estimator " << name << " n " << n << " a " << ana.amplitude());
      qrm::rng g1(77), g2(77);
      qrm::estimation_result rs, ra;
      rs = qrm_test::run_named(name, sim, g1, false, 0.05);
      ra = qrm_test::run_named(name, ana, g2, false, 0.05);
      REQUIRE(rs.rounds.size() == ra.rounds.size());
      for (std::size_t i = 0; i < rs.rounds.size(); ++i) {
        CHECK(rs.rounds[i].power == ra.rounds[i].power);
        CHECK(rs.rounds[i].hits == ra.rounds[i].hits);
      }
      CHECK(rs.phase_counts == ra.phase_counts);
      // Identical counts; the post-processing then sees a's that differ by ~1e-16 only where it
      // reads p_0 directly (canonical), so the estimates agree to far better than 1e-9.
      CHECK(rs.estimate == doctest::Approx(ra.estimate).epsilon(1e-9).scale(1));
      CHECK(rs.a_calls == ra.a_calls);
    }
  }
}

namespace {
// FAE transcribed directly from the FAE rules stated in fae.hpp's header in exact-probability mode: returns the theta
// interval, the raw estimate, and the A-call count.
struct fae_reference {
  double theta_lo, theta_hi, estimate;
  std::uint64_t calls;
};
fae_reference fae_from_spec(double a, double delta, int l, bool rescale) {
  const double prob = rescale ? a / 16 : a;
  const double theta = std::asin(std::sqrt(prob));
  const int N1 = int(std::floor(1944 * std::log(2 / delta))), N2 = int(std::floor(972 * std::log(2 / delta)));
  std::uint64_t calls = 0;
  auto c_of = [&](long k, int N) {
    calls += std::uint64_t(2 * k + 1) * std::uint64_t(N);
    return 1 - 2 * std::pow(std::sin((2 * k + 1) * theta), 2);  // c(k) = 1 - 2 p(k)
  };
  double tl = 0, th = std::asin(0.25), v = 0;
  bool stage1 = true;
  int j0 = l;
  for (int j = 1; j <= l; ++j) {
    const double Kj = std::pow(2.0, j + 1) + 2;
    if (stage1) {
      const double c = c_of(long(std::pow(2, j - 1)), N1);
      const double w = std::sqrt(12 * std::log(2 / delta) / N1);
      const double chi = std::min(1.0, c + w), clo = std::max(-1.0, c - w);
      tl = std::acos(chi) / Kj;
      th = std::acos(clo) / Kj;
      if (std::pow(2.0, j + 1) * th >= 3 * pi / 8 && j < l) {
        j0 = j;
        v = std::pow(2.0, j) * (tl + th);
        stage1 = false;
      }
    } else {
      const double c1 = c_of(long(std::pow(2, j - 1)), N2);
      const double c2 = c_of(long(std::pow(2, j - 1) + std::pow(2, j0 - 1)), N2);
      const double s = (c1 * std::cos(v) - c2) / std::sin(v);
      const double rho = std::atan2(s, c1);
      const double nn = std::trunc((Kj * th - rho + pi / 3) / (2 * pi));
      tl = (2 * pi * nn + rho - pi / 3) / Kj;
      th = (2 * pi * nn + rho + pi / 3) / Kj;
    }
  }
  const double mid = (tl + th) / 2;
  const double est = rescale ? std::pow(4 * std::sin(mid), 2) : std::pow(std::sin(mid), 2);
  return {tl, th, est, calls};
}
}  // namespace

TEST_CASE("FAE in exact mode matches a direct transcription of the FAE rules stated in fae.hpp's header") {
  int compared = 0;
  for (double a : {1e-5, 0.003, 0.05, 0.1, 0.2, 0.24, 0.3, 0.5, 0.77, 0.95, 0.999}) {
    for (double delta : {0.01, 0.05, 0.001}) {
      for (int l : {1, 2, 3, 5, 7}) {
        for (bool rescale : {false, true}) {
          if (!rescale && a > 0.25) continue;
          const auto ref = fae_from_spec(a, delta, l, rescale);
          qrm::analytic_oracle o(a);
          qrm::rng g(1);
          qrm::fae_options opt{delta, unsigned(l), rescale, true};
          const auto r = qrm::faster_amplitude_estimation(o, opt, g);
          INFO("a " << a << " delta " << delta << " l " << l << " rescale " << rescale);
          // Same formulas in the same order: agreement to rounding (1e-12 relative).
          CHECK(r.raw_estimate == doctest::Approx(ref.estimate).epsilon(1e-12));
          CHECK(r.estimate == doctest::Approx(std::min(1.0, ref.estimate)).epsilon(1e-12));
          CHECK(r.a_calls == ref.calls);
          // The interval is the clipped theta interval mapped through (scale sin)^2.
          const double tmax = rescale ? std::asin(0.25) : pi / 2, sc = rescale ? 4 : 1;
          auto map = [&](double t) { return t <= 0 ? 0.0 : t >= tmax ? 1.0 : std::pow(sc * std::sin(t), 2); };
          CHECK(r.confidence_interval[0] == doctest::Approx(map(ref.theta_lo)).epsilon(1e-12).scale(1e-300));
          CHECK(r.confidence_interval[1] == doctest::Approx(map(ref.theta_hi)).epsilon(1e-12).scale(1e-300));
          // Exact mode: the interval contains the truth.
          CHECK(r.confidence_interval[0] <= a);
          CHECK(a <= r.confidence_interval[1]);
          ++compared;
        }
      }
    }
  }
  CHECK(compared > 200);
}

TEST_CASE("FAE: the CLI reference case, and the shot counts of those rules") {
  // qrm estimate --estimator fae --probability 0.2 --delta 0.01 --maxiter 5 --no-rescale --exact-probabilities
  qrm::analytic_oracle o(0.2);
  qrm::rng g(1);
  const auto r = qrm::faster_amplitude_estimation(o, qrm::fae_options{0.01, 5, false, true}, g);
  const auto ref = fae_from_spec(0.2, 0.01, 5, false);
  CHECK(r.estimate == doctest::Approx(ref.estimate).epsilon(1e-14));
  // N1 = floor(1944 ln 200) = 10299, N2 = floor(972 ln 200) = 5149.
  REQUIRE(!r.rounds.empty());
  CHECK(r.rounds[0].shots == std::uint64_t(std::floor(1944 * std::log(200.0))));
  CHECK(r.rounds.back().shots == std::uint64_t(std::floor(972 * std::log(200.0))));
  std::uint64_t calls = 0;
  for (const auto& rr : r.rounds) calls += (2 * rr.power + 1) * rr.shots;
  CHECK(r.a_calls == calls);
  CHECK(r.check_a_calls == r.rounds[0].shots);
}

TEST_CASE("FAE without rescale refuses a > 1/4 instead of answering on the wrong branch") {
  qrm::rng g(3);
  qrm::analytic_oracle big(0.6);
  CHECK(error_of([&] {
          qrm::faster_amplitude_estimation(big, qrm::fae_options{0.01, 5, false, true}, g);
        }).find("at most 1/4") != std::string::npos);
  CHECK(error_of([&] {
          qrm::faster_amplitude_estimation(big, qrm::fae_options{0.01, 5, false, false}, g);
        }).find("enable rescale") != std::string::npos);
  // What it would otherwise have done: the first round cannot tell theta from its alias, and the
  // reference algorithm answers about 0.018 for a = 0.5.
  const auto alias = fae_from_spec(0.5, 0.01, 5, false);
  CHECK(std::fabs(alias.estimate - 0.5) > 0.4);
  // At a = 1/4 the k = 0 check cannot decide: either it refuses or it warns, never silence
  // (it refuses only if its interval lies wholly above 1/4, probability <= delta/2).
  qrm::analytic_oracle edge(0.25);
  std::string warning,
      error = error_of([&] {
        warning = qrm::faster_amplitude_estimation(edge, qrm::fae_options{0.01, 5, false, false}, g).warning;
      });
  CHECK((error != "(no error)" || !warning.empty()));
  // Well below 1/4: no warning (the check's interval would have to reach 5 sd above 0.2).
  qrm::analytic_oracle small(0.2);
  CHECK(qrm::faster_amplitude_estimation(small, qrm::fae_options{0.01, 5, false, false}, g).warning.empty());
  // With rescale, a > 1/4 is fine.
  const auto r = qrm::faster_amplitude_estimation(big, qrm::fae_options{0.01, 5, true, true}, g);
  CHECK(r.estimate == doctest::Approx(0.6).epsilon(0.01));
}

TEST_CASE(
    "hard cases: a in {0, 1e-12, 1e-6, 0.5, 1 - 1e-9, 1}, every estimator, exact and sampled, analytic and simulated") {
  // Sampled cells use alpha = 1e-5: with 4 random cells per estimator and oracle, 8 estimators and
  // 2 oracles, a correct set of intervals fails here with probability below 64 * 1e-5 < 1e-3
  // (the cells a = 0 and a = 1 are deterministic: p_k is exactly 0 or 1).
  const double cases[] = {0.0, 1e-12, 1e-6, 0.5, 1.0 - 1e-9, 1.0};
  for (double a : cases) {
    for (const std::string& name : qrm_test::estimator_names()) {
      for (bool exact : {true, false}) {
        for (bool sim : {false, true}) {
          INFO("a " << a << " estimator " << name << " exact " << exact << " simulated " << sim);
          qrm::rng g(1000 + static_cast<std::uint64_t>(a * 1e6));
          qrm::estimation_result r;
          if (sim) {
            simulated o(qrm::bernoulli_problem(a));
            r = qrm_test::run_named(name, o, g, exact, 1e-5);
          } else {
            qrm::analytic_oracle o(a);
            r = qrm_test::run_named(name, o, g, exact, 1e-5);
          }
          CHECK(std::isfinite(r.estimate));
          CHECK(std::isfinite(r.confidence_interval[0]));
          CHECK(std::isfinite(r.confidence_interval[1]));
          CHECK(r.estimate >= 0.0);
          CHECK(r.estimate <= 1.0);
          CHECK(r.confidence_interval[0] <= r.confidence_interval[1]);
          CHECK(r.confidence_interval[0] <= a);
          CHECK(a <= r.confidence_interval[1]);
          CHECK(r.warning.empty());
        }
      }
    }
    // FAE without rescale where it applies (a <= 1/4).
    if (a <= 0.25) {
      for (bool exact : {true, false}) {
        qrm::analytic_oracle o(a);
        qrm::rng g(5);
        const auto r = qrm::faster_amplitude_estimation(o, qrm::fae_options{1e-6, 5, false, exact}, g);
        CHECK(std::isfinite(r.estimate));
        CHECK(r.confidence_interval[0] <= a);
        CHECK(a <= r.confidence_interval[1]);
      }
    }
  }
}

TEST_CASE("exact-probability mode is deterministic and ignores the seed") {
  qrm::analytic_oracle o(0.3141);
  for (const std::string& name : qrm_test::estimator_names()) {
    qrm::rng g1(1), g2(999);
    const auto r1 = qrm_test::run_named(name, o, g1, true, 0.05), r2 = qrm_test::run_named(name, o, g2, true, 0.05);
    INFO(name);
    CHECK(r1.estimate == r2.estimate);
    CHECK(r1.confidence_interval == r2.confidence_interval);
    CHECK(r1.a_calls == r2.a_calls);
    CHECK(g1() != g2());  // and the generators were not needed to agree
  }
}

TEST_CASE("exact mode: the maximum-likelihood estimators recover a; the others are within their resolution") {
  for (double a : {0.013, 0.2, 0.5, 0.81}) {
    qrm::analytic_oracle o(a);
    qrm::rng g(1);
    INFO("a " << a);
    // Likelihood maximisers return the true theta when fed the exact law (Gibbs' inequality);
    // golden-section refinement resolves theta to ~1e-12.
    CHECK(qrm_test::run_named("mlae", o, g, true, 0.05).estimate == doctest::Approx(a).epsilon(1e-8));
    CHECK(qrm_test::run_named("canonical", o, g, true, 0.05).estimate == doctest::Approx(a).epsilon(1e-8));
    CHECK(qrm_test::run_named("mc", o, g, true, 0.05).estimate == doctest::Approx(a).epsilon(1e-14));
    // QCoin's inversion is exact when the head frequency is the exact probability.
    CHECK(qrm_test::run_named("qcoin", o, g, true, 0.05).estimate == doctest::Approx(a).epsilon(1e-12));
    // IQAE returns the middle of its final interval, half-width <= epsilon = 0.005.
    const auto iq = qrm_test::run_named("iqae", o, g, true, 0.05);
    CHECK(std::fabs(iq.estimate - a) <= 0.005);
    CHECK(iq.confidence_interval[1] - iq.confidence_interval[0] <= 2 * 0.005 + 1e-15);
  }
}

TEST_CASE("MLAE finds the right mode with large powers (staged search, no aliasing)") {
  // Powers up to 2^15: the fastest term has ~2e4 periods on [0, pi/2], more than one grid could
  // resolve. Exact mode must return a (golden-section precision), sampled mode must cover it.
  for (double a : {0.0123, 0.3, 0.8765}) {
    qrm::analytic_oracle o(a);
    qrm::mlae_options opt;
    opt.m = 16;
    opt.exact_probabilities = true;
    qrm::rng g(1);
    CHECK(qrm::maximum_likelihood_amplitude_estimation(o, opt, g).estimate == doctest::Approx(a).epsilon(1e-10));
    opt.exact_probabilities = false;
    opt.alpha = 1e-4;  // three sampled runs miss together with probability below 3e-4
    const auto r = qrm::maximum_likelihood_amplitude_estimation(o, opt, g);
    INFO("a " << a << " estimate " << r.estimate);
    CHECK(r.confidence_interval[0] <= a);
    CHECK(a <= r.confidence_interval[1]);
    CHECK(r.confidence_interval[1] - r.confidence_interval[0] < 1e-4);
  }
}

TEST_CASE("QCoin's estimate follows the authors' algorithm step by step (replayed from the recorded hits)") {
  // An independent transcription of the update rule of the authors' simulator code, fed with the
  // head counts the estimator recorded: it must choose the same references l and end at the same E.
  for (double a : {0.07, 0.3, 0.62, 0.97}) {
    for (std::uint64_t seed : {1, 2, 3}) {
      qrm::analytic_oracle o(a);
      qrm::rng g(seed);
      qrm::qcoin_options opt;
      opt.steps = 6;
      opt.shots_per_step = 40;
      const auto r = qrm::quantum_coin_estimation(o, opt, g);
      REQUIRE(r.rounds.size() == 6);
      const double L = 40;
      double E = r.rounds[0].hits / L;
      double delta = std::sin(pi / 2 / 2) / 2;
      double lower = std::max(0.0, E - delta), upper = std::min(1.0, E + delta);
      for (int k = 2; k <= 6; ++k) {
        const int n = 1 << (k - 2);
        delta = std::sin(pi / 2 / std::pow(2.0, k)) / 2;
        const double scale = std::sin(std::asin(upper - lower) * 2 * n);
        const auto& rr = r.rounds[k - 1];
        CHECK(rr.power == std::uint64_t(n));
        CHECK(rr.reference == doctest::Approx(lower).epsilon(1e-15));
        double e = std::sqrt(rr.hits / L);
        if (e > scale) e = scale;
        E = std::sin(std::asin(e) / (2.0 * n)) + lower;
        lower = std::max(lower, E - delta);
        upper = std::min(upper, E + delta);
      }
      INFO("a " << a << " seed " << seed);
      CHECK(r.estimate == doctest::Approx(E).epsilon(1e-14));
    }
  }
}

TEST_CASE("call counting: A applications 2k+1 and Q applications k per shot, for every estimator") {
  qrm::analytic_oracle o(0.37);
  for (const std::string& name : qrm_test::estimator_names()) {
    qrm::rng g(11);
    const auto r = qrm_test::run_named(name, o, g, false, 0.05);
    INFO(name);
    std::uint64_t a = 0, q = 0, shots = 0;
    for (const auto& rr : r.rounds) {
      shots += rr.shots;
      if (name == "qcoin" && rr.power > 0 && &rr != &r.rounds.front()) {
        a += 4 * rr.power * rr.shots;  // each coin iteration: C and C^dagger, each one A and one A^dagger
        q += rr.power * rr.shots;
      } else if (name == "canonical") {
        a += (2 * rr.power + 1) * rr.shots;  // power = M - 1 controlled Q's, plus the A itself
        q += rr.power * rr.shots;
      } else {
        a += (2 * rr.power + 1) * rr.shots;
        q += rr.power * rr.shots;
      }
    }
    CHECK(r.a_calls == a);
    CHECK(r.grover_calls == q);
    CHECK(r.shots == shots);
    CHECK(r.seconds >= 0.0);
  }
  qrm::rng g(1);
  const auto c = qrm::canonical_amplitude_estimation(o, qrm::canonical_options{4, 50, 0.05, false}, g);
  CHECK(c.a_calls == (2 * 16 - 1) * 50);
  CHECK(c.grover_calls == 15 * 50);
}

TEST_CASE("bad options name the problem and the value") {
  qrm::analytic_oracle o(0.3);
  qrm::rng g(1);
  CHECK(error_of([&] { qrm::analytic_oracle bad(1.5); }).find("1.5") != std::string::npos);
  CHECK(error_of([&] {
          qrm::faster_amplitude_estimation(o, qrm::fae_options{0.0, 5, true, false}, g);
        }).find("delta") != std::string::npos);
  CHECK(error_of([&] {
          qrm::faster_amplitude_estimation(o, qrm::fae_options{0.01, 0, true, false}, g);
        }).find("maxiter") != std::string::npos);
  qrm::iqae_options io;
  io.epsilon = 0.7;
  CHECK(error_of([&] { qrm::iterative_amplitude_estimation(o, io, g); }).find("epsilon") != std::string::npos);
  qrm::mlae_options mo;
  mo.alpha = 1.0;
  CHECK(error_of([&] { qrm::maximum_likelihood_amplitude_estimation(o, mo, g); }).find("alpha") != std::string::npos);
  qrm::qcoin_options qo;
  qo.shots_per_step = 0;
  CHECK(error_of([&] { qrm::quantum_coin_estimation(o, qo, g); }).find("shots") != std::string::npos);
  CHECK(error_of([&] {
          qrm::canonical_amplitude_estimation(o, qrm::canonical_options{0, 10, 0.05, false}, g);
        }).find("evaluation_qubits") != std::string::npos);
  qrm::estimation_problem e{qrm::program(2), {qrm::control{5, true}}};
  CHECK(error_of([&] { simulated s(e); }).find("qubit 5") != std::string::npos);
  CHECK(error_of([&] { qrm::coin_program(qrm::bernoulli_problem(0.5), 1.2); }).find("1.2") != std::string::npos);
}

TEST_CASE("radiance: value = estimate * S * emission_scale, the interval likewise") {
  qrm::estimation_result r;
  r.estimate = 0.125;
  r.confidence_interval = {0.1, 0.15};
  const auto v = qrm::to_radiance(r, 3, 2.0);
  CHECK(v.value == doctest::Approx(0.75));
  CHECK(v.confidence_interval[0] == doctest::Approx(0.6));
  CHECK(v.confidence_interval[1] == doctest::Approx(0.9));
  CHECK(error_of([&] { qrm::to_radiance(r, 0, 1); }).find("path_terms") != std::string::npos);
  CHECK(error_of([&] { qrm::to_radiance(r, 3, -1); }).find("emission_scale") != std::string::npos);
}

TEST_CASE("estimators on the SineIntegral circuit, simulated, agree with the truth") {
  // A few simulated runs (the many-seed statistics use analytic oracles, test_estimation_stats).
  const unsigned n = 5;
  const double truth = qrm::sine_integral_value(n);
  simulated o(qrm::sine_integral_problem(n));
  for (const std::string& name : {std::string("fae"), std::string("iqae"), std::string("mlae"), std::string("qcoin")}) {
    qrm::rng g(31);
    const auto r = qrm_test::run_named(name, o, g, false, 1e-4);
    INFO(name << " estimate " << r.estimate);
    // alpha = 1e-4 per run: four runs fail together with probability below 4e-4.
    CHECK(r.confidence_interval[0] <= truth);
    CHECK(truth <= r.confidence_interval[1]);
  }
}

TEST_CASE("the library rows of README's bad-input table: exact messages") {
  qrm::analytic_oracle o(0.3), half(0.5);
  qrm::rng g(1);
  CHECK(error_of([] { qrm::analytic_oracle bad(std::nan("")); }) ==
        "analytic_oracle: amplitude a must be in [0, 1], got nan");
  CHECK(error_of([&] { qrm::faster_amplitude_estimation(o, qrm::fae_options{0.0, 5, true, false}, g); }) ==
        "faster_amplitude_estimation: delta must be in (0, 1), got 0.000000");
  CHECK(error_of([&] { qrm::faster_amplitude_estimation(half, qrm::fae_options{0.01, 5, false, true}, g); }) ==
        "faster_amplitude_estimation: without rescale the amplitude must be at most 1/4, but P(good) = 0.500000; "
        "enable rescale");
  CHECK_THROWS_AS(qrm::faster_amplitude_estimation(half, qrm::fae_options{0.01, 5, false, true}, g), std::domain_error);
  try {  // the type callers catch to report in their own terms, with the bounds it found
    qrm::faster_amplitude_estimation(half, qrm::fae_options{0.01, 5, false, false}, g);
    FAIL("FAE without rescale ran on a = 0.5");
  } catch (const qrm::fae_above_quarter& e) {
    CHECK(e.shots == 10299);
    CHECK(e.low > 0.25);
    CHECK(e.low <= 0.5);
    CHECK(e.high >= 0.5);
  }
  const qrm::estimation_problem e{qrm::program(2), {qrm::control{5, true}}};
  CHECK(error_of([&] { simulated s(e); }) == "simulated_oracle: good condition on qubit 5 but A has 2 qubits");
  CHECK(error_of([] { qrm::to_radiance(qrm::estimation_result{}, 0.0); }) ==
        "to_radiance: path_terms S must be positive and finite, got 0.000000");
}
