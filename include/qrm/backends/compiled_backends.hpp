// qrm/backends/compiled_backends.hpp: include in exactly one source file of a program whose other
// source files are compiled with QRM_COMPILED_BACKENDS defined. This file then compiles both
// backends (the state classes for float, double, std::complex<float> and std::complex<double>,
// and the dense kernels) and the others call them instead of compiling their own copies: a
// source file that runs the backends compiles in about half the time (README, "Compiling the
// backends once"). Without the macro a program needs no such file and the library stays
// header-only. Compile this file with the options the rest of the program uses (optimisation,
// QRM_NO_AVX512, QRM_FEWER_KERNELS).
#pragma once

#include "compact.hpp"
#include "dense.hpp"
// The dense members and kernels, which dense.hpp leaves out when QRM_COMPILED_BACKENDS is defined.
#include "detail/dense_members.hpp"

namespace qrm {
QRM_DETAIL_DENSE_INSTANCES(template)
QRM_DETAIL_COMPACT_INSTANCES(template)
}  // namespace qrm
