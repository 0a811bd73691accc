// Must not compile with -DQRM_MUST_FAIL: a compact state of integer amplitudes.
#include <qrm/backends/compact.hpp>

int main() {
#ifdef QRM_MUST_FAIL
  qrm::compact_state<int> s(4);
#else
  qrm::compact_state<float> s(4);
#endif
  return static_cast<int>(s.nonzeros()) - 1;
}
