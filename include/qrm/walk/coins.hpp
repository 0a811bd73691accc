// qrm/walk/coins.hpp: coin operators, the unitaries a voxel applies to the direction register.
//
// Column d of a coin is where direction d goes: U|d> = sum_r U[r][d] |r>. Kinds:
//   vacuum      identity (air: no gate at all)
//   lambertian  scatter into the outgoing hemisphere in superposition. 2D: the paper's +-1/2
//               matrix (as in the authors' code), incoming -> {n-2, n-1, n, n+1}, 1/4 each.
//               lambertian_coin_2d_symmetric: a real 2D coin symmetric about the normal.
//               3D: incoming -> equal magnitude over the outgoing set, made unitary with the
//               columns of a Hadamard matrix (real, Sylvester, when the outgoing set has 2^k
//               directions; otherwise the complex Fourier matrix).
//   boundary    reverse the direction (2D: d -> d xor 4, an X on the top direction qubit).
//   specular    mirror over the surface plane, snapped to the direction set as a permutation
//               (specular_coin below says how a mirrored direction outside the set is snapped).
//   glossy      a lobe around the mirror direction: G = B S, S the specular permutation and
//               B = exp(-i tau L) a unitary acting on the outgoing hemisphere only (glossy_coin).
//   medium      participating media: pass straight on with probability 1 - density, else scatter
//               isotropically to the other directions (medium_coin).
// Direction-register states beyond the set's D directions are left alone (identity).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "directions.hpp"
#include "../circuit/ops.hpp"
#include "scene.hpp"

namespace qrm {

// lambertian_coin_2d(n): the paper's 8x8 Lambertian coin for normal index n (the authors' +-1/2 matrix).
template <int = 0>
dense_matrix lambertian_coin_2d(int n) {
  if (n < 0 || n > 7) throw std::invalid_argument("lambertian_coin_2d: normal index must be 0..7, got " + std::to_string(n));
  auto mod8 = [](int v) { return ((v % 8) + 8) % 8; };
  const int par[2] = {mod8(n + 2), mod8(n - 2)};
  const int inc[3] = {mod8(n + 3), mod8(n + 4), mod8(n + 5)};
  const int out[3] = {n, mod8(n - 1), mod8(n + 1)};
  int m[8][8] = {};
  for (int i : out) {
    m[par[0]][i] = 1;
    m[i][par[1]] = 1;
    for (int j : inc) m[i][j] = 1;
  }
  for (int i : inc) {
    m[i][par[0]] = 1;
    m[par[1]][i] = 1;
    for (int j : out) m[i][j] = 1;
  }
  for (int i : par) m[i][i] = 1;
  // Signs: rows are "outgoing-type" (m[row][0] == 0) or "incoming-type"; the k-th row of each
  // type negates its nonzero entries whose ordinals are in neg[k].
  const std::vector<std::vector<int>> neg = {{2, 3}, {1, 3}, {1, 2}, {}};
  int seen_out = 0, seen_in = 0;
  for (int row = 0; row < 8; ++row) {
    const int k = m[row][0] == 0 ? seen_out++ : seen_in++;
    if (k >= 4) throw std::logic_error("lambertian_coin_2d: more than four rows of one type");
    int ordinal = 0;
    for (int col = 0; col < 8; ++col) {
      if (m[row][col] == 0) continue;
      if (std::find(neg[static_cast<std::size_t>(k)].begin(), neg[static_cast<std::size_t>(k)].end(), ordinal) !=
          neg[static_cast<std::size_t>(k)].end())
        m[row][col] = -m[row][col];
      ++ordinal;
    }
  }
  dense_matrix u(8);
  for (std::size_t r = 0; r < 8; ++r)
    for (std::size_t c = 0; c < 8; ++c) u(r, c) = 0.5 * m[r][c];
  return u;
}

// lambertian_coin_2d_symmetric(n): a real 8x8 Lambertian coin that keeps a mirror-symmetric scene's
// light map symmetric (the paper's coin is one-sided: incoming -> {n-2, n-1, n, n+1}). It commutes
// with the mirror about the normal, R(n+k) = n-k. Incoming (n+5, n+4, n+3) -> outgoing (n-1, n, n+1)
// through G = 2 v v^T - I (a negated Householder reflection), v = (a, b, a): G is symmetric,
// orthogonal, and unchanged by swapping its first and last index in rows and columns, which is R on
// both triples. b^2 = (1 + sqrt(p0)) / 2, a^2 = (1 - sqrt(p0)) / 4 make G's middle column
// (2ab, sqrt(p0), 2ab) the cosine lobe of the straight-in n+4: P(n) : P(n+-1) = cos 0 : cos 45 deg,
// so P(n) = p0 = sqrt(2) - 1 ~ 0.4142, P(n+-1) = 1 - 1/sqrt(2) ~ 0.2929. That forces the oblique n+3
// (real entries, mirror symmetry) to lean to one side; here to its specular direction n+1:
// ((1 + sqrt(p0)) / 2)^2 ~ 0.6753 to n+1, 1 - 1/sqrt(2) ~ 0.2929 to n, ((1 - sqrt(p0)) / 2)^2 ~ 0.0318
// to n-1 (n+5: the mirror image). The incoming columns fill the outgoing subspace, so outgoing inputs
// go back into the surface through G^T = G, (n-1, n, n+1) -> (n+5, n+4, n+3); tangent n+-2 stay put.
template <int = 0>
dense_matrix lambertian_coin_2d_symmetric(int n) {
  if (n < 0 || n > 7)
    throw std::invalid_argument("lambertian_coin_2d_symmetric: normal index must be 0..7, got " + std::to_string(n));
  auto dir = [n](int k) { return static_cast<std::size_t>(((n + k) % 8 + 8) % 8); };
  const double p0 = 1.0 / (1.0 + std::numbers::sqrt2);  // cos 0 / (cos 0 + 2 cos 45 deg)
  const double s = std::sqrt(p0);
  const double a = std::sqrt((1.0 - s) / 4.0), b = std::sqrt((1.0 + s) / 2.0);
  const double v[3] = {a, b, a};
  const int in[3] = {5, 4, 3}, out[3] = {-1, 0, 1};
  dense_matrix u(8);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      const double g = 2.0 * v[i] * v[j] - (i == j ? 1.0 : 0.0);
      u(dir(out[i]), dir(in[j])) = g;  // incoming -> outgoing: G
      u(dir(in[j]), dir(out[i])) = g;  // outgoing -> incoming: G^T
    }
  u(dir(2), dir(2)) = 1.0;
  u(dir(-2), dir(-2)) = 1.0;
  return u;
}

namespace detail {
// Greedy snap: among the sources not yet assigned and the targets not yet taken, pairs
// (d, t) are taken in order of increasing distance between image[d] and t (ties: lower d,
// then lower t), each source and each target used once. With as many free targets as free
// sources every source gets one, so a full pass is a bijection; and whenever image[d] is
// itself a free target, the pair at distance 0 is taken first, so the snap is exact there.
template <int = 0>
void greedy_snap(const direction_set& s, const std::vector<vec3>& image, const std::vector<std::size_t>& sources,
                 const std::vector<std::size_t>& targets, std::vector<std::size_t>& perm, std::vector<bool>& taken) {
  const std::size_t D = s.size();
  struct cand {
    double dist;
    std::size_t from, to;
  };
  std::vector<cand> all;
  for (std::size_t d : sources) {
    if (perm[d] != D) continue;
    const vec3& t = image[d];
    for (std::size_t e : targets) {
      if (taken[e]) continue;
      const vec3 diff{t[0] - s.vectors[e][0], t[1] - s.vectors[e][1], t[2] - s.vectors[e][2]};
      all.push_back({dot(diff, diff), d, e});
    }
  }
  std::sort(all.begin(), all.end(), [](const cand& a, const cand& b) {
    if (a.dist != b.dist) return a.dist < b.dist;
    return a.from != b.from ? a.from < b.from : a.to < b.to;
  });
  for (const cand& c : all)
    if (perm[c.from] == D && !taken[c.to]) {
      perm[c.from] = c.to;
      taken[c.to] = true;
    }
}

// image_of(s, f): f applied to every direction of s.
template <class F>
std::vector<vec3> image_of(const direction_set& s, F f) {
  std::vector<vec3> r;
  r.reserve(s.size());
  for (const vec3& v : s.vectors) r.push_back(f(v));
  return r;
}

// A permutation of the directions close to d -> image[d] (greedy_snap over all of them).
template <int = 0>
std::vector<std::size_t> snap_permutation(const direction_set& s, const std::vector<vec3>& image) {
  std::vector<std::size_t> all(s.size());
  for (std::size_t d = 0; d < s.size(); ++d) all[d] = d;
  std::vector<std::size_t> perm(s.size(), s.size());
  std::vector<bool> taken(s.size(), false);
  greedy_snap(s, image, all, all, perm, taken);
  return perm;
}

template <int = 0>
inline dense_matrix permutation_coin(const std::vector<std::size_t>& perm, std::size_t dim) {
  dense_matrix u(dim);
  for (std::size_t d = 0; d < dim; ++d) u(d < perm.size() ? perm[d] : d, d) = 1.0;
  return u;
}
}  // namespace detail

// boundary_coin(s): reverse every direction (d -> the direction nearest -d, as a permutation).
template <int = 0>
dense_matrix boundary_coin(const direction_set& s) {
  const auto reversed = detail::image_of(s, [](const vec3& v) { return vec3{-v[0], -v[1], -v[2]}; });
  const auto perm = detail::snap_permutation(s, reversed);
  return detail::permutation_coin(perm, std::size_t{1} << s.bits());
}

// What a Lambertian coin does with a direction set and a normal.
struct lambertian_split {
  std::vector<std::size_t> outgoing, incoming, others;  // others: tangent directions
  std::size_t grazing_counted_outgoing = 0;  // see lambertian_coin
};

// The outgoing / incoming split for normal n: d.n > 0 is outgoing, d.n < 0 incoming. A unitary
// needs |incoming| <= |outgoing|; when a set has more incoming directions for some normal
// (e.g. the 15-direction golden spiral), the directions closest to the surface plane (tangent
// ones first, then the least incoming) are counted as outgoing until it balances. That is
// reported in grazing_counted_outgoing; antipodal sets never need it.
template <int = 0>
lambertian_split split_hemisphere(const direction_set& s, const vec3& normal) {
  const vec3 n = normalized(normal);
  constexpr double eps = 1e-9;
  lambertian_split r;
  std::vector<std::pair<double, std::size_t>> rest;  // (d.n, d) for d.n <= eps
  for (std::size_t d = 0; d < s.size(); ++d) {
    const double c = dot(s.vectors[d], n);
    if (c > eps)
      r.outgoing.push_back(d);
    else
      rest.push_back({c, d});
  }
  // Most outgoing first; ties in index order (rest is built in index order).
  std::sort(rest.begin(), rest.end(),
            [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  std::size_t incoming_count = 0;
  for (const auto& [c, d] : rest) incoming_count += c < -eps ? 1 : 0;
  std::size_t next = 0;
  while (r.outgoing.size() < incoming_count && next < rest.size()) {
    if (rest[next].first < -eps) --incoming_count;
    r.outgoing.push_back(rest[next].second);
    ++r.grazing_counted_outgoing;
    ++next;
  }
  for (std::size_t i = next; i < rest.size(); ++i)
    (rest[i].first < -eps ? r.incoming : r.others).push_back(rest[i].second);
  std::sort(r.outgoing.begin(), r.outgoing.end());
  std::sort(r.incoming.begin(), r.incoming.end());
  std::sort(r.others.begin(), r.others.end());
  return r;
}

// lambertian_coin(s, n): incoming directions go to equal-magnitude superpositions of the
// outgoing ones; tangent directions and unused register states are left alone; outgoing
// directions take the remaining orthonormal columns (Gram-Schmidt in index order), as the 2D
// coin sends outgoing directions back into the surface to stay unitary.
template <int = 0>
dense_matrix lambertian_coin(const direction_set& s, const vec3& normal) {
  const lambertian_split sp = split_hemisphere(s, normal);
  const std::size_t dim = std::size_t{1} << s.bits();
  const std::size_t m = sp.outgoing.size();
  if (m == 0) throw std::invalid_argument("lambertian_coin: no outgoing direction for this normal");
  // Columns of an m x m Hadamard matrix (unimodular entries, orthogonal columns).
  const bool power_of_two = (m & (m - 1)) == 0;
  auto hadamard = [&](std::size_t j, std::size_t k) -> complex {
    if (power_of_two) return (std::popcount(j & k) % 2 == 0) ? 1.0 : -1.0;  // Sylvester
    return std::polar(1.0, 2.0 * std::numbers::pi * static_cast<double>(j * k) / static_cast<double>(m));
  };
  dense_matrix u(dim);
  std::vector<bool> column_done(dim, false);
  const double amp = 1.0 / std::sqrt(static_cast<double>(m));
  for (std::size_t k = 0; k < sp.incoming.size(); ++k) {
    for (std::size_t j = 0; j < m; ++j) u(sp.outgoing[j], sp.incoming[k]) = amp * hadamard(j, k);
    column_done[sp.incoming[k]] = true;
  }
  for (std::size_t t : sp.others) {
    u(t, t) = 1.0;
    column_done[t] = true;
  }
  for (std::size_t d = s.size(); d < dim; ++d) {
    u(d, d) = 1.0;
    column_done[d] = true;
  }
  // Outgoing columns: an orthonormal basis of what the incoming columns leave of
  // span(outgoing, incoming).
  std::vector<std::vector<complex>> basis;
  for (std::size_t k : sp.incoming) {
    std::vector<complex> v(dim);
    for (std::size_t r = 0; r < dim; ++r) v[r] = u(r, k);
    basis.push_back(v);
  }
  std::vector<std::size_t> candidates = sp.outgoing;
  candidates.insert(candidates.end(), sp.incoming.begin(), sp.incoming.end());
  std::size_t next_column = 0;
  for (std::size_t c : candidates) {
    if (next_column == sp.outgoing.size()) break;
    std::vector<complex> v(dim);
    v[c] = 1.0;
    for (int pass = 0; pass < 2; ++pass)  // twice: classical Gram-Schmidt loses orthogonality once
      for (const auto& b : basis) {
        complex proj{};
        for (std::size_t r = 0; r < dim; ++r) proj += std::conj(b[r]) * v[r];
        for (std::size_t r = 0; r < dim; ++r) v[r] -= proj * b[r];
      }
    double len = 0;
    for (const complex& z : v) len += std::norm(z);
    len = std::sqrt(len);
    if (len < 1e-8) continue;
    for (complex& z : v) z /= len;
    for (std::size_t r = 0; r < dim; ++r) u(r, sp.outgoing[next_column]) = std::abs(v[r]) < 1e-15 ? complex{} : v[r];
    column_done[sp.outgoing[next_column]] = true;
    ++next_column;
    basis.push_back(v);
  }
  if (next_column != sp.outgoing.size() || std::find(column_done.begin(), column_done.end(), false) != column_done.end())
    throw std::logic_error("lambertian_coin: could not complete the unitary");
  return u;
}

// specular_permutation(s, n): where the mirror over the plane with unit normal n sends each
// direction, as a permutation of the set. The exact mirror image r = d - 2 (d.n) n is often not
// in the set (golden spirals; cube sets with oblique normals); then d goes to the nearest free
// direction by the greedy snap (detail::greedy_snap: closest pairs first, each source and each
// target used once). Done in two passes so that a mirror never sends light into its surface:
// first the incoming directions of split_hemisphere(s, n) are snapped onto its outgoing ones
// (there are at least as many), then all the remaining directions onto the remaining ones. (One
// greedy pass over all directions sent 111 of 728 incoming directions of golden-64 into or along
// the surface over 23 normals; two passes send none, except where a set has more directions
// pointing in than out, where split_hemisphere counts the grazing ones as outgoing.) Greedy is
// not optimal: most directions land within a neighbour spacing of their mirror image, the last
// ones of a pass get what is left (golden-64: tens of degrees off for a few of them).
// Each pass assigns every source a distinct target, so the result is a bijection of the set:
// the coin is a permutation matrix, hence unitary (real, orthogonal) for any set and normal.
// Where the set is closed under the mirror (cube sets with axis normals; the 2D king moves
// with any of their 8 normals), every pair at distance 0 is taken first: the exact reflection.
template <int = 0>
std::vector<std::size_t> specular_permutation(const direction_set& s, const vec3& normal) {
  const vec3 n = normalized(normal);
  const std::vector<vec3> mirror = detail::image_of(s, [&](const vec3& v) {
    const double k = 2.0 * dot(v, n);
    return vec3{v[0] - k * n[0], v[1] - k * n[1], v[2] - k * n[2]};
  });
  const lambertian_split sp = split_hemisphere(s, n);
  std::vector<std::size_t> all(s.size());
  for (std::size_t d = 0; d < s.size(); ++d) all[d] = d;
  std::vector<std::size_t> perm(s.size(), s.size());
  std::vector<bool> taken(s.size(), false);
  detail::greedy_snap(s, mirror, sp.incoming, sp.outgoing, perm, taken);
  detail::greedy_snap(s, mirror, all, all, perm, taken);
  return perm;
}

// specular_coin(s, n): the mirror as a coin (the permutation above; unused register states kept).
template <int = 0>
inline dense_matrix specular_coin(const direction_set& s, const vec3& normal) {
  return detail::permutation_coin(specular_permutation(s, normal), std::size_t{1} << s.bits());
}

namespace detail {
// Eigen-decomposition of a real symmetric matrix (row-major, n x n) by cyclic Jacobi rotations:
// a = V diag(values) V^T, V orthogonal to rounding (each rotation is exactly orthogonal up to
// one rounding per entry). Small matrices only (a hemisphere of directions).
struct symmetric_eigen {
  std::vector<double> values;
  std::vector<double> vectors;  // column k is the eigenvector of values[k]; row-major n x n
};
template <int = 0>
symmetric_eigen jacobi_eigen(std::vector<double> a, std::size_t n) {
  std::vector<double> v(n * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) v[i * n + i] = 1.0;
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0, total = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) (i == j ? total : off) += a[i * n + j] * a[i * n + j];
    if (off <= 1e-30 * (total + off) || off == 0) break;
    for (std::size_t p = 0; p + 1 < n; ++p)
      for (std::size_t q = p + 1; q < n; ++q) {
        const double apq = a[p * n + q];
        if (apq == 0) continue;
        const double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
        for (std::size_t k = 0; k < n; ++k) {  // columns p, q of a
          const double akp = a[k * n + p], akq = a[k * n + q];
          a[k * n + p] = c * akp - sn * akq;
          a[k * n + q] = sn * akp + c * akq;
        }
        for (std::size_t k = 0; k < n; ++k) {  // rows p, q of a
          const double apk = a[p * n + k], aqk = a[q * n + k];
          a[p * n + k] = c * apk - sn * aqk;
          a[q * n + k] = sn * apk + c * aqk;
        }
        for (std::size_t k = 0; k < n; ++k) {
          const double vkp = v[k * n + p], vkq = v[k * n + q];
          v[k * n + p] = c * vkp - sn * vkq;
          v[k * n + q] = sn * vkp + c * vkq;
        }
      }
  }
  symmetric_eigen e;
  e.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) e.values[i] = a[i * n + i];
  e.vectors = std::move(v);
  return e;
}

// The angle between neighbouring directions of a set: the mean over directions of the angle to
// the nearest other one (cube-26: about 37 degrees; golden-64: about 26). The glossy coupling's
// angular scale, so that one lobe parameter means about the same spread in any set.
template <int = 0>
inline double neighbour_angle(const direction_set& s) {
  double sum = 0;
  for (std::size_t d = 0; d < s.size(); ++d) {
    double best = -2;
    for (std::size_t e = 0; e < s.size(); ++e)
      if (e != d) best = std::max(best, dot(s.vectors[d], s.vectors[e]));
    sum += std::acos(std::clamp(best, -1.0, 1.0));
  }
  return sum / static_cast<double>(s.size());
}
}  // namespace detail

// glossy_coin(s, n, tau): a glossy reflection. G = B S, S the specular permutation above and
// B = exp(-i tau L) on the outgoing directions O of split_hemisphere(s, n) (identity on every
// other direction and register state). L is the graph Laplacian of O with coupling weights
//     w(e, f) = exp(-(theta_ef / theta_0)^2),   e != f in O,
// theta_ef the angle between e and f and theta_0 the set's neighbour angle: L = diag(sum_f w)
// - w, real symmetric, so B is unitary (exactly, for any tau) and symmetric, and G is unitary
// as a product of unitaries. Physically B is the free Schroedinger evolution, for time tau, of
// a wave on the discrete outgoing hemisphere: a walker that S sends to the mirror direction m
// spreads to the neighbours of m, more the closer they are: for small tau
//     P(m -> e) = |B_em|^2 ~ tau^2 w(m, e)^2 = tau^2 exp(-2 (theta_me / theta_0)^2),
// a Gaussian lobe in angle around the mirror direction (as a Beckmann-like microfacet lobe),
// whose weight off the mirror direction grows with tau and whose width grows as tau carries the
// wave further; tau = 0 is the mirror. B is symmetric, so P(m -> e) = P(e -> m) (reciprocity).
// What the coin never does: send an incoming direction into the surface: S maps incoming
// directions into O and B keeps span(O). The lobe's mean cosine to the mirror direction falls
// monotonically from 1 at tau = 0 to glossy_lobe_max (tests/test_coins.cpp measures it; README
// "Materials" has the table): golden-64 (the CLI's default set) 0.96, 0.85, 0.71, 0.57 at tau =
// 1, 2, 3, 4; cube-26 0.92, 0.74, 0.52, 0.34. Beyond 4 the wave on the finite hemisphere starts
// to come back towards the mirror direction, so the lobe would narrow again.
template <int = 0>
dense_matrix glossy_coin(const direction_set& s, const vec3& normal, double tau) {
  if (!(tau >= 0.0 && tau <= glossy_lobe_max))
    throw std::invalid_argument("glossy_coin: lobe parameter must be in [0, " + std::to_string(glossy_lobe_max) +
                                "], got " + std::to_string(tau));
  const vec3 n = normalized(normal);
  const std::vector<std::size_t> perm = specular_permutation(s, n);
  const std::vector<std::size_t> out = split_hemisphere(s, n).outgoing;
  const std::size_t m = out.size(), dim = std::size_t{1} << s.bits();
  const double theta0 = detail::neighbour_angle(s);
  std::vector<double> lap(m * m, 0.0);
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < m; ++j) {
      if (i == j) continue;
      const double c = std::clamp(dot(s.vectors[out[i]], s.vectors[out[j]]), -1.0, 1.0);
      const double x = std::acos(c) / theta0, w = std::exp(-x * x);
      lap[i * m + j] = -w;
      lap[i * m + i] += w;
    }
  const detail::symmetric_eigen e = detail::jacobi_eigen(lap, m);
  // B on O: sum_k V_ik exp(-i tau lambda_k) V_jk.
  std::vector<complex> b(m * m);
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < m; ++j) {
      complex z{};
      for (std::size_t k = 0; k < m; ++k)
        z += e.vectors[i * m + k] * e.vectors[j * m + k] * std::polar(1.0, -tau * e.values[k]);
      b[i * m + j] = z;
    }
  std::vector<std::size_t> slot(dim, m);  // position of a direction in O, or m
  for (std::size_t i = 0; i < m; ++i) slot[out[i]] = i;
  dense_matrix u(dim);
  for (std::size_t d = 0; d < dim; ++d) {
    const std::size_t t = d < perm.size() ? perm[d] : d;
    if (slot[t] == m) {
      u(t, d) = 1.0;
      continue;
    }
    if (tau == 0.0) {  // exactly the mirror (the spectral sum would leave ~1e-16 elsewhere)
      u(t, d) = 1.0;
      continue;
    }
    for (std::size_t i = 0; i < m; ++i) u(out[i], d) = b[i * m + slot[t]];
  }
  return u;
}


namespace detail {
// A conference matrix of order n: C with zero diagonal, entries +-1 off it, C C^T = (n - 1) I;
// symmetric or antisymmetric. Built by Paley's construction when q = n - 1 is a prime power
// (C = [[0, 1^T], [+-1, Q]], Q_ab = chi(a - b) over GF(q), chi the quadratic character; q = 1
// mod 4 makes it symmetric, q = 3 mod 4 antisymmetric), else, for an antisymmetric one, by
// doubling one of order n / 2: [[C, C + I], [C - I, -C]]. Empty if neither applies.
struct conference_matrix {
  std::size_t n = 0;
  bool symmetric = false;
  std::vector<int> c;  // row-major n x n
};

// q = p^k with p prime, or (0, 0).
template <int = 0>
inline std::pair<unsigned, unsigned> prime_power(unsigned q) {
  if (q < 2) return {0, 0};
  unsigned p = 2;
  while (q % p != 0) ++p;
  unsigned k = 0, r = q;
  while (r % p == 0) {
    r /= p;
    ++k;
  }
  return r == 1 ? std::pair{p, k} : std::pair{0u, 0u};
}

// The quadratic character of GF(p^k) on the elements 0..q-1 (element = digits base p, the
// coefficients of a polynomial mod a monic irreducible of degree k, found by search: the first
// monic polynomial under which every nonzero element has an inverse).
template <int = 0>
std::vector<int> quadratic_character(unsigned p, unsigned k) {
  unsigned q = 1;
  for (unsigned i = 0; i < k; ++i) q *= p;
  auto digits = [&](unsigned a) {
    std::vector<unsigned> d(k);
    for (unsigned i = 0; i < k; ++i, a /= p) d[i] = a % p;
    return d;
  };
  auto mul = [&](unsigned a, unsigned b, const std::vector<unsigned>& modulus) {  // modulus: x^k = -sum m_i x^i
    const auto x = digits(a), y = digits(b);
    std::vector<unsigned> prod(2 * k, 0);
    for (unsigned i = 0; i < k; ++i)
      for (unsigned j = 0; j < k; ++j) prod[i + j] = (prod[i + j] + x[i] * y[j]) % p;
    for (unsigned t = 2 * k - 1; t >= k && t > 0; --t) {
      const unsigned top = prod[t];
      prod[t] = 0;
      for (unsigned i = 0; i < k; ++i) prod[t - k + i] = (prod[t - k + i] + (p - modulus[i]) * top) % p;
    }
    unsigned r = 0;
    for (unsigned i = k; i-- > 0;) r = r * p + prod[i];
    return r;
  };
  std::vector<unsigned> modulus(k, 0);
  for (unsigned m = 0; m < q; ++m) {
    for (unsigned i = 0, r = m; i < k; ++i, r /= p) modulus[i] = r % p;
    bool field = true;
    for (unsigned a = 1; a < q && field; ++a) {
      bool inverse = false;
      for (unsigned b = 1; b < q && !inverse; ++b) inverse = mul(a, b, modulus) == 1;
      field = inverse;
    }
    if (field) break;
  }
  std::vector<int> chi(q, -1);
  chi[0] = 0;
  for (unsigned y = 1; y < q; ++y) chi[mul(y, y, modulus)] = 1;
  return chi;
}

template <int = 0>
conference_matrix make_conference_matrix(std::size_t n) {
  conference_matrix r;
  if (n < 2) return r;
  const auto pk = prime_power(static_cast<unsigned>(n - 1));
  const unsigned p = pk.first, k = pk.second;  // not a structured binding: the lambda below captures them
  if (p != 0) {
    const unsigned q = static_cast<unsigned>(n - 1);
    const std::vector<int> chi = quadratic_character(p, k);
    auto sub = [&](unsigned a, unsigned b) {  // a - b digit-wise mod p
      unsigned out = 0, scale = 1;
      for (unsigned i = 0; i < k; ++i, a /= p, b /= p, scale *= p) out += ((a % p + p - b % p) % p) * scale;
      return out;
    };
    r.n = n;
    r.symmetric = q % 4 == 1;  // chi(-1) = 1 exactly when q = 1 mod 4 (q odd; q even fails the check below)
    r.c.assign(n * n, 0);
    for (unsigned a = 0; a < q; ++a) {
      r.c[a + 1] = 1;
      r.c[(a + 1) * n] = r.symmetric ? 1 : -1;
      for (unsigned b = 0; b < q; ++b) r.c[(a + 1) * n + b + 1] = chi[sub(a, b)];
    }
  } else if (n % 2 == 0) {
    const conference_matrix h = make_conference_matrix(n / 2);
    if (h.n == 0 || h.symmetric) return r;
    const std::size_t m = n / 2;
    r.n = n;
    r.symmetric = false;
    r.c.assign(n * n, 0);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t j = 0; j < m; ++j) {
        const int c = h.c[i * m + j], id = i == j ? 1 : 0;
        r.c[i * n + j] = c;
        r.c[i * n + j + m] = c + id;
        r.c[(i + m) * n + j] = c - id;
        r.c[(i + m) * n + j + m] = -c;
      }
  }
  if (r.n == 0) return r;
  // Checked rather than trusted (and Paley's Q fails it for even q): C C^T = (n - 1) I, zero
  // diagonal, nonzero elsewhere, the stated symmetry.
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      long dotp = 0;
      for (std::size_t t = 0; t < n; ++t) dotp += long{r.c[i * n + t]} * r.c[j * n + t];
      if (dotp != (i == j ? static_cast<long>(n - 1) : 0L) || (i == j) != (r.c[i * n + j] == 0) ||
          r.c[i * n + j] != (r.symmetric ? 1 : -1) * r.c[j * n + i])
        return conference_matrix{};  // not a conference matrix (e.g. Paley with q even)
    }
  return r;
}
}  // namespace detail

// medium_isotropic_limit(D): the largest density medium_coin reaches on a set of D directions:
// 1 when a conference matrix of order D exists (D = 6, 8, 14, 26, 32, 64, every set qrm offers
// but golden-15), else 4 (D - 1) / D^2 (0.249 for D = 15).
template <int = 0>
inline double medium_isotropic_limit(std::size_t count) {
  return detail::make_conference_matrix(count).n != 0
             ? 1.0
             : 4.0 * static_cast<double>(count - 1) / (static_cast<double>(count) * static_cast<double>(count));
}

// medium_coin(s, density): a participating medium's coin. With p = density, every direction d
// goes on straight with probability 1 - p and to each other direction with p / (D - 1)
// (isotropic scattering), |U_dd|^2 = 1 - p, |U_ed|^2 = p / (D - 1), exactly (up to rounding).
//   Conference construction (D = 6, 8, 14, 26, 32, 64 and any D with a conference matrix):
//     U = a I + i b H,  a = sqrt(1 - p), b = sqrt(p), H = C / sqrt(D - 1) (C symmetric) or
//     i C / sqrt(D - 1) (C antisymmetric), C a conference matrix of order D. H is Hermitian
//     with H^2 = I, so U^dagger U = (a^2 + b^2) I = I for every p in [0, 1]; the diagonal of H
//     is 0 and its other entries have modulus 1 / sqrt(D - 1). For antisymmetric C (D = 8, 32,
//     64: Paley with q = 3 mod 4, or doubling) U = a I - b C / sqrt(D - 1) is real; for
//     symmetric C (D = 6, 14, 26) it is complex and needs a complex backend.
//   Otherwise (odd D: a Hermitian H with H^2 = I and zero diagonal has trace 0, so D even):
//     U = I + beta J on the D directions (J all ones), |beta| = r = sqrt(p / (D - 1)) and
//     arg beta = psi with cos psi = -D r / 2: U^dagger U = I + (2 r cos psi + D r^2) J = I. It
//     needs D r / 2 <= 1, i.e. p <= 4 (D - 1) / D^2 (0.249 for golden-15); a larger density
//     throws (use an even set).
// p = 0 is the identity exactly. Register states beyond D are left alone.
template <int = 0>
dense_matrix medium_coin(const direction_set& s, double density) {
  const std::size_t D = s.size(), dim = std::size_t{1} << s.bits();
  if (!(density >= 0.0 && density <= 1.0))
    throw std::invalid_argument("medium_coin: density must be in [0, 1], got " + std::to_string(density));
  dense_matrix u(dim);
  for (std::size_t d = 0; d < dim; ++d) u(d, d) = 1.0;
  if (density == 0.0 || D < 2) return u;
  const detail::conference_matrix c = detail::make_conference_matrix(D);
  if (c.n == D) {
    const double a = std::sqrt(1.0 - density), h = std::sqrt(density / static_cast<double>(D - 1));
    for (std::size_t e = 0; e < D; ++e)
      for (std::size_t d = 0; d < D; ++d) {
        const double ced = static_cast<double>(c.c[e * D + d]);
        if (e == d)
          u(e, d) = a;
        else
          u(e, d) = c.symmetric ? complex(0.0, h * ced) : complex(-h * ced, 0.0);
      }
    return u;
  }
  const double limit = medium_isotropic_limit(D);
  if (density > limit)
    throw std::invalid_argument("medium_coin: density " + std::to_string(density) + " is above " +
                                std::to_string(limit) + ", the most this isotropic coin reaches on " +
                                std::to_string(D) + " directions (odd D has no conference matrix); use an even set");
  const double r = std::sqrt(density / static_cast<double>(D - 1));
  const double cos_psi = std::max(-1.0, -static_cast<double>(D) * r / 2.0);
  const complex beta = r * complex(cos_psi, std::sqrt(std::max(0.0, 1.0 - cos_psi * cos_psi)));
  for (std::size_t e = 0; e < D; ++e)
    for (std::size_t d = 0; d < D; ++d) u(e, d) = (e == d ? complex(1.0) : complex{}) + beta;
  return u;
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_COINS_INSTANCES(PREFIX)                                                    \
  PREFIX dense_matrix lambertian_coin_2d<0>(int);                                             \
  PREFIX dense_matrix lambertian_coin_2d_symmetric<0>(int);                                   \
  PREFIX dense_matrix boundary_coin<0>(const direction_set&);                                 \
  PREFIX lambertian_split split_hemisphere<0>(const direction_set&, const vec3&);             \
  PREFIX dense_matrix lambertian_coin<0>(const direction_set&, const vec3&);                  \
  PREFIX std::vector<std::size_t> specular_permutation<0>(const direction_set&, const vec3&); \
  PREFIX detail::symmetric_eigen detail::jacobi_eigen<0>(std::vector<double>, std::size_t);   \
  PREFIX dense_matrix glossy_coin<0>(const direction_set&, const vec3&, double);              \
  PREFIX std::vector<int> detail::quadratic_character<0>(unsigned, unsigned);                 \
  PREFIX detail::conference_matrix detail::make_conference_matrix<0>(std::size_t);            \
  PREFIX dense_matrix medium_coin<0>(const direction_set&, double);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_COINS_INSTANCES(extern template)
}  // namespace qrm
#endif
