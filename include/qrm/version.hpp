// qrm/version.hpp: library version.
#pragma once

#define QRM_VERSION_MAJOR 0
#define QRM_VERSION_MINOR 1
#define QRM_VERSION_PATCH 0

namespace qrm {
inline constexpr const char* version = "0.1.0";
}
