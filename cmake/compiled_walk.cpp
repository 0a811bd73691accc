// qrm's walk builders, compiled once for qrm's own programs (CMakeLists.txt: qrm_compiled).
#include <qrm/walk/compiled_walk.hpp>
