// qrm/backends/detail/dense_pairs.hpp: a 2x2 gate on qubit 0, 1 or 2 of a complex<float> state
// in float arithmetic (qrm::float_math::single_precision).
//
// On a low target t both amplitudes of a pair lie in one vector of floats: lane f is part f % 2
// (re, im) of the amplitude f / 2, whose row is bit t of f / 2, and its partner is lane f ^ P
// with P = 2^(t+1). Each output is
//   m_rr z + m_r,1-r (z with the pair's rows exchanged),
// and each complex product re(m) w + im(m) (w with re and im exchanged, sign folded into the
// coefficient), so a vector costs three lane shuffles (f ^ 1, f ^ P, f ^ P ^ 1) and four
// multiply-adds against per-lane coefficients, with no widening to double. (In double arithmetic the
// widening and the shuffles share one port; that kernel reached 1.15-1.25x the pair loop.)
//
// In double arithmetic with AVX2 (AVX-512 has the lane kernels of dense_lanes.hpp) on target 0 or
// 1, four amplitudes are widened as two registers of two complex doubles, the pairs' row-0
// amplitudes and their row-1 partners: each product is then one in-lane (re, im) swap and two
// multiplies, and the only shuffles are within the eight floats before widening and after.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "dense_batched.hpp"

namespace qrm::detail {

typedef float v8f __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));

// The per-lane coefficients of gate g on target t (0..2) for 16 lanes:
// out = a_re z + a_im (z ^ 1) + b_re (z ^ P) + b_im (z ^ P ^ 1), lanes indexed as above.
struct pair_coefficients {
  float a_re[16], a_im[16], b_re[16], b_im[16];

  template <int = 0>
  static pair_coefficients of(const gate1& g, unsigned t) {
    pair_coefficients c;
    for (unsigned f = 0; f < 16; ++f) {
      const unsigned row = (f / 2 >> t) & 1u, part = f % 2;
      const complex own = g.m[row][row], other = g.m[row][1 - row];
      const double sign = part == 0 ? -1.0 : 1.0;  // re out: re(m) re(z) - im(m) im(z)
      c.a_re[f] = static_cast<float>(own.real());
      c.a_im[f] = static_cast<float>(sign * own.imag());
      c.b_re[f] = static_cast<float>(other.real());
      c.b_im[f] = static_cast<float>(sign * other.imag());
    }
    return c;
  }
};

// out lane f = v lane f ^ X (by reference: a vector returned by value trips -Wpsabi).
template <unsigned X, class V, std::size_t... I>
[[gnu::always_inline]] inline void lanes_xor(const V& v, V& out, std::index_sequence<I...>) {
  out = __builtin_shufflevector(v, v, static_cast<int>(I ^ X)...);
}

// Applies the gate to the `count` amplitudes at p (a multiple of the vector's amplitudes);
// Partner = P, 2 * P <= the vector's lanes.
template <class V, unsigned Partner>
[[gnu::always_inline]] inline void low_target_pairs(float* p, std::uint64_t count, const pair_coefficients& c) {
  constexpr unsigned lanes = sizeof(V) / sizeof(float);
  constexpr auto seq = std::make_index_sequence<lanes>{};
  V ar, ai, br, bi;
  std::memcpy(&ar, c.a_re, sizeof ar);
  std::memcpy(&ai, c.a_im, sizeof ai);
  std::memcpy(&br, c.b_re, sizeof br);
  std::memcpy(&bi, c.b_im, sizeof bi);
  for (std::uint64_t f = 0; f < 2 * count; f += lanes) {
    V z;
    std::memcpy(&z, p + f, sizeof z);
    V z_ri, z_partner, z_partner_ri;
    lanes_xor<1>(z, z_ri, seq);
    lanes_xor<Partner>(z, z_partner, seq);
    lanes_xor<Partner | 1>(z, z_partner_ri, seq);
    const V out = ar * z + ai * z_ri + br * z_partner + bi * z_partner_ri;
    std::memcpy(p + f, &out, sizeof out);
  }
}

typedef float v4f __attribute__((vector_size(16)));
typedef double v4d __attribute__((vector_size(32)));

// The coefficients of gate g for two complex doubles per register, by output row r:
// out_r = own_re z_r + own_im (z_r, re and im exchanged) + other_re z_1-r + other_im (...).
struct widened_pair_coefficients {
  double own_re[2][4], own_im[2][4], other_re[2][4], other_im[2][4];

  template <int = 0>
  static widened_pair_coefficients of(const gate1& g) {
    widened_pair_coefficients c;
    for (unsigned r = 0; r < 2; ++r)
      for (unsigned l = 0; l < 4; ++l) {
        const double sign = l % 2 == 0 ? -1.0 : 1.0;  // re out: re(m) re(z) - im(m) im(z)
        c.own_re[r][l] = g.m[r][r].real();
        c.own_im[r][l] = sign * g.m[r][r].imag();
        c.other_re[r][l] = g.m[r][1 - r].real();
        c.other_im[r][l] = sign * g.m[r][1 - r].imag();
      }
    return c;
  }
};

#ifdef QRM_HAS_CPU_DISPATCH
// Applies the gate on target T (0 or 1) to the `count` amplitudes at p (a multiple of 4) in double
// arithmetic; each step's amplitudes k = 0..3 are two halves of four floats, row 0 those with bit T
// of k clear.
template <unsigned T>
[[gnu::always_inline]] inline void low_target_pairs_widened(float* p, std::uint64_t count,
                                                             const widened_pair_coefficients& c) {
  v4d own_re[2], own_im[2], other_re[2], other_im[2];
  std::memcpy(own_re, c.own_re, sizeof own_re);
  std::memcpy(own_im, c.own_im, sizeof own_im);
  std::memcpy(other_re, c.other_re, sizeof other_re);
  std::memcpy(other_im, c.other_im, sizeof other_im);
  for (std::uint64_t f = 0; f < 2 * count; f += 8) {
    v4f lo, hi, rows0, rows1;
    std::memcpy(&lo, p + f, sizeof lo);
    std::memcpy(&hi, p + f + 4, sizeof hi);
    if constexpr (T == 0) {
      rows0 = __builtin_shufflevector(lo, hi, 0, 1, 4, 5);
      rows1 = __builtin_shufflevector(lo, hi, 2, 3, 6, 7);
    } else {
      rows0 = lo;
      rows1 = hi;
    }
    v4d x, y;
    widen_four_floats(rows0, x);
    widen_four_floats(rows1, y);
    const v4d xs = __builtin_shufflevector(x, x, 1, 0, 3, 2), ys = __builtin_shufflevector(y, y, 1, 0, 3, 2);
    const v4f x_out = __builtin_convertvector(own_re[0] * x + own_im[0] * xs + other_re[0] * y + other_im[0] * ys, v4f);
    const v4f y_out = __builtin_convertvector(own_re[1] * y + own_im[1] * ys + other_re[1] * x + other_im[1] * xs, v4f);
    if constexpr (T == 0) {
      lo = __builtin_shufflevector(x_out, y_out, 0, 1, 4, 5);
      hi = __builtin_shufflevector(x_out, y_out, 2, 3, 6, 7);
    } else {
      lo = x_out;
      hi = y_out;
    }
    std::memcpy(p + f, &lo, sizeof lo);
    std::memcpy(p + f + 4, &hi, sizeof hi);
  }
}

template <int = 0>
__attribute__((target("avx2,fma"))) void low_target_pairs_widened_avx2(float* p, std::uint64_t count, unsigned t,
                                                                      const widened_pair_coefficients& c) {
  if (t == 0) low_target_pairs_widened<0>(p, count, c);
  else low_target_pairs_widened<1>(p, count, c);
}

// Target t at most 1 (AVX2) or 2 (AVX-512).
template <int = 0>
__attribute__((target("avx2,fma"))) void low_target_pairs_avx2(float* p, std::uint64_t count, unsigned t,
                                                              const pair_coefficients& c) {
  if (t == 0) low_target_pairs<v8f, 2>(p, count, c);
  else low_target_pairs<v8f, 4>(p, count, c);
}
template <int = 0>
__attribute__((target("avx512f"))) void low_target_pairs_avx512(float* p, std::uint64_t count, unsigned t,
                                                                const pair_coefficients& c) {
  if (t == 0) low_target_pairs<v16f, 2>(p, count, c);
  else if (t == 1) low_target_pairs<v16f, 4>(p, count, c);
  else low_target_pairs<v16f, 8>(p, count, c);
}
#endif

}  // namespace qrm::detail
