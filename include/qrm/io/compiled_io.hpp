// qrm/io/compiled_io.hpp: include in exactly one source file of a program whose other source
// files are compiled with QRM_COMPILED_IO defined. This file then compiles the image and table
// writers and readers (PNG, PFM, SVG plots, CSV, the atomic file write under them) once, and the
// others call them instead of compiling their own copies (README, "Compiling the backends once":
// the same scheme as QRM_COMPILED_BACKENDS).
#pragma once

#include "atomic_file.hpp"
#include "csv.hpp"
#include "pfm.hpp"
#include "png.hpp"
#include "svg_plot.hpp"

namespace qrm::io {
QRM_DETAIL_ATOMIC_FILE_INSTANCES(template)
QRM_DETAIL_CSV_INSTANCES(template)
QRM_DETAIL_PFM_INSTANCES(template)
QRM_DETAIL_PNG_INSTANCES(template)
QRM_DETAIL_SVG_PLOT_INSTANCES(template)
}  // namespace qrm::io
