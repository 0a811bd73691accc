// qrm's estimators for its two oracle types, compiled once for qrm's own programs (CMakeLists.txt:
// qrm_compiled).
#include <qrm/estimation/compiled_estimation.hpp>
