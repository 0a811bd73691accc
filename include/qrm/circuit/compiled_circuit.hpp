// qrm/circuit/compiled_circuit.hpp: include in exactly one source file of a program whose other
// source files are compiled with QRM_COMPILED_CIRCUIT defined. This file then compiles the
// circuit layer's run-time translators (decompose, decomposed_metrics, to_qasm, from_qasm: the
// lowering to one- and two-qubit gates and the OpenQASM 3 writer and parser) once, and the others
// call them instead of compiling their own copies (README, "Compiling the backends once": the same
// scheme as QRM_COMPILED_BACKENDS).
#pragma once

#include "decompose.hpp"
#include "qasm.hpp"

namespace qrm {
QRM_DETAIL_DECOMPOSE_INSTANCES(template)
QRM_DETAIL_QASM_INSTANCES(template)
}  // namespace qrm
