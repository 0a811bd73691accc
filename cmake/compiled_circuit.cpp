// qrm's circuit translators (decomposition, OpenQASM 3), compiled once for qrm's own programs
// (CMakeLists.txt: qrm_compiled).
#include <qrm/circuit/compiled_circuit.hpp>
