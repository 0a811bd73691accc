// qrm/qrm.hpp: the whole library. One header per facility:
//   registers.hpp        typed registers (position, direction, emission, reflectance, steps, out, ...)
//   layout.hpp           layouts, qubit selectors (bit, slice, qubits), controls (when, on, off)
//   gates.hpp            gate templates: x y z h ry rz phase u, unitary, add, mux_ry, mux_unitary,
//                        prepare_uniform
//   circuit.hpp          seq, repeat, unroll, circuit<L, ...>, compile-time metrics, run()
//   ops.hpp              the primitive instruction set every backend implements (gate_sink)
//   program.hpp          run-time programs: record, replay, invert
//   backends/dense.hpp   state_vector<S>: the dense backend
//   backends/compact.hpp compact_state<S, L>: only the nonzero amplitudes (labels: uint64_t or wide_label<W>)
//   measure.hpp          probabilities, distributions and samples through a layout
//   random.hpp           seeded generator, binomial sampling
#pragma once

#include "version.hpp"
#include "registers.hpp"
#include "layout.hpp"
#include "ops.hpp"
#include "gates.hpp"
#include "circuit.hpp"
#include "program.hpp"
#include "random.hpp"
#include "measure.hpp"
#include "backends/dense.hpp"
#include "backends/compact.hpp"
