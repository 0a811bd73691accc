// examples/tour.cpp: the code of README.md's tour, built and run as a test so it stays true.
#include <cmath>
#include <cstdio>

#include <qrm/qrm.hpp>

// Registers are types: a role, a name, a width. A layout places them at compile-time offsets.
using x = qrm::position<"x", 3>;
using dir = qrm::direction<3>;
using le = qrm::emission<3>;
using out = qrm::output<>;
using L = qrm::layout<out, le, dir, x>;
static_assert(L::width == 10 && L::offset<dir> == 4);

int main() {
  // Gates name their qubits and controls by type; run-time data (angles, tables) lives in the object.
  auto c = qrm::make_circuit<L>(
      qrm::h<dir>{},                                        // directions in superposition
      qrm::increment<x, qrm::when<dir, 2>>{},               // shift east when dir == E
      qrm::mux_ry<qrm::bit<le, 0>, x>{{1, 0.9}, {5, 1.2}},  // sample: Ry selected by the position
      qrm::x<out, qrm::on<qrm::bit<le, 0>>>{});
  static_assert(decltype(c)::depth_bound == 11 && decltype(c)::is_real);

  qrm::state_vector<double> psi(L::width);  // or qrm::compact_state<double>
  qrm::run(psi, c);
  const double p = qrm::probability<L, qrm::on<out>>(psi);

  // The paper's circuit for one start point, the estimate, and the classical reference.
  const qrm::walk_model model(qrm::paper_8x8(), qrm::king_2d());
  const qrm::walk_start start = model.light_map_start({3, 4, 0});
  const qrm::walk_program w = qrm::make_walk_program(model, start, {.steps = 3});
  const qrm::estimation_problem problem{w.circuit, {qrm::control{w.out, true}}};
  qrm::simulated_oracle<qrm::compact_state<double>> oracle(problem);  // every Grover iteration applied
  qrm::rng g(1);
  const auto r = qrm::faster_amplitude_estimation(oracle, {.delta = 0.01, .maxiter = 5, .rescale = true}, g);
  const double radiance = r.estimate * 3 * w.tables.emission_scale;  // times S (and the emission scale)
  const double classical = qrm::path_sum(model, start, 3, 0);        // the branching path sum

  const double exact = qrm::walk_probability<qrm::compact_backend>(w);  // P(out = 1) read from the state
  std::printf("P(out=1) of the small circuit: %.6f\n", p);
  std::printf("cell (3, 4), red: FAE radiance %.6f [%.6f, %.6f], exact faithful %.6f, classical %.6f, %llu A calls\n",
              radiance, r.confidence_interval[0] * 3, r.confidence_interval[1] * 3,
              exact * 3, classical, static_cast<unsigned long long>(r.a_calls));
  // The walker moves from x = 0 to x = 1 exactly when dir = E (probability 1/8), and Le_0 is
  // rotated by Ry(0.9) there: P(out = 1) = sin^2(0.45) / 8.
  const bool small_ok = std::abs(p - std::pow(std::sin(0.45), 2) / 8) < 1e-15;
  const bool cell_ok = r.confidence_interval[0] <= exact && exact <= r.confidence_interval[1];
  return small_ok && cell_ok ? 0 : 1;
}
