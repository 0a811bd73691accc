// qrm/resources.hpp: what a circuit or an amplitude estimate would cost on a fault-tolerant
// quantum computer.
//   resources/clifford_t.hpp          logical qubits, CNOTs, Toffolis, T-count, T-depth, rotations
//   resources/surface_code.hpp        hardware presets, code distance, T factories, physical qubits, time
//   resources/amplitude_estimate.hpp  one estimate: A, the Grover iterate, the estimator's shots
#pragma once

#include "resources/clifford_t.hpp"
#include "resources/surface_code.hpp"
#include "resources/amplitude_estimate.hpp"
