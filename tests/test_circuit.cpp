// Circuits on the dense backend: composition, adjoints, uniform preparation, programs, the
// Path-gate identity P(out=1) = E[f]/S, and run-time errors that name the problem.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <string>

#include <qrm/qrm.hpp>

#include "support/errors.hpp"
#include "support/backends.hpp"
#include "support/random_ops.hpp"

using qrm_test::error_of;

namespace {
using x = qrm::position<"x", 3>;
using dir = qrm::direction<3>;
using le = qrm::emission<3>;
using rho = qrm::reflectance<2>;
using stp = qrm::steps<2>;
using out = qrm::output<>;
using L = qrm::layout<x, dir, le, rho, stp, out>;

double ry_angle(double v) { return 2.0 * std::asin(std::sqrt(v)); }

}  // namespace

TEST_CASE("a circuit followed by its adjoint is the identity") {
  const auto c = qrm::make_circuit<L>(
      qrm::h<dir>{}, qrm::increment<x, qrm::when<dir, 3>>{}, qrm::add<x, -3, qrm::when<dir, 5>>{},
      qrm::ry<qrm::bit<le, 0>, qrm::off<qrm::bit<x, 2>>>{0.4}, qrm::phase<out, qrm::on<qrm::bit<dir, 1>>>{0.9},
      qrm::mux_ry<qrm::bit<le, 1>, x>{{1, 0.3}, {6, 1.2}}, qrm::prepare_uniform<stp, 3>{},
      qrm::unitary<qrm::qubits<qrm::bit<rho, 0>, qrm::bit<rho, 1>>>{qrm_test::random_unitary(2, *std::make_unique<qrm::rng>(3), true)});
  qrm::state_vector<std::complex<double>> s(L::width);
  qrm::run(s, c);
  CHECK(std::abs(s.amplitude(0)) < 0.9);  // the circuit did something
  qrm::run(s, c.adjoint());
  // Each gate and its inverse contribute a rounding of order 1e-16 per amplitude.
  CHECK(std::abs(s.amplitude(0) - 1.0) < 1e-12);
}

TEST_CASE("prepare_uniform gives 1/M on the first M values, and its adjoint undoes it") {
  for (std::uint64_t m = 1; m <= 4; ++m) {
    qrm::state_vector<double> s(L::width);
    auto run_m = [&](auto prep) {
      qrm::run(s, qrm::make_circuit<L>(prep));
      const auto p = qrm::distribution<L, stp>(s);
      for (std::uint64_t v = 0; v < 4; ++v) CHECK(p[v] == doctest::Approx(v < m ? 1.0 / double(m) : 0.0).epsilon(1e-12));
      qrm::run(s, qrm::make_circuit<L>(prep.adjoint()));
      CHECK(s.amplitude(0) == doctest::Approx(1.0).epsilon(1e-12));
    };
    switch (m) {
      case 1: run_m(qrm::prepare_uniform<stp, 1>{}); break;
      case 2: run_m(qrm::prepare_uniform<stp, 2>{}); break;
      case 3: run_m(qrm::prepare_uniform<stp, 3>{}); break;
      default: run_m(qrm::prepare_uniform<stp, 4>{}); break;
    }
  }
  // Larger registers, every count: the amplitudes themselves are 1/sqrt(M), not only |.|^2.
  using big = qrm::ancilla<"big", 4>;
  using LB = qrm::layout<big>;
  auto check = [](auto prep, std::uint64_t m) {
    qrm::state_vector<double> s(4);
    qrm::run(s, qrm::make_circuit<LB>(prep));
    for (std::uint64_t v = 0; v < 16; ++v) CHECK(s.amplitude(v) == doctest::Approx(v < m ? 1.0 / std::sqrt(double(m)) : 0.0).epsilon(1e-12));
  };
  check(qrm::prepare_uniform<big, 5>{}, 5);
  check(qrm::prepare_uniform<big, 11>{}, 11);
  check(qrm::prepare_uniform<big, 16>{}, 16);
}

TEST_CASE("the Path gate: P(out=1) = (1/S) sum_i Le_i prod_{k<i} rho_k for product inputs") {
  // Amplitude-encode Le_i and rho_k, then apply the Path gate of the paper (Fig. 3).
  const double Le[3] = {0.2, 0.7, 0.5}, Rho[2] = {0.6, 0.9};
  const auto c = qrm::make_circuit<L>(
      qrm::ry<qrm::bit<le, 0>>{ry_angle(Le[0])}, qrm::ry<qrm::bit<le, 1>>{ry_angle(Le[1])},
      qrm::ry<qrm::bit<le, 2>>{ry_angle(Le[2])}, qrm::ry<qrm::bit<rho, 0>>{ry_angle(Rho[0])},
      qrm::ry<qrm::bit<rho, 1>>{ry_angle(Rho[1])}, qrm::prepare_uniform<stp, 3>{},
      qrm::x<out, qrm::when<stp, 0>, qrm::on<qrm::bit<le, 0>>>{},
      qrm::x<out, qrm::when<stp, 1>, qrm::on<qrm::bit<le, 1>>, qrm::on<qrm::bit<rho, 0>>>{},
      qrm::x<out, qrm::when<stp, 2>, qrm::on<qrm::bit<le, 2>>, qrm::on<rho>>{});
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
  const double expected = (Le[0] + Le[1] * Rho[0] + Le[2] * Rho[0] * Rho[1]) / 3.0;
  CHECK(qrm::probability<L, qrm::on<out>>(s) == doctest::Approx(expected).epsilon(1e-13));
}

TEST_CASE("a recorded program replays to the same state and inverts") {
  const auto c = qrm::make_circuit<L>(qrm::h<dir>{}, qrm::increment<x, qrm::when<dir, 1>>{},
                                      qrm::mux_ry<out, dir>{{0, 0.1}, {1, 0.2}, {7, 3.0}}, qrm::prepare_uniform<stp, 3>{});
  const qrm::program p = qrm::program::from(c);
  CHECK(p.width() == L::width);
  CHECK(p.registers().size() == 6);
  CHECK(p.is_real());
  qrm::state_vector<double> a(L::width), b(L::width);
  qrm::run(a, c);
  qrm::run(b, p);
  CHECK(qrm_test::max_diff(qrm_test::backend_traits<qrm::state_vector<double>>::dump(a),
                           qrm_test::backend_traits<qrm::state_vector<double>>::dump(b)) == 0.0);
  qrm::run(b, p.adjoint());
  CHECK(b.amplitude(0) == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("unroll builds steps that differ by a compile-time index") {
  const auto steps = qrm::unroll<3>([](auto i) { return qrm::x<qrm::bit<le, decltype(i)::value>>{}; });
  const auto c = qrm::make_circuit<L>(steps);
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
  CHECK(qrm::probability<L, qrm::on<le>>(s) == 1.0);
  static_assert(decltype(c)::depth_bound == 1);
}

TEST_CASE("run-time errors name the problem") {
  qrm::state_vector<double> s(4);
  const qrm::control c5{5, true};
  CHECK(error_of([&] { s.apply_gate1(qrm::gate::x(), 7, {}); }).find("qubit 7 is outside the 4-qubit state") != std::string::npos);
  CHECK(error_of([&] { s.apply_gate1(qrm::gate::x(), 0, std::span<const qrm::control>(&c5, 1)); })
            .find("control qubit 5") != std::string::npos);
  const qrm::control c0{0, true};
  CHECK(error_of([&] { s.apply_gate1(qrm::gate::x(), 0, std::span<const qrm::control>(&c0, 1)); })
            .find("used twice") != std::string::npos);
  CHECK(error_of([&] { s.apply_gate1(qrm::gate::phase(0.1), 0, {}); }).find("complex_gate_needs_complex_backend") !=
        std::string::npos);
  CHECK(error_of([] { qrm::ry<out>{std::nan("")}; }).find("ry: angle must be finite") != std::string::npos);
  qrm::dense_matrix bad = qrm::dense_matrix::identity(4);
  bad(0, 0) = 2.0;
  CHECK(error_of([&] { qrm::real_unitary<qrm::slice<dir, 0, 2>> u{bad}; }).find("not unitary") != std::string::npos);
  CHECK(error_of([&] { qrm::real_unitary<dir> u{qrm::dense_matrix::identity(4)}; }).find("matrix is 4x4 but the targets need 8x8") !=
        std::string::npos);
  CHECK(error_of([] { qrm::mux_ry<out, dir>{{9, 0.1}}; }).find("select value 9 does not fit 3 select qubits") !=
        std::string::npos);
  // Programs and run: messages formatted with snprintf (detail::throw_formatted) keep their numbers.
  qrm::program six(6);
  CHECK(error_of([&] { six.apply_gate1(qrm::gate::x(), 9, {}); })
            .find("program: op uses qubit 9 but the program has 6 qubits") != std::string::npos);
  qrm::program phased(1);
  phased.apply_gate1(qrm::gate::x(), 0, {});
  phased.apply_gate1(qrm::gate::phase(0.1), 0, {});
  CHECK(error_of([&] { qrm::run(s, phased); }).find("run: op 1 has a complex matrix") != std::string::npos);
  CHECK(error_of([] { qrm::add_value<dir>{9}; }).find("add_value: constant 9 does not fit a 3-qubit register") !=
        std::string::npos);
  CHECK(error_of([] { qrm::state_vector<std::complex<double>>(40); }).find("40 qubits of complex<double> need 16 TiB") !=
        std::string::npos);
  qrm::dense_options small;
  small.max_bytes = 1024;
  CHECK(error_of([&] { qrm::state_vector<double>(10, small); }).find("need 8 KiB, more than the 1 KiB allowed") !=
        std::string::npos);
  CHECK(error_of([] { qrm::state_vector<double>(70); }).find("70 qubits") != std::string::npos);
  qrm::program wide(30);
  CHECK(error_of([&] { qrm::run(s, wide); }).find("needs 30 qubits but the backend has 4") != std::string::npos);
}

namespace {
// Registers whose width a scene file decides: the same names and roles, width dynamic_width.
using dyn_x = qrm::position<"x", qrm::dynamic_width>;
using dyn_dir = qrm::direction<qrm::dynamic_width>;
using DL = qrm::layout<out, dyn_dir, dyn_x>;
using SL = qrm::layout<out, dir, x>;

// What needs a constant width refuses a dynamic register (requires !requires style).
static_assert(qrm::dynamic_register<dyn_x> && qrm::static_register<x>);
static_assert(!qrm::selector<dyn_x>);         // no bit<>, slice<> or gate template over it
template <class R>
concept has_width = requires { R::width; };
template <class L>
concept takes_circuits = requires { qrm::make_circuit<L>(qrm::x<out>{}); };
static_assert(!has_width<dyn_x> && has_width<x>);  // no width member to misuse
static_assert(!qrm::static_layout<DL> && qrm::static_layout<SL>);
static_assert(!takes_circuits<DL> && takes_circuits<SL>);  // circuit<> needs constant offsets
static_assert(SL{}.offset_of<x>() == SL::offset<x>);                // one accessor for both kinds
}  // namespace

TEST_CASE("a layout with dynamic widths places registers like the static one and checks the same rules") {
  const DL dl(3, 3);  // dir, x
  CHECK(dl.num_qubits() == SL::width);
  CHECK(dl.offset_of<dyn_dir>() == SL::offset<dir>);
  CHECK(dl.offset_of<dyn_x>() == SL::offset<x>);
  CHECK(dl.width_of<dyn_x>() == 3);
  CHECK(dl.qubits_of<dyn_x>() == std::vector<qrm::qubit_index>{4, 5, 6});
  CHECK(dl.registers_info()[2].name == "x");
  // Different widths move what follows.
  const DL wide(5, 7);
  CHECK(wide.offset_of<dyn_x>() == 6);
  CHECK(wide.num_qubits() == 13);
  // The rule a static register states at compile time, checked at construction, by name.
  CHECK(error_of([] { DL(3, 65); }) ==
        "register_width_must_fit_64_bits: register 'x' is 65 qubits wide; register values are 64-bit numbers");
  CHECK(error_of([&] { (void)dl.qubit_of<dyn_x>(3); }) ==
        "bit_index_must_be_within_register: bit 3 of register 'x', which has 3 qubits");
  // with_widths: every register's width; a static register must have its declared width.
  using ML = qrm::layout<out, dir, dyn_x>;
  CHECK(ML::with_widths({1, 3, 4}).offset_of<dyn_x>() == 4);
  CHECK(error_of([] { ML::with_widths({1, 2, 4}); }) == "register 'dir' has 3 qubits in the layout type, but 2 are needed");
}
