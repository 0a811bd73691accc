// qrm/circuit/registers.hpp: typed quantum registers (a role, a name and a width, all compile-time).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "../support/detail/meta.hpp"

namespace qrm {

// What a register holds in the ray-marching circuit; generic circuits use `ancilla`.
enum class role : unsigned char { position, direction, emission, reflectance, steps, out, history, distance, ancilla };

constexpr std::string_view role_name(role r) {
  switch (r) {
    case role::position: return "position";
    case role::direction: return "direction";
    case role::emission: return "emission";
    case role::reflectance: return "reflectance";
    case role::steps: return "steps";
    case role::out: return "out";
    case role::history: return "history";
    case role::distance: return "distance";
    case role::ancilla: return "ancilla";
  }
  return "?";
}

// Largest value a register of `width` qubits holds (width <= 64).
constexpr std::uint64_t max_value_of_width(std::size_t width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

// dynamic_width: a register width fixed when its layout is built (a scene read at run time), in
// the spirit of std::dynamic_extent.
inline constexpr std::size_t dynamic_width = ~std::size_t{0};

// reg<Name, Width, Role>: a register of Width qubits, read as a little-endian unsigned number.
// Its name and role are always types; Width is a constant, or dynamic_width (then the layout
// holds it, and the rules below are checked when the layout is built).
template <detail::fixed_string Name, std::size_t Width, role Role = role::ancilla>
struct reg {
  static constexpr bool register_width_must_be_positive = Width >= 1;
  static_assert(register_width_must_be_positive, "register_width_must_be_positive: a register holds at least one qubit");
  static constexpr bool register_width_must_fit_64_bits = Width <= 64;
  static_assert(register_width_must_fit_64_bits, "register_width_must_fit_64_bits: register values are 64-bit numbers");

  static constexpr std::string_view name = Name.view();
  static constexpr std::size_t width = Width;
  static constexpr bool is_dynamic = false;
  static constexpr role kind = Role;
  static constexpr std::uint64_t max_value = max_value_of_width(Width);
};

// reg<Name, dynamic_width, Role>: no `width` member, so a facility that needs the width at compile
// time (bit<>, slice<>, when<> values, circuit<>) refuses the register by name.
template <detail::fixed_string Name, role Role>
struct reg<Name, dynamic_width, Role> {
  static constexpr std::string_view name = Name.view();
  static constexpr bool is_dynamic = true;
  static constexpr role kind = Role;
};

namespace detail {
template <class T>
inline constexpr bool is_reg = false;
template <fixed_string N, std::size_t W, role R>
inline constexpr bool is_reg<reg<N, W, R>> = true;

}  // namespace detail

// register_type: any qrm::reg<...>; static_register / dynamic_register by how its width is known.
template <class T>
concept register_type = detail::is_reg<T>;
template <class T>
concept static_register = register_type<T> && !T::is_dynamic;
template <class T>
concept dynamic_register = register_type<T> && T::is_dynamic;

// The registers of the ray-marching circuit, named by role (names default to the paper's).
template <detail::fixed_string Name, std::size_t Width>
using position = reg<Name, Width, role::position>;
template <std::size_t Width, detail::fixed_string Name = "dir">
using direction = reg<Name, Width, role::direction>;
template <std::size_t Width, detail::fixed_string Name = "Le">
using emission = reg<Name, Width, role::emission>;
template <std::size_t Width, detail::fixed_string Name = "rho">
using reflectance = reg<Name, Width, role::reflectance>;
template <std::size_t Width, detail::fixed_string Name = "steps">
using steps = reg<Name, Width, role::steps>;
template <detail::fixed_string Name = "out">
using output = reg<Name, 1, role::out>;
template <detail::fixed_string Name, std::size_t Width>
using history = reg<Name, Width, role::history>;
template <detail::fixed_string Name, std::size_t Width>
using distance = reg<Name, Width, role::distance>;
template <detail::fixed_string Name, std::size_t Width>
using ancilla = reg<Name, Width, role::ancilla>;

// Qubits needed to hold the values 0..count-1 (at least one).
constexpr std::size_t bits_for(std::uint64_t count) {
  std::size_t b = 1;
  while (b < 64 && (std::uint64_t{1} << b) < count) ++b;
  return b;
}

}  // namespace qrm
