// qrm/render/compiled_render.hpp: include in exactly one source file of a program whose other
// source files are compiled with QRM_COMPILED_RENDER defined. This file then compiles the 3D
// renderer's builders (the voxelizer and the built-in scenes, the first-hit ray march, the exact,
// Monte Carlo and emulated renders, the path sums and path enumeration) once, and the others call
// them instead of compiling their own copies (README, "Compiling the backends once": the same
// scheme as QRM_COMPILED_BACKENDS).
#pragma once

#include "classical.hpp"
#include "dda.hpp"
#include "voxelize.hpp"

namespace qrm::render {
QRM_DETAIL_CLASSICAL_RENDER_INSTANCES(template)
QRM_DETAIL_DDA_INSTANCES(template)
QRM_DETAIL_VOXELIZE_INSTANCES(template)
}  // namespace qrm::render
