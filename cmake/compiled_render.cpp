// qrm's 3D renderer builders, compiled once for qrm's own programs (CMakeLists.txt: qrm_compiled).
#include <qrm/render/compiled_render.hpp>
