// qrm/estimation/oracle.hpp: what an estimator asks the quantum computer.
//
// An estimator never touches a backend. It asks an oracle for p_k = P(good) in Q^k A|0> (and,
// for the quantum coin, for the head probability of a reference coin) and draws shots itself
// with qrm::binomial, so two oracles that agree on p_k give the same counts for the same seed.
//   analytic_oracle            p_k = sin^2((2k+1) theta), a = sin^2 theta, from a once-computed a
//   simulated_oracle<Backend>  applies Q^k A for real on a backend, continuing from Q^(k-1) A
//   with_simulated_oracle<F>   a simulated_oracle on the backend that family F picks for the problem
//   any_oracle                 any of them (or another amplitude_oracle) behind one type
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "../backends/backend.hpp"
#include "../circuit/program.hpp"
#include "grover.hpp"
#include "problem.hpp"

namespace qrm {

namespace detail {
// A probability read from a simulation may be off by rounding (-1e-16, 1 + 1e-16); anything
// further out (or NaN) is a bug upstream and is reported, never clamped silently.
template <int = 0>
inline double checked_probability(double p, const char* who) {
  constexpr double slack = 1e-9;
  if (!(p >= -slack && p <= 1.0 + slack))
    throw std::domain_error(std::string(who) + ": probability " + std::to_string(p) + " is outside [0, 1]");
  return std::clamp(p, 0.0, 1.0);
}

// theta in [0, pi/2] with sin^2 theta = a, computed stably: asin(sqrt a) loses relative accuracy
// near a = 1 (sqrt near 1 is flat), acos(sqrt(1 - a)) does not.
template <int = 0>
inline double amplitude_angle(double a) {
  a = std::clamp(a, 0.0, 1.0);
  return a <= 0.5 ? std::asin(std::sqrt(a)) : std::acos(std::sqrt(1.0 - a));
}

// sin^2((2k+1) theta).
template <int = 0>
inline double amplified_probability(double theta, std::uint64_t k) {
  const double s = std::sin((2.0 * static_cast<double>(k) + 1.0) * theta);
  return std::clamp(s * s, 0.0, 1.0);
}

// Head probability of the quantum coin with amplitude l - a after n coin iterations started from
// |0...0> (see qcoin.hpp): sin^2(2 n asin|l - a|).
template <int = 0>
inline double coin_head_probability(double a, double l, std::uint64_t n) {
  const double phi = std::asin(std::min(1.0, std::fabs(l - a)));
  const double s = std::sin(2.0 * static_cast<double>(n) * phi);
  return std::clamp(s * s, 0.0, 1.0);
}
}  // namespace detail

// amplitude_oracle: p_k for Q^k A, a rescaled copy (amplitude a * s^2), and coin probabilities.
template <class O>
concept amplitude_oracle = requires(O& o, const O& co, std::uint64_t k, double x) {
  { o.probability(k) } -> std::convertible_to<double>;
  { o.coin_probability(x, k) } -> std::convertible_to<double>;
  { co.rescaled(x) } -> std::convertible_to<O>;
};

// analytic_oracle: the closed form. Build it from a probability, or from a problem run once on a
// backend (that single run computes a; it is a calibration, not part of any estimator's count).
class analytic_oracle {
 public:
  explicit analytic_oracle(double a) : a_(validated(a)), theta_(detail::amplitude_angle(a_)) {}

  // From a problem: runs A once on make(width) and reads P(good).
  template <backend Backend, class Make>
  static analytic_oracle from_problem(const estimation_problem& e, Make make) {
    detail::check_good(e.good, e.a.width(), "analytic_oracle::from_problem");
    Backend b = make(e.a.width());
    run(b, e.a);
    return analytic_oracle(
        detail::checked_probability(b.probability(std::span<const control>(e.good)), "analytic_oracle::from_problem"));
  }
  template <backend Backend>
  static analytic_oracle from_problem(const estimation_problem& e) {
    return from_problem<Backend>(e, [](std::size_t n) { return Backend(n); });
  }

  double amplitude() const { return a_; }  // a = P(good) in A|0>
  double theta() const { return theta_; }
  double probability(std::uint64_t k) const { return detail::amplified_probability(theta_, k); }
  template <int = 0>
  analytic_oracle rescaled(double s) const {
    if (!(s > 0.0 && s <= 1.0))
      throw std::invalid_argument("analytic_oracle::rescaled: scale must be in (0, 1], got " + std::to_string(s));
    return analytic_oracle(a_ * s * s);
  }
  double coin_probability(double l, std::uint64_t n) const { return detail::coin_head_probability(a_, l, n); }

 private:
  template <int = 0>
  static double validated(double a) {
    if (!(a >= 0.0 && a <= 1.0))
      throw std::invalid_argument("analytic_oracle: amplitude a must be in [0, 1], got " + std::to_string(a));
    return a;
  }
  double a_;
  double theta_;
};

// simulated_oracle<Backend>: every Grover iteration applied on a backend made by `make(width)`
// (default: Backend(width)). p_k for growing k continues from the stored Q^(k-1) A state; a
// smaller k restarts from A|0>. Values already computed are remembered.
template <backend Backend>
class simulated_oracle {
 public:
  using factory = std::function<Backend(std::size_t)>;

  explicit simulated_oracle(
      estimation_problem e, factory make = [](std::size_t n) { return Backend(n); })
      : e_(std::move(e)), make_(std::move(make)) {
    detail::check_good(e_.good, e_.a.width(), "simulated_oracle");
    if (e_.a.width() == 0) throw std::invalid_argument("simulated_oracle: A has no qubits");
    grover_ = grover_operator(e_);
  }

  const estimation_problem& problem() const { return e_; }

  // P(good) in Q^k A|0>.
  double probability(std::uint64_t k) {
    if (auto it = cache_.find(k); it != cache_.end()) return it->second;
    if (!state_ || k < k_) {
      state_.reset();
      state_.emplace(make_(e_.a.width()));
      run(*state_, e_.a);
      k_ = 0;
      ++restarts_;
    }
    for (; k_ < k; ++k_) {
      run(*state_, grover_);
      ++iterations_;
    }
    const double p =
        detail::checked_probability(state_->probability(std::span<const control>(e_.good)), "simulated_oracle");
    cache_.emplace(k, p);
    return p;
  }

  // The same problem with a * s^2: A gets a real ancilla rotated by Ry(2 asin s).
  simulated_oracle rescaled(double s) const { return simulated_oracle(rescaled_problem(e_, s), make_); }

  // Head probability (leaving |0...0>) after n iterations of G = C S0 C^dagger S0 on |0...0>,
  // with C = coin_program(problem, l): every coin iteration simulated.
  double coin_probability(double l, std::uint64_t n) {
    const auto key = std::make_pair(l, n);
    if (auto it = coin_cache_.find(key); it != coin_cache_.end()) return it->second;
    const program g = coin_iteration(e_, l);
    const std::size_t w = g.width();
    Backend b = make_(w);
    for (std::uint64_t i = 0; i < n; ++i) {
      run(b, g);
      ++coin_iterations_;
    }
    std::vector<control> zero;
    for (qubit_index q = 0; q < w; ++q) zero.push_back({q, false});
    const double stay = detail::checked_probability(b.probability(std::span<const control>(zero)),
                                                    "simulated_oracle::coin_probability");
    const double p = 1.0 - stay;
    coin_cache_.emplace(key, p);
    return p;
  }

  // Bookkeeping for tests: Grover iterations and coin iterations really simulated, and restarts.
  std::uint64_t simulated_grover_iterations() const { return iterations_; }
  std::uint64_t simulated_coin_iterations() const { return coin_iterations_; }
  std::uint64_t restarts() const { return restarts_; }

 private:
  estimation_problem e_;
  factory make_;
  program grover_;
  std::optional<Backend> state_;
  std::uint64_t k_ = 0;
  std::uint64_t iterations_ = 0, coin_iterations_ = 0, restarts_ = 0;
  std::map<std::uint64_t, double> cache_;
  std::map<std::pair<double, std::uint64_t>, double> coin_cache_;
};

// with_simulated_oracle<F>(problem, f): f(oracle), the oracle a simulated_oracle on the backend
// that family F picks for the problem's A (real amplitudes when A is real), its states built by
// F::make.
template <backend_family F, class Fn>
auto with_simulated_oracle(const estimation_problem& e, Fn&& f) {
  return F::visit(e.a.width(), e.a.is_real(), [&](auto type) {
    using B = typename decltype(type)::type;
    simulated_oracle<B> oracle(e, [](std::size_t n) { return F::template make<B>(n); });
    return f(oracle);
  });
}

// any_oracle: any amplitude_oracle behind one type. Code that picks an oracle at run time (the
// renderer: ideal, noisy, ...) runs the estimators on this one type, so each estimator is compiled
// once and not once per oracle type. Copies share the oracle (and its caches).
template <int = 0>
class basic_any_oracle {
 public:
  template <class O>  // the first test keeps copies from checking amplitude_oracle<basic_any_oracle>
    requires(!std::same_as<std::remove_cvref_t<O>, basic_any_oracle> && amplitude_oracle<O>)
  explicit basic_any_oracle(O o) : self_(std::make_shared<held<O>>(std::move(o))) {}

  double probability(std::uint64_t k) { return self_->probability(k); }
  double coin_probability(double l, std::uint64_t n) { return self_->coin_probability(l, n); }
  basic_any_oracle rescaled(double s) const { return self_->rescaled(s); }

 private:
  struct base {
    virtual ~base() = default;
    virtual double probability(std::uint64_t) = 0;
    virtual double coin_probability(double, std::uint64_t) = 0;
    virtual basic_any_oracle rescaled(double) const = 0;
  };
  template <class O>
  struct held final : base {
    explicit held(O o) : oracle(std::move(o)) {}
    double probability(std::uint64_t k) override { return oracle.probability(k); }
    double coin_probability(double l, std::uint64_t n) override { return oracle.coin_probability(l, n); }
    basic_any_oracle rescaled(double s) const override { return basic_any_oracle(O(oracle.rescaled(s))); }
    O oracle;
  };
  std::shared_ptr<base> self_;
};

using any_oracle = basic_any_oracle<>;

}  // namespace qrm
