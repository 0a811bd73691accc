// qrm/io.hpp: output files (needs nothing else of qrm).
//   io/image.hpp        linear-RGB float images: tone mapping to sRGB, upsampling, error maps, stats
//   io/png.hpp          PNG writer (8-bit RGB/grey, stored deflate), crc32, adler32
//   io/pfm.hpp          PFM float images: exact write and read
//   io/svg_plot.hpp     SVG line/scatter plots (log axes, fitted slopes), least-squares fits
//   io/csv.hpp          results tables as CSV (round-trip numbers) and Markdown
//   io/atomic_file.hpp  whole-file writes via temp file + rename, creating directories
//   io/progress.hpp     thread-safe progress bar on stderr
#pragma once

#include "io/image.hpp"
#include "io/png.hpp"
#include "io/pfm.hpp"
#include "io/svg_plot.hpp"
#include "io/csv.hpp"
#include "io/atomic_file.hpp"
#include "io/progress.hpp"
