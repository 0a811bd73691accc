// qrm/circuit.hpp: the generic circuit layer (no backend, no scene).
//   circuit/registers.hpp  typed registers: position, direction, emission (Le), reflectance (rho), steps, out, ...
//   circuit/layout.hpp     layouts (qubit offsets), selectors bit/slice/qubits, controls when/on/off
//   circuit/ops.hpp        the five primitive operations every backend implements (gate_sink)
//   circuit/gates.hpp      gate templates: x y z h ry rz phase u, unitary/real_unitary, add/increment,
//                          mux_ry, mux_unitary (multiplexed), prepare_uniform
//   circuit/compose.hpp    seq, repeat, unroll, circuit<L, ...> with constexpr width / depth bound, run()
//   circuit/program.hpp    run-time programs: record, replay, invert
//   circuit/metrics.hpp    width, logical depth, gate counts of a program
//   circuit/fuse.hpp       gate fusion: runs of small gates multiplied into one matrix
//   circuit/decompose.hpp  lowering to single-qubit gates + CNOTs (with ancillas), decomposed counts
//   circuit/qasm.hpp       OpenQASM 3 export (logical or decomposed) and import
#pragma once

#include "circuit/registers.hpp"
#include "circuit/layout.hpp"
#include "circuit/ops.hpp"
#include "circuit/gates.hpp"
#include "circuit/compose.hpp"
#include "circuit/program.hpp"
#include "circuit/metrics.hpp"
#include "circuit/fuse.hpp"
#include "circuit/decompose.hpp"
#include "circuit/qasm.hpp"
