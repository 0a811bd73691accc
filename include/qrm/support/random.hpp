// qrm/support/random.hpp: a seeded, platform-independent random generator and the distributions qrm
// samples from (standard library distributions differ between implementations, so results
// would not be reproducible across compilers).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace qrm {

// rng: xoshiro256** seeded through splitmix64; `stream(seed, i)` gives independent generators
// for independent work items (pixels, cells), so results do not depend on scheduling.
class rng {
 public:
  using result_type = std::uint64_t;
  explicit rng(std::uint64_t seed = 0x5eed) { reseed(seed); }

  template <int = 0>
  static rng stream(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t x = seed ^ (0x9e3779b97f4a7c15ull * (index + 1));
    return rng(splitmix(x) ^ splitmix(x));
  }

  template <int = 0>
  void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& w : s_) w = splitmix(x);
  }

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }
  result_type operator()() {
    const std::uint64_t r = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return r;
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }
  // Uniform integer in [0, n) (n > 0), without modulo bias.
  template <int = 0>
  std::uint64_t below(std::uint64_t n) {
    if (n == 0) throw std::invalid_argument("rng::below: n must be positive");
    const std::uint64_t limit = max() - max() % n;
    for (;;) {
      const std::uint64_t r = (*this)();
      if (r < limit) return r % n;
    }
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  template <int = 0>
  static std::uint64_t splitmix(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::array<std::uint64_t, 4> s_{};
};

namespace detail {
// log(k!) without std::lgamma (which writes a global in glibc): exact sums below 256, Stirling's
// series (error < 1e-15 relative) above.
template <int = 0>
inline double log_factorial(std::uint64_t k) {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (std::size_t i = 1; i < t.size(); ++i) t[i] = t[i - 1] + std::log(static_cast<double>(i));
    return t;
  }();
  if (k < table.size()) return table[k];
  const double x = static_cast<double>(k) + 1.0;
  const double ix = 1.0 / x, ix2 = ix * ix;
  return (x - 0.5) * std::log(x) - x + 0.91893853320467274178 +
         ix * (1.0 / 12 - ix2 * (1.0 / 360 - ix2 * (1.0 / 1260 - ix2 / 1680)));
}
}  // namespace detail

// binomial(n, p, g): number of successes in n Bernoulli(p) trials (exact sampling: inversion for
// small n*p, Hormann's BTRS transformed rejection otherwise).
template <int = 0>
inline std::uint64_t binomial(std::uint64_t n, double p, rng& g) {
  if (!(p >= 0.0 && p <= 1.0))
    throw std::invalid_argument("binomial: probability must be in [0, 1], got " + std::to_string(p));
  if (n == 0 || p == 0.0) return 0;
  if (p == 1.0) return n;
  if (p > 0.5) return n - binomial(n, 1.0 - p, g);
  const double q = 1.0 - p;
  const double nd = static_cast<double>(n);
  if (nd * p < 10.0) {
    const double s = p / q, a = (nd + 1.0) * s;
    double r = std::pow(q, nd), u = g.uniform();
    std::uint64_t x = 0;
    while (u > r && x < n) {
      u -= r;
      ++x;
      r *= a / static_cast<double>(x) - s;
      if (r <= 0) break;
    }
    return x;
  }
  const double spq = std::sqrt(nd * p * q);
  const double b = 1.15 + 2.53 * spq;
  const double a = -0.0873 + 0.0248 * b + 0.01 * p;
  const double c = nd * p + 0.5;
  const double vr = 0.92 - 4.2 / b;
  const double alpha = (2.83 + 5.1 / b) * spq;
  const double lpq = std::log(p / q);
  const double m = std::floor((nd + 1.0) * p);
  const double h = detail::log_factorial(static_cast<std::uint64_t>(m)) +
                   detail::log_factorial(static_cast<std::uint64_t>(nd - m));
  for (;;) {
    const double u = g.uniform() - 0.5;
    double v = g.uniform();
    const double us = 0.5 - std::fabs(u);
    const double kd = std::floor((2.0 * a / us + b) * u + c);
    if (kd < 0.0 || kd > nd) continue;
    if (us >= 0.07 && v <= vr) return static_cast<std::uint64_t>(kd);
    v = std::log(v * alpha / (a / (us * us) + b));
    const auto k = static_cast<std::uint64_t>(kd);
    const double upper = h - detail::log_factorial(k) - detail::log_factorial(n - k) + (kd - m) * lpq;
    if (v <= upper) return k;
  }
}

}  // namespace qrm
