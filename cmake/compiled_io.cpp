// qrm's image and table writers, compiled once for qrm's own programs (CMakeLists.txt: qrm_compiled).
#include <qrm/io/compiled_io.hpp>
