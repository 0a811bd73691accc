// The kernel tests (kernel_cases.hpp) on the dense backend, every amplitude type, plus the
// dense backend's threading.
#include <complex>

#include "kernel_cases.hpp"

#define QRM_DENSE_BACKENDS                                                                            \
  qrm::state_vector<double>, qrm::state_vector<float>, qrm::state_vector<std::complex<double>>, \
      qrm::state_vector<std::complex<float>>
TEST_CASE_TEMPLATE_INVOKE(gate1_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(unitary_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(add_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(mux_placements, QRM_DENSE_BACKENDS);
TEST_CASE_TEMPLATE_INVOKE(norm_drift, QRM_DENSE_BACKENDS);
// Only the dense backend uses threads (the compact one is single-threaded; its determinism is
// tested in test_compact.cpp).
TEST_CASE_TEMPLATE_INVOKE(thread_determinism, qrm::state_vector<double>, qrm::state_vector<std::complex<double>>);
TEST_CASE_TEMPLATE_INVOKE(chunked_subspaces, qrm::state_vector<double>, qrm::state_vector<std::complex<float>>);
