// qrm's backends, compiled once for qrm's own programs (CMakeLists.txt: qrm_compiled).
#include <qrm/backends/compiled_backends.hpp>
