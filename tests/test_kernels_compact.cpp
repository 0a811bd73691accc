// The kernel tests (kernel_cases.hpp) on the compact backend, every amplitude type and a wide
// basis label.
#include <complex>

#include "kernel_cases.hpp"

#define QRM_COMPACT_BACKENDS                                                                               \
  qrm::compact_state<double>, qrm::compact_state<float>, qrm::compact_state<std::complex<double>>,   \
      qrm::compact_state<std::complex<float>>, qrm::compact_state<std::complex<double>, qrm::wide_label<2>>
TEST_CASE_TEMPLATE_INVOKE(gate1_placements, QRM_COMPACT_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(unitary_placements, QRM_COMPACT_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(add_placements, QRM_COMPACT_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(mux_placements, QRM_COMPACT_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(norm_drift, QRM_COMPACT_BACKENDS);
