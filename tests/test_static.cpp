// Compile-time facts: register widths and offsets, selectors, controls, circuit metrics, and
// the named rules (checked positively with static_assert, negatively with `requires !requires`).
#include <doctest/doctest.h>

#include <utility>

#include <qrm/qrm.hpp>

namespace {

using x = qrm::position<"x", 3>;
using y = qrm::position<"y", 3>;
using dir = qrm::direction<3>;
using le = qrm::emission<3>;
using rho = qrm::reflectance<2>;
using stp = qrm::steps<2>;
using out = qrm::output<>;
using walk_layout = qrm::layout<x, y, dir, le, rho, stp, out>;
using foreign = qrm::ancilla<"foreign", 2>;

// ---- registers and layouts -----------------------------------------------------------------
static_assert(dir::width == 3 && dir::kind == qrm::role::direction && dir::name == "dir");
static_assert(out::width == 1 && out::kind == qrm::role::out);
static_assert(le::max_value == 7);
static_assert(walk_layout::width == 3 + 3 + 3 + 3 + 2 + 2 + 1);
static_assert(walk_layout::offset<x> == 0 && walk_layout::offset<y> == 3 && walk_layout::offset<dir> == 6);
static_assert(walk_layout::offset<out> == 16);
static_assert(walk_layout::contains<rho> && !walk_layout::contains<foreign>);
static_assert(walk_layout::register_table[2].name == "dir" && walk_layout::register_table[2].offset == 6);
static_assert(qrm::bits_for(3) == 2 && qrm::bits_for(8) == 3 && qrm::bits_for(9) == 4 && qrm::bits_for(1) == 1);

// ---- selectors and controls ----------------------------------------------------------------
static_assert(qrm::resolve<walk_layout, qrm::bit<le, 2>>()[0] == 11);
static_assert(qrm::resolve<walk_layout, qrm::slice<dir, 1, 2>>() == std::array<qrm::qubit_index, 2>{7, 8});
static_assert(qrm::resolve<walk_layout, qrm::qubits<out, qrm::bit<x, 0>>>() == std::array<qrm::qubit_index, 2>{16, 0});
static_assert(qrm::selector_width<qrm::qubits<x, y>> == 6);
constexpr auto step_is_2 = qrm::detail::resolve_controls<walk_layout, qrm::when<stp, 2>>();
static_assert(step_is_2[0].qubit == 14 && !step_is_2[0].value && step_is_2[1].qubit == 15 && step_is_2[1].value);
constexpr auto rho_off = qrm::detail::resolve_controls<walk_layout, qrm::off<rho>>();
static_assert(!rho_off[0].value && !rho_off[1].value);

// ---- circuit metrics -------------------------------------------------------------------------
// The Path gate for three steps: prepare steps, then one multi-controlled X per term.
using path_circuit = qrm::circuit<walk_layout, qrm::prepare_uniform<stp, 3>,
                                  qrm::x<out, qrm::when<stp, 0>, qrm::on<qrm::bit<le, 0>>>,
                                  qrm::x<out, qrm::when<stp, 1>, qrm::on<qrm::bit<le, 1>>, qrm::on<qrm::bit<rho, 0>>>,
                                  qrm::x<out, qrm::when<stp, 2>, qrm::on<qrm::bit<le, 2>>, qrm::on<rho>>>;
static_assert(path_circuit::width == 17);
static_assert(path_circuit::is_real);
// prepare_uniform on 2 qubits: 2 layers; then 3 X gates all on `out` and `steps`: 3 layers.
static_assert(path_circuit::depth_bound == 5);
static_assert(path_circuit::qubits_touched == 2 + 3 + 2 + 1);
static_assert(path_circuit::gate_count_bound == 2 + 3);

// Independent gates share a layer; a chain on one qubit does not.
using parallel = qrm::circuit<walk_layout, qrm::h<x>, qrm::h<y>, qrm::h<dir>>;
static_assert(parallel::depth_bound == 1 && parallel::gate_count_bound == 9);
using chain = qrm::circuit<walk_layout, qrm::h<out>, qrm::x<out>, qrm::z<out>>;
static_assert(chain::depth_bound == 3);
using repeated = qrm::circuit<walk_layout, qrm::repeat<4, qrm::seq<qrm::h<out>, qrm::x<out>>>>;
static_assert(repeated::depth_bound == 8 && repeated::gate_count_bound == 8);
// A multiplexed gate occupies one layer per possible select value (here 2^6 positions).
using sample = qrm::circuit<walk_layout, qrm::mux_ry<qrm::bit<le, 0>, qrm::qubits<x, y>>>;
static_assert(sample::depth_bound == 64);

static_assert(!qrm::circuit<walk_layout, qrm::phase<out>>::is_real);
static_assert(qrm::can_run<path_circuit, qrm::state_vector<double>>);
static_assert(qrm::can_run<qrm::circuit<walk_layout, qrm::phase<out>>, qrm::state_vector<std::complex<float>>>);

// ---- the named rules, negatively ----------------------------------------------------------
// A complex gate on a real-valued backend.
static_assert(!qrm::can_run<qrm::circuit<walk_layout, qrm::phase<out>>, qrm::state_vector<double>>);
// A gate on a register the layout does not have.
static_assert(!qrm::gate_in_layout<qrm::x<foreign>, walk_layout>);
static_assert(qrm::gate_in_layout<qrm::x<out, qrm::on<dir>>, walk_layout>);
template <class L, class G>
concept placeable = requires { requires qrm::gate_in_layout<G, L>; };
static_assert(!placeable<walk_layout, qrm::h<foreign>>);

// Selectors and controls that name no qubits, or values that do not fit.
static_assert(!qrm::selector<int>);
static_assert(!qrm::selector<qrm::bit<dir, 3>>);  // dir has bits 0..2
static_assert(qrm::selector<qrm::bit<dir, 2>>);
static_assert(!qrm::selector<qrm::slice<dir, 2, 2>>);
static_assert(!qrm::control_spec<qrm::when<dir, 8>>);  // 8 does not fit 3 qubits
static_assert(qrm::control_spec<qrm::when<dir, 7>>);

template <class Target, class... C>
concept disjoint_args = qrm::detail::checked_qubits<qrm::detail::type_list<Target>, C...>::qubits_must_be_disjoint;
static_assert(!disjoint_args<qrm::bit<dir, 0>, qrm::on<qrm::bit<dir, 0>>>);
static_assert(!disjoint_args<out, qrm::on<out>>);
static_assert(!disjoint_args<dir, qrm::on<qrm::slice<dir, 1, 1>>>);
static_assert(disjoint_args<qrm::bit<dir, 0>, qrm::on<qrm::slice<dir, 1, 2>>>);

// A requires-expression that tries to use the offset of a foreign register in a layout must fail.
template <class L, class R>
concept has_register = requires { requires L::template contains<R>; };
static_assert(has_register<walk_layout, dir> && !has_register<walk_layout, foreign>);

template <class B, class C>
concept runs_on = requires(B& b, const C& c) { requires qrm::can_run<C, B>; };
static_assert(!runs_on<qrm::state_vector<float>, qrm::circuit<walk_layout, qrm::y<out>>>);
static_assert(runs_on<qrm::state_vector<std::complex<double>>, qrm::circuit<walk_layout, qrm::y<out>>>);

// ---- backends -------------------------------------------------------------------------------
static_assert(qrm::backend<qrm::state_vector<double>> && qrm::backend<qrm::state_vector<float>> &&
              qrm::backend<qrm::state_vector<std::complex<double>>> &&
              qrm::backend<qrm::state_vector<std::complex<float>>>);
static_assert(qrm::backend<qrm::compact_state<double>> && qrm::backend<qrm::compact_state<float>> &&
              qrm::backend<qrm::compact_state<std::complex<double>>> &&
              qrm::backend<qrm::compact_state<std::complex<float>>> &&
              qrm::backend<qrm::compact_state<std::complex<double>, qrm::wide_label<2>>> &&
              qrm::backend<qrm::compact_state<float, qrm::wide_label<3>>>);
static_assert(qrm::backend_family<qrm::dense_backend> && qrm::backend_family<qrm::compact_backend>);
static_assert(qrm::dense_backend::name == "dense" && qrm::compact_backend::name == "compact");

// A backend with every operation except the one numbered Missing (-1: none missing).
template <int Missing>
struct partial_backend {
  using scalar_type = double;
  using real_type = double;
  static constexpr bool is_complex = false;
  explicit partial_backend(std::size_t) {}
  void apply_gate1(const qrm::gate1&, qrm::qubit_index, std::span<const qrm::control>) requires(Missing != 0) {}
  void apply_unitary(const qrm::dense_matrix&, std::span<const qrm::qubit_index>, std::span<const qrm::control>)
    requires(Missing != 1) {}
  void apply_add(std::int64_t, std::span<const qrm::qubit_index>, std::span<const qrm::control>)
    requires(Missing != 2) {}
  void apply_mux1(std::span<const qrm::mux1_entry>, qrm::qubit_index, std::span<const qrm::qubit_index>,
                  std::span<const qrm::control>) requires(Missing != 3) {}
  void apply_mux_unitary(std::span<const qrm::dense_matrix>, std::span<const qrm::mux_unitary_entry>,
                         std::span<const qrm::qubit_index>, std::span<const qrm::qubit_index>,
                         std::span<const qrm::control>) requires(Missing != 4) {}
  void set_basis_state(std::uint64_t) requires(Missing != 5) {}
  void set_amplitudes(std::span<const double>) requires(Missing != 6) {}
  std::size_t num_qubits() const requires(Missing != 7) { return 0; }
  double amplitude(std::uint64_t) const requires(Missing != 8) { return 0; }
  std::vector<double> to_dense() const requires(Missing != 9) { return {}; }
  double norm_squared() const requires(Missing != 10) { return 0; }
  double probability(std::span<const qrm::control>) const requires(Missing != 11) { return 0; }
  std::vector<double> distribution(std::span<const qrm::qubit_index>) const requires(Missing != 12) { return {}; }
};
static_assert(qrm::backend<partial_backend<-1>>);
// Each missing operation is caught, by the part of the concept that names it.
template <int... K>
constexpr bool none_is_a_backend(std::integer_sequence<int, K...>) {
  return (... && !qrm::backend<partial_backend<K>>);
}
static_assert(none_is_a_backend(std::make_integer_sequence<int, 13>{}));
static_assert(!qrm::gate_sink<partial_backend<3>> && qrm::state_loader<partial_backend<3>> &&
              qrm::state_reader<partial_backend<3>>);
static_assert(qrm::gate_sink<partial_backend<6>> && !qrm::state_loader<partial_backend<6>> &&
              qrm::state_reader<partial_backend<6>>);
static_assert(qrm::gate_sink<partial_backend<9>> && qrm::state_loader<partial_backend<9>> &&
              !qrm::state_reader<partial_backend<9>>);
// Not backends either: a gate_sink that cannot be read (a recorder), integer amplitudes, an int.
static_assert(qrm::gate_sink<qrm::program> && !qrm::backend<qrm::program>);
struct integer_backend : partial_backend<-1> {
  using scalar_type = int;
  using partial_backend::partial_backend;
};
static_assert(!qrm::amplitude_store<integer_backend> && !qrm::backend<integer_backend>);
template <class B>
concept backend_type = requires { requires qrm::backend<B>; };
static_assert(!backend_type<int> && backend_type<qrm::compact_state<double>>);
// A family needs a name, visit and make, and backends for real and complex amplitudes.
struct unnamed_family {
  template <class S>
  using state = qrm::state_vector<S>;
};
static_assert(!qrm::backend_family<unnamed_family>);
struct family_without_visit {
  static constexpr std::string_view name = "no visit";
  template <class S>
  using state = qrm::compact_state<S>;
  template <class B>
  static B make(std::size_t n) {
    return B(n);
  }
};
static_assert(!qrm::backend_family<family_without_visit>);
struct recorder_family : family_without_visit {
  template <class S>
  using state = qrm::program;
  template <class F>
  static int visit(std::size_t, bool, F&&) {
    return 0;
  }
};
static_assert(!qrm::backend_family<recorder_family>);

}  // namespace

TEST_CASE("compile-time facts hold (see the static_asserts in this file)") {
  CHECK(path_circuit::depth_bound == 5);
}
