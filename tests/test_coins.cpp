// Coins: unitary for every direction set and normal, and they scatter as the paper says.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <qrm/walk/coins.hpp>
#include <qrm/walk/directions.hpp>
#include <qrm/support/random.hpp>

namespace {

// All tolerances: coin entries are built from a few arithmetic operations and one Gram-Schmidt
// pass in double precision, so U^dagger U = I holds to ~1e-15; 1e-12 is the bar.
constexpr double tol = 1e-12;

std::vector<qrm::vec3> test_normals(qrm::rng& g) {
  std::vector<qrm::vec3> ns = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 0}, {1, 1, 1}};
  for (int i = 0; i < 24; ++i) {
    qrm::vec3 v{2 * g.uniform() - 1, 2 * g.uniform() - 1, 2 * g.uniform() - 1};
    if (qrm::norm(v) > 0.1) ns.push_back(v);
  }
  for (auto& n : ns) n = qrm::normalized(n);
  return ns;
}

}  // namespace

TEST_CASE("the paper's 2D Lambertian coin: orthogonal, entries 0 or +-1/2, incoming -> {n-2..n+1} at 1/4") {
  for (int n = 0; n < 8; ++n) {
    const qrm::dense_matrix u = qrm::lambertian_coin_2d(n);
    CHECK(qrm::unitarity_error(u) < tol);
    CHECK(u.is_real());
    for (const auto& z : u.data) CHECK((z == qrm::complex(0.0) || std::abs(std::abs(z.real()) - 0.5) < 1e-15));
    const int incoming = (n + 4) % 8;
    std::set<int> expected = {(n + 6) % 8, (n + 7) % 8, n, (n + 1) % 8};
    for (int r = 0; r < 8; ++r) {
      const double p = std::norm(u(static_cast<std::size_t>(r), static_cast<std::size_t>(incoming)));
      CHECK(p == doctest::Approx(expected.count(r) ? 0.25 : 0.0));
    }
  }
}

namespace {

std::size_t dir2d(int n, int k) { return static_cast<std::size_t>(((n + k) % 8 + 8) % 8); }

// Largest | |U[R r][R d]|^2 - |U[r][d]|^2 | over r, d, with R(n+k) = n-k the mirror about normal n.
double mirror_asymmetry(const qrm::dense_matrix& u, int n) {
  double worst = 0;
  for (int r = 0; r < 8; ++r)
    for (int d = 0; d < 8; ++d) {
      const double p = std::norm(u(dir2d(n, r - n), dir2d(n, d - n)));
      const double mirrored = std::norm(u(dir2d(n, n - r), dir2d(n, n - d)));
      worst = std::max(worst, std::abs(mirrored - p));
    }
  return worst;
}

}  // namespace

TEST_CASE("the symmetric 2D Lambertian coin: orthogonal, mirror symmetric, incoming -> a cosine lobe on {n-1, n, n+1}") {
  // The straight-in lobe, from the cosines alone: P(n) : P(n+-1) = cos 0 : cos 45 deg, summing to 1.
  const double c0 = std::cos(0.0), c45 = std::cos(std::numbers::pi / 4);
  const double p_normal = c0 / (c0 + 2 * c45), p_side = c45 / (c0 + 2 * c45);
  CHECK(std::abs(p_normal - 0.41421356237309503) < 1e-15);
  CHECK(std::abs(p_side - 0.29289321881345248) < 1e-15);
  for (int n = 0; n < 8; ++n) {
    INFO("normal index " << n);
    const qrm::dense_matrix u = qrm::lambertian_coin_2d_symmetric(n);
    CHECK(u.dim == 8);
    CHECK(qrm::unitarity_error(u) < tol);
    CHECK(u.is_real());
    CHECK(mirror_asymmetry(u, n) < tol);
    // Incoming n+3, n+4, n+5 reach only the outgoing n-1, n, n+1 (all of the probability).
    for (int k : {3, 4, 5}) {
      double outgoing = 0;
      for (int r = 0; r < 8; ++r) {
        const double p = std::norm(u(dir2d(n, r), dir2d(n, k)));
        if (r == 7 || r == 0 || r == 1)
          outgoing += p;
        else
          CHECK(p == 0.0);
      }
      CHECK(std::abs(outgoing - 1.0) < tol);
    }
    const auto p_from = [&](int k_in, int k_out) { return std::norm(u(dir2d(n, k_out), dir2d(n, k_in))); };
    CHECK(std::abs(p_from(4, 0) - p_normal) < tol);
    CHECK(std::abs(p_from(4, 1) - p_side) < tol);
    CHECK(std::abs(p_from(4, -1) - p_side) < tol);
    // The oblique n+3 is forced to P(n) = p_side too, and leans to its specular direction n+1.
    CHECK(std::abs(p_from(3, 0) - p_side) < tol);
    CHECK(p_from(3, 1) > 0.6);
    CHECK(p_from(3, -1) < 0.05);
    // Outgoing inputs go back into the surface (n+3..n+5), tangent directions are left alone.
    for (int k : {-1, 0, 1}) {
      double incoming = 0;
      for (int r : {3, 4, 5}) incoming += p_from(k, r);
      CHECK(std::abs(incoming - 1.0) < tol);
    }
    CHECK(u(dir2d(n, 2), dir2d(n, 2)) == qrm::complex(1.0));
    CHECK(u(dir2d(n, -2), dir2d(n, -2)) == qrm::complex(1.0));
    // What this coin is for: the paper's coin is one-sided about the normal.
    CHECK(mirror_asymmetry(qrm::lambertian_coin_2d(n), n) > 0.2);
  }
  CHECK_THROWS_WITH(qrm::lambertian_coin_2d_symmetric(8), doctest::Contains("0..7, got 8"));
  CHECK_THROWS_WITH(qrm::lambertian_coin_2d_symmetric(-1), doctest::Contains("0..7, got -1"));
}

TEST_CASE("2D boundary and specular coins are the expected permutations") {
  const auto king = qrm::king_2d();
  const qrm::dense_matrix b = qrm::boundary_coin(king);
  for (std::size_t d = 0; d < 8; ++d) CHECK(b(d ^ 4u, d) == qrm::complex(1.0));  // X on the top direction qubit
  for (int n = 0; n < 8; ++n) {
    const auto dv = king.vectors[static_cast<std::size_t>(n)];
    const qrm::dense_matrix s = qrm::specular_coin(king, dv);
    CHECK(qrm::unitarity_error(s) < tol);
    for (int d = 0; d < 8; ++d) {
      // Mirror over the surface plane of normal n: d -> (2n + 4 - d) mod 8.
      const int mirrored = ((2 * n + 4 - d) % 8 + 8) % 8;
      CHECK(s(static_cast<std::size_t>(mirrored), static_cast<std::size_t>(d)) == qrm::complex(1.0));
    }
  }
}

TEST_CASE("3D coins are unitary for D in {6, 14, 15, 26, 32} and many normals") {
  qrm::rng g(77);
  const auto normals = test_normals(g);
  for (std::size_t D : {6u, 14u, 15u, 26u, 32u}) {
    const qrm::direction_set s = qrm::sphere_directions(D, 3);
    CHECK(s.size() == D);
    CHECK(qrm::unitarity_error(qrm::boundary_coin(s)) < tol);
    std::size_t grazing_cases = 0;
    for (const auto& n : normals) {
      INFO("D = " << D << " normal (" << n[0] << ", " << n[1] << ", " << n[2] << ")");
      const qrm::dense_matrix u = qrm::lambertian_coin(s, n);
      CHECK(u.dim == (std::size_t{1} << s.bits()));
      CHECK(qrm::unitarity_error(u) < tol);
      CHECK(qrm::unitarity_error(qrm::specular_coin(s, n)) < tol);
      // Every incoming direction goes to an equal-magnitude superposition of the outgoing set.
      const auto split = qrm::split_hemisphere(s, n);
      CHECK(split.incoming.size() <= split.outgoing.size());
      grazing_cases += split.grazing_counted_outgoing > 0;
      for (std::size_t i : split.incoming) {
        double total = 0;
        for (std::size_t r = 0; r < u.dim; ++r) {
          const double p = std::norm(u(r, i));
          const bool outgoing = std::find(split.outgoing.begin(), split.outgoing.end(), r) != split.outgoing.end();
          CHECK(p == doctest::Approx(outgoing ? 1.0 / double(split.outgoing.size()) : 0.0).epsilon(1e-12));
          total += p;
        }
        CHECK(total == doctest::Approx(1.0));
        // Truly incoming: the direction points into the surface.
        CHECK(qrm::dot(s.vectors[i], n) < 0);
      }
      // Tangent directions and unused register states are untouched.
      for (std::size_t t : split.others) CHECK(u(t, t) == qrm::complex(1.0));
      for (std::size_t d = D; d < u.dim; ++d) CHECK(u(d, d) == qrm::complex(1.0));
    }
    // Symmetric (antipodal) sets never need grazing directions counted as outgoing.
    if (D == 6 || D == 14 || D == 26) CHECK(grazing_cases == 0);
  }
}

TEST_CASE("antipodal sets reverse exactly, and displacements move about one voxel") {
  for (std::size_t D : {6u, 14u, 26u}) {
    const auto s = qrm::cube_directions(D, 3);
    const auto b = qrm::boundary_coin(s);
    for (std::size_t d = 0; d < D; ++d)
      for (std::size_t r = 0; r < D; ++r)
        if (b(r, d) != qrm::complex(0.0)) CHECK(qrm::dot(s.vectors[r], s.vectors[d]) == doctest::Approx(-1.0));
  }
  const auto a = qrm::antipodal_spiral(32, 3);
  for (std::size_t d = 0; d < 16; ++d) CHECK(qrm::dot(a.vectors[d], a.vectors[d + 16]) == doctest::Approx(-1.0));
  const auto g = qrm::golden_spiral(15, 3);
  for (std::size_t d = 0; d < 15; ++d) {
    const auto& dp = g.displacement[d];
    const double len = std::sqrt(double(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2])) / 8.0;
    // Rounding each axis to 1/8 voxel changes the length by at most sqrt(3)/16 ~ 0.11.
    CHECK(std::abs(len - 1.0) < 0.11);
  }
  CHECK_THROWS_WITH(qrm::cube_directions(7), doctest::Contains("6, 14 or 26"));
  CHECK_THROWS_WITH(qrm::antipodal_spiral(15), doctest::Contains("even"));
  CHECK_THROWS_WITH(qrm::lambertian_coin_2d(8), doctest::Contains("0..7, got 8"));
}
