// qrm/backends.hpp: simulators that run circuits and programs (kernels in backends/detail/).
//   backends/backend.hpp   the concept qrm::backend<B> and backend families (a backend chosen as a type)
//   backends/dense.hpp     state_vector<S>: all 2^n amplitudes (S = complex or real, double or float),
//                          and its family dense_backend
//   backends/compact.hpp   compact_state<S, L>: only the nonzero amplitudes (labels uint64_t or wide_label<W>),
//                          and its family compact_backend
//   backends/measure.hpp   probabilities, distributions and samples through a layout
#pragma once

#include "backends/backend.hpp"
#include "backends/dense.hpp"
#include "backends/compact.hpp"
#include "backends/measure.hpp"
